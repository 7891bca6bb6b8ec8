;;;; test-item-pool.lisp -- a timed controller uses its agenda items, their
;;;; conses and its runs again (src/control/timeline/item-pool.lisp).  An item
;;;; or run retired while something still reaches it would be handed out
;;;; twice and play as two things at once, so the random specs and streams of
;;;; the model-based test are played with nothing used again but retired
;;;; items and runs marked :FREE, and after every call nothing the timeline
;;;; reaches may be :FREE; and played again with the pool on, the traces must
;;;; be the same.

(in-package #:player-tests)

(def-suite* item-pool :in player-tests)

(defun timeline-reachable-items (timeline)
  "Every agenda item TIMELINE can still reach: on its agenda, pending in or
recorded by the runs there, running or waiting, live ops, timers."
  (let ((items '()))
    (labels ((note (item) (when item (push item items)))
             (note-run (run)
               (when run
                 (mapc #'note (player.control::run-items run))
                 (mapc #'note (player.control::run-pending run)))))
      (let ((agenda (player.control::timeline-agenda timeline)))
        (dotimes (i (player.control::agenda-count agenda))
          (let ((item (svref (player.control::agenda-items agenda) i)))
            (note item)
            (note-run (player.control::agenda-item-run item)))))
      (mapc #'note-run (player.control::timeline-runs timeline))
      (mapc #'note-run (player.control::timeline-queue timeline))
      (mapc #'note (player.control::timeline-live-ops timeline))
      (dolist (state (player.control::timeline-timers timeline))
        (note (player.control::timer-state-item state))))
    items))

(defun retired-but-reached (controller)
  "How many items, and runs of items, CONTROLLER's timeline reaches that were retired."
  (let ((timeline (player.control::controller-timeline controller)))
    (+ (count :free (timeline-reachable-items timeline) :key #'player.control::agenda-item-status)
       (count :free (remove-duplicates
                     (append (player.control::timeline-runs timeline) (player.control::timeline-queue timeline)
                             (remove nil (mapcar #'player.control::agenda-item-run (timeline-reachable-items timeline)))))
              :key #'player.control::run-policy))))

(defun play-stream-checking-items (machine spec actions initial)
  "Play ACTIONS like TM-PLAY-STREAM (a trace presenter), counting after every
call the retired items still reached.  Returns that count and the number of
checks made."
  (let ((controller (make-controller machine :timed t :presenter (make-trace-presenter)
                                               :initial-state (model-state-alist (tms-model spec) initial)))
        (reached 0) (checks 0))
    (flet ((check () (incf checks) (incf reached (retired-but-reached controller))))
      (handler-case
          (progn
            (dolist (action actions)
              (ecase (first action)
                (:send (destructuring-bind (event time policy) (rest action)
                         (if policy
                             (send-event controller event :at (float time 1d0) :when-busy policy)
                             (send-event controller event :at (float time 1d0)))))
                (:check (advance controller (float (second action) 1d0)))
                (:settle (loop for step from 1 to *tm-settle-steps*
                               while (controller-busy-p controller)
                               do (advance controller (float (+ (second action) (* 50 step)) 1d0))
                                  (check))))
              (check))
            (finish-events controller)
            (check))
        (player::timeline-error () nil)))
    (values reached checks)))

(defun item-pool-problem (seed stream)
  "What goes wrong with recycled items on stream STREAM of random spec SEED, or
NIL.  Returns a second value: how many times the items were checked."
  (call-with-random-stream
   seed stream
   (lambda (machine spec actions initial)
     (flet ((summary (recycle)
              (tm-play-summary-with 'player.control::*recycle-agenda-items* recycle machine spec actions initial)))
       (multiple-value-bind (reached checks)
           (let ((player.control::*recycle-agenda-items* nil))
             (play-stream-checking-items machine spec actions initial))
         (values (cond ((plusp reached)
                        (format nil "~D retired items still reached" reached))
                       ((not (equal (summary t) (summary nil)))
                        "the trace with items used again differs from the one with fresh items"))
                 checks))))))

(test timeline-items-used-again-are-never-reached
  "On random timed specs and streams (cuts, macros, parallel channels, timers,
triggers, every policy), no item a timeline retired is reached again, and
playing with items used again gives the trace of playing with fresh ones."
  (multiple-value-bind (problems checks) (tm-stream-problems #'item-pool-problem)
    (is (null problems) "~{~A~^~%~}" problems)
    ;; About seven checks a stream: fewer means the streams played nothing.
    (is (> checks 1000) "only ~D checks" checks)))

(test timed-peedy-uses-its-items-again
  "Peedy on a timed controller, half the events preempting the one playing:
the timeline's pool hands items out again, so it allocates a fraction of what
fresh items would take (about 450 bytes an event) and the trace is the one
fresh items give."
  (let* ((machine (compile-spec (first (load-spec (checkout-file "specs/peedy.lisp")))))
         (names (coerce (event-names machine) 'simple-vector))
         (*random-state* (sb-ext:seed-random-state 7))
         (stream (loop repeat 2000
                       collect (cons (svref names (random (length names))) (zerop (random 2))))))
    (flet ((play (presenter)
             (let ((controller (make-controller machine :timed t :presenter presenter)))
               (loop for (name . interrupts) in stream
                     do (if interrupts
                            (send-event controller name :at (+ (controller-time controller) 0.3d0)
                                                        :when-busy :preempt)
                            (progn (finish-events controller)
                                   (send-event controller name))))
               (finish-events controller)
               (values controller presenter))))
      (play (make-null-presenter))      ; warm up: compiled events, footprints
      (let* ((before (sb-ext:get-bytes-consed))
             (controller (play (make-null-presenter)))
             (bytes (/ (- (sb-ext:get-bytes-consed) before) (length stream)))
             (agenda (player.control::timeline-agenda (player.control::controller-timeline controller))))
        (is (player.control::agenda-free agenda) "the pool is empty at the end")
        (is (< bytes 350) "~,1F bytes an event" bytes)
        ;; What is given back is what was taken: the spares stay as few as
        ;; the items alive at once, not one more for every cut.
        (let ((spare-items (loop for item = (player.control::agenda-free agenda) then (player.control::agenda-item-owner item)
                                 while item count t))
              (spare-conses (length (player.control::agenda-free-conses agenda))))
          (is (< spare-items 200) "~D spare items after ~D events" spare-items (length stream))
          (is (< spare-conses 200) "~D spare conses after ~D events" spare-conses (length stream))))
      (let ((recycled (nth-value 1 (play (make-trace-presenter))))
            (fresh (let ((player.control::*recycle-agenda-items* nil)) (nth-value 1 (play (make-trace-presenter))))))
        (is (equal (trace-lines recycled) (trace-lines fresh)))
        (is (> (length (trace-lines fresh)) 4000))))))

(defun c++-spec-variant-problem (seed label variable values)
  "Where the Lisp traces of random timed spec SEED of the C++ comparison (its
:time directives leave changes due after an event's end) differ as special
VARIABLE takes each of VALUES, or NIL.  Each of 16 scenarios is drawn with
the first value (a spec whose timers keep it busy for ever gives none) and
played with each.  LABEL (a string) names the throwaway spec.  Returns the
number of scenarios played, and the machine, as more values."
  (multiple-value-bind (forms model extras) (c++-timeline-spec seed)
    (let ((machine (machine-of-forms (rs-symbol "~A-~D" label seed) forms (find-package '#:player-user)))
          (prng (make-rs-prng (+ 400000 seed)))
          (*package* (find-package '#:player-user)))
      (flet ((with-value (value thunk)
               (progv (list variable) (list value) (funcall thunk))))
        (loop for i below 16
              for initial = (if (zerop i) '() (random-initial-state prng model extras))
              for (events until when-busy) = (handler-case
                                                  (with-value (first values)
                                                    (lambda () (random-timed-scenario prng machine initial)))
                                                (player::timeline-error () (return (values nil i machine))))
              for traces = (loop for value in values
                                 collect (with-value value
                                           (lambda ()
                                             (handler-case (lisp-timed-trace machine initial events
                                                                             :until until :when-busy when-busy)
                                               (player::timeline-error (e) (list :error (princ-to-string e)))))))
              unless (every (lambda (trace) (equal trace (first traces))) (rest traces))
                do (return (values (format nil "scenario ~D ~S: the traces differ as ~(~A~) changes"
                                           i events variable)
                                   (1+ i) machine))
              finally (return (values nil i machine)))))))

(test timeline-items-used-again-on-the-c++-comparison-specs
  "The random specs of the C++ comparison (macros, :time directives, runtime
values, every policy) play the same with items used again as with fresh ones."
  (let ((problems '()) (played 0))
    (dolist (seed (loop for seed from 1 to 20 collect seed))
      (multiple-value-bind (problem count)
          (handler-case (c++-spec-variant-problem seed "item-pool" 'player.control::*recycle-agenda-items* '(nil t))
            (error (e) (format nil "error: ~A" e)))
        (incf played (or count 0))
        (when problem (push (format nil "seed ~D: ~A" seed problem) problems))))
    (is (null problems) "~{~A~^~%~}" (reverse problems))
    (is (>= played 250) "only ~D scenarios" played)))
