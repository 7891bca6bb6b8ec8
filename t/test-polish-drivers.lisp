;;;; test-polish-drivers.lisp -- one script starting many blink drivers at
;;;; once costs work in proportion to how many: each start no longer
;;;; evaluates the body again (src/performance/replay.lisp), composing the
;;;; pose again at the same instant is skipped when nothing changed it
;;;; (src/body/body.lisp), and composing asks a table for each driver's
;;;; shared channels (src/body/layers.lisp).  The work counted is the
;;;; drivers composed, summed over every composition of the pose.

(in-package #:player-tests)

(def-suite* polish-drivers :in player-tests)

(defun write-blinker-files (directory count)
  "Write a library whose script MANY starts COUNT blink drivers at once, and a
spec whose event ev-go plays it, into DIRECTORY; return the spec."
  (with-open-file (out (merge-pathnames "lib.lisp" directory) :direction :output :if-exists :supersede)
    (format out "(defscript many (:duration 2)~%")
    (dotimes (k count)
      (format out "  (:at 0.5 :motor (:blink :seed ~D :mean-interval 0.5))~%" k))
    (format out ")~%"))
  (with-open-file (out (merge-pathnames "spec.lisp" directory) :direction :output :if-exists :supersede)
    (write-string "(in-package :player-user)
(defspec blinker \"Blinks a great deal.\" (:scripts \"lib.lisp\")
  (state-variable went boolean false)
  (op many :add went :duration 2)
  (event ev-go :op many))
" out))
  (first (player:load-spec (merge-pathnames "spec.lisp" directory))))

(defun blinker-work (count)
  "Play COUNT blink drivers started at once, sampled at 10 frames a second:
two values, the drivers composed summed over every composition of the pose,
and how many blink drivers are active 1 s in."
  (with-rig-directory (dir)
    (let ((spec (write-blinker-files dir count))
          (work 0))
      (sb-int:encapsulate 'player.body::compose-pose 'polish-count
                          (lambda (function body time)
                            (incf work (length (player.body::body-active body)))
                            (funcall function body time)))
      (unwind-protect
           (let* ((simulation (player:simulate spec :events '(ev-go) :silent t :fps 10))
                  (scene (player.performance::simulation-scene-at simulation 1d0))
                  (body (find-if (lambda (o) (typep o 'player:body)) (player:scene-objects scene))))
             (values work (count-if (lambda (driver) (typep driver 'player.body::blink-driver))
                                    (player.body::body-active body))))
        (sb-int:unencapsulate 'player.body::compose-pose 'polish-count)))))

(test many-blink-drivers-started-at-once-cost-linear-work
  "Four times as many blink drivers started at one instant by one script
cost less than six times the work (it was sixteen: every start composed the
pose with every driver started before it)."
  (multiple-value-bind (small small-active) (blinker-work 100)
    (multiple-value-bind (large large-active) (blinker-work 400)
      ;; The idle blink makes one more.
      (is (<= 100 small-active 101) "~D blink drivers active of 100" small-active)
      (is (<= 400 large-active 401) "~D blink drivers active of 400" large-active)
      (is (< large (* 6 small)) "400 drivers cost ~D, 100 cost ~D: ~,1Fx" large small (/ large small)))))
