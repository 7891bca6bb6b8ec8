;;;; tempo.lisp -- a script played faster or slower: every time in it scaled
;;;; by one factor, its items' starts and spans and the times inside their
;;;; motor calls (keys, beats, durations).  What a looping script of :beats
;;;; becomes at the tempo of the music playing (Peedy's tap-foot).

(in-package #:player.performance)

(defparameter *motor-time-options* '(:duration :hold :stroke :retract :fade :for)
  "Options of a motor call whose value, when a number, is seconds.")

(defun scale-motor-frame (frame factor)
  "The motor call FRAME with its seconds multiplied by FACTOR: :keys' times,
:times, :visemes' times and the options of *MOTOR-TIME-OPTIONS*."
  (cons (first frame)
        (loop for (key value) on (rest frame) by #'cddr
              append (list key
                           (cond ((and (member key *motor-time-options*) (realp value)) (* value factor))
                                 ((and (member key '(:keys :visemes)) (alexandria:proper-list-p value))
                                  (mapcar (lambda (entry)
                                            (if (and (consp entry) (realp (first entry)))
                                                (cons (* (first entry) factor) (rest entry))
                                                entry))
                                          value))
                                 ((and (eq key :times) (alexandria:proper-list-p value) (every #'realp value))
                                  (mapcar (lambda (time) (* time factor)) value))
                                 (t value))))))

(defun scale-item (item factor)
  "A copy of ITEM with its start, span and (for a motor item) its call's times scaled by FACTOR."
  (let ((copy (if (motor-item-p item)
                  (let ((frame (scale-motor-frame (motor-item-frame item) factor)))
                    (make-motor-item :form (script-item-form item) :frame frame
                                     :call (parse-motor-frame frame)))
                  (copy-structure item)))
        (until (script-item-until item)))
    (setf (script-item-at copy) (* (script-item-at item) factor)
          (script-item-until copy) (and until (* until factor)))
    copy))

(defvar *scaled-scripts* (make-hash-table :test #'eq :weakness :key :synchronized t)
  "Scripts already scaled: SCRIPT -> ((FACTOR . SCALED) ...).")

(defun scale-script (script factor)
  "SCRIPT with every time in it multiplied by FACTOR (> 0): its duration,
critical times and items (SCALE-ITEM); SCRIPT itself for a factor of 1.
Each is made once."
  (if (= factor 1)
      script
      (or (cdr (assoc factor (gethash script *scaled-scripts*) :test #'=))
          (let ((scaled (%make-script :name (script-name script) :duration (* (script-duration script) factor)
                                      :loop (script-loop script) :beats (script-beats script)
                                      :critical (mapcar (lambda (entry) (cons (car entry) (* (cdr entry) factor)))
                                                        (script-critical script))
                                      :items (mapcar (lambda (item) (scale-item item factor)) (script-items script))
                                      :documentation (script-documentation script)
                                      :source (script-source script) :form (script-form script))))
            (push (cons factor scaled) (gethash script *scaled-scripts*))
            scaled))))

(defun script-at-tempo (script tempo)
  "SCRIPT as played at TEMPO beats a minute: a script of :beats N stretched
to last N beats; any other script, or a TEMPO of NIL, as it is."
  (if (and tempo (script-beats script) (plusp (script-duration script)))
      (scale-script script (/ (* (script-beats script) (/ 60d0 tempo)) (script-duration script)))
      script))
