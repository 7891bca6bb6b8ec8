;;;; idle-life.lisp -- a body at rest is never still (Pantomime: "drivers
;;;; running basic continuous processes such as eye-blinking and stance should
;;;; have low priority but should always be trying to drive their respective
;;;; DOF's"): the motor calls of idle life, each a driver on its own layer
;;;; that any op overrides, for whatever a skeleton can do of them.

(in-package #:player.body)

(defparameter *idle-life-calls*
  '((:blink :mean-interval 4 :regularity 8 :idle t)
    (:breathe)
    (:saccades)
    (:weight-shift)
    (:hand-relaxer)
    (:swing-legs))
  "The motor calls of idle life: blinks (every 4 s on average), breathing, small
saccades, weight shifts, relaxed hands, and legs that swing while sitting awake.")

(defun idle-life-drivers (body start &key (seed 0))
  "Drivers performing *IDLE-LIFE-CALLS* on BODY from START, those its skeleton
cannot perform (a figure without lids does not blink) left out; SEED varies
the random ones (blink intervals, saccades, shifts) between characters."
  (check-argument 'idle-life-drivers 'body body #'body-p "a body (from make-body)")
  (check-seconds 'idle-life-drivers 'start start)
  (check-real 'idle-life-drivers :seed seed :integer t :minimum 0)
  (loop for frame in *idle-life-calls*
        for call = (parse-motor-frame (if (member (first frame) '(:blink :saccades :weight-shift))
                                          (append frame (list :seed (+ seed (if (eq (first frame) :blink) 1 2))))
                                          frame))
        for driver = (handler-case (make-driver call body start)
                       (motor-error () nil))
        when driver collect driver))

(defun start-idle-life (body start &key (seed 0))
  "Add BODY's IDLE-LIFE-DRIVERS from START; return them."
  (let ((drivers (idle-life-drivers body start :seed seed)))
    (dolist (driver drivers drivers)
      (body-add-driver body driver))))
