;;;; cradle-timing.lisp -- the cradle's moves in time: how long each takes,
;;;; and the intermediate states a move passes through (its granularity).
;;;;
;;;; Clark & Palmer (§5) suggest transitions "annotated with a length of time"
;;;; and "functions which generate intermediate states to any level of
;;;; detail", for acceleration. A sphere is a pendulum: a swing between an
;;;; extreme and the bottom takes a quarter of its period, (π/2)·√(L/g), and
;;;; along it the angle follows the pendulum's cosine, so the sphere swings
;;;; fastest at the bottom and slows to a stop at the top. Stopping, turning
;;;; and colliding are near-instants (*CRADLE-INSTANT*).

(in-package #:player.compose)

(defparameter *gravity* 9.81d0 "m/s².")

(defparameter *cradle-instant* 0.05d0
  "The seconds a move in which no sphere changes position takes (a turn at an
extreme, a collision): short, but long enough to be drawn.")

(defparameter *cradle-lift-seconds* 1
  "The seconds the hand takes to lift spheres from rest.")

(defun cradle-swing-seconds ()
  "The seconds a sphere takes to swing between an extreme and the bottom: a
quarter of the period of a pendulum as long as the cradle's strings."
  (rounded (* (/ pi 2) (sqrt (/ (cradle-geometry :string) *gravity*)))))

(defun cradle-move-seconds (source target)
  "The seconds the cradle's move from node SOURCE to TARGET takes: a swing
when some sphere changes position, an instant otherwise."
  (if (some (lambda (a b) (/= (car a) (car b))) (cradle-spheres source) (cradle-spheres target))
      (cradle-swing-seconds)
      *cradle-instant*))

(defun timed-cradle (graph &optional (rest nil rest-p))
  "GRAPH, a cradle graph, with each move's time (CRADLE-MOVE-SECONDS); a move
out of the node REST (to another node), when REST is given, is a hand lifting spheres
(*CRADLE-LIFT-SECONDS*)."
  (graph-with-durations graph (lambda (source target)
                                (if (and rest-p (equal source rest) (not (equal target rest)))
                                    *cradle-lift-seconds*
                                    (cradle-move-seconds source target)))))

(defun pendulum-fraction (before after u)
  "Where a sphere moving from position BEFORE to AFTER is at the fraction U
(0 ... 1) of the move's time, as a signed fraction of the extreme: a fall
from an extreme follows cos(πu/2), a rise to one sin(πu/2), so the sphere is
fastest at the bottom."
  (cond ((= before after) before)
        ((zerop before) (* after (sin (* u (/ pi 2)))))
        (t (* before (cos (* u (/ pi 2)))))))

(defun cradle-refinement (source target steps)
  "The granularity function of the cradle: the intermediate states of the
move from node SOURCE to TARGET at STEPS + 1 evenly spaced instants, as a
list of (U . ANGLES), U from 0 to 1 and ANGLES each sphere's string angle in
radians, leftmost first (positions between -1 and 1 scaled by the swing)."
  (check-argument 'cradle-refinement 'steps steps (lambda (x) (typep x '(integer 1))) "an integer >= 1")
  (loop for k from 0 to steps
        for u = (/ k steps)
        collect (cons u (loop for a in (cradle-spheres source)
                              for b in (cradle-spheres target)
                              collect (cradle-angle (pendulum-fraction (car a) (car b) u))))))
