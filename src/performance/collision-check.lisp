;;;; collision-check.lisp -- CHECK plays each script a spec needs, from the
;;;; body's rest pose in the library's scene with nothing stopping the hands,
;;;; and warns about the first moment a hand passes through a prop or a body:
;;;; the time, the two parts and how deep.  Grazing a surface is not passing
;;;; through it: only a hand *CHECK-DEPTH* inside counts (at play time the
;;;; physics stops every hand at contact anyway, src/physics/collisions.lisp).

(in-package #:player.performance)

(defparameter *check-depth* 0.01d0
  "Metres a hand must be inside something before CHECK reports the script.")

(defparameter *collision-check-fps* 10
  "Frames per second CHECK samples a script's motion at.")

(defparameter *collision-check-seconds* 10
  "The longest stretch of a script (a loop) CHECK plays.")

(defun first-script-collision (library character skeleton script)
  "The first sampled moment SCRIPT of LIBRARY, played on CHARACTER (a body of
SKELETON) from rest, puts a hand *CHECK-DEPTH* into something: (TIME HAND
OBSTACLE DEPTH), or NIL.  A script that cannot play is left to the other checks."
  (handler-case
      (let* ((*stop-at-contact* nil)
             (performance (make-performance library (list (list character skeleton)) :silent t))
             (end (min (script-duration script) *collision-check-seconds*)))
        (perform-script performance (script-name script) 0)
        (loop for k from 0 to (ceiling (* end *collision-check-fps*))
              for time = (min end (/ k (float *collision-check-fps* 1d0)))
              for hit = (find-if (lambda (hit) (> (fourth hit) *check-depth*))
                                 (scene-collisions (performance-frame performance time)))
              when hit return (cons time (rest hit))))
    (player-error () nil)))

(defun item-index-at (script time)
  "The index of SCRIPT's last item starting at or before TIME (0 when none)."
  (or (position-if (lambda (item) (<= (script-item-at item) time)) (script-items script) :from-end t) 0))

(defun script-collision-diagnostics (library skeleton names character)
  "A :COLLISION warning for each script LIBRARY plays for NAMES whose motion,
played on CHARACTER with SKELETON, passes a hand through a prop or a body
\(see FIRST-SCRIPT-COLLISION); its DETAILS are (:SCRIPT :TIME :PARTS :FILE :LINE)."
  (let ((cache (make-hash-table :test #'equal)))
    (loop for script in (remove-if-not #'script-p (needed-definitions library names))
          for hit = (first-script-collision library character skeleton script)
          when hit
            collect (destructuring-bind (time hand obstacle depth) hit
                      (let ((place (item-place script (item-index-at script time) cache)))
                        (make-diagnostic
                         :collision
                         (format nil "~@[~A:~]~@[~D: ~]script ~A: at ~A s the ~A passes through ~A (~D mm deep)"
                                 (and place (file-namestring (car place))) (cdr place)
                                 (lisp-text (script-name script)) (format-number time)
                                 (string-downcase (string hand)) obstacle (round (* 1000 depth)))
                         (list :script (script-name script) :time time
                               :parts (list (string-downcase (string hand)) obstacle)
                               :file (car place) :line (cdr place))))))))
