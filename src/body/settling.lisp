;;;; settling.lisp -- a body comes to rest in its settled pose.  A channel
;;;; nobody drives either holds its last angle (between the items of a script
;;;; still playing) or settles: it eases, on a minimum-jerk curve, from where
;;;; it was let go to the body's settled pose (BODY-TARGET), over seconds that
;;;; follow how far it has to travel.  The performance says when channels
;;;; settle (the script that drove them is over, cut or not) and what the
;;;; settled pose is (the pose of the state the controller is in); here is
;;;; only the mechanism, so that a body's last pose depends on where it must
;;;; end, never on the path it took there.

(in-package #:player.body)

(defparameter *settle-speed* 90d0
  "Degrees a second a settling joint travels on average (a morph weight of 1 counts as 90 degrees).")

(defparameter *shortest-settle* 0.3d0
  "Seconds the shortest settling takes, however small the travel: a move the eye can follow.")

(defparameter *longest-settle* 1.5d0
  "Seconds the longest settling takes, however far the travel.")

(defun settle-seconds (travel)
  "Seconds a settling over TRAVEL degrees takes: TRAVEL at *SETTLE-SPEED*,
no less than *SHORTEST-SETTLE* and no more than *LONGEST-SETTLE*."
  (max *shortest-settle* (min *longest-settle* (/ (abs travel) *settle-speed*))))

(defun channel-travel (body index)
  "How far channel INDEX of BODY is from the settled pose, counted from its
held angle, in degrees (a morph weight scaled to degrees)."
  (let ((delta (abs (- (aref (body-target body) index) (aref (body-held body) index)))))
    (if (>= index (skeleton-dof-count (body-skeleton body)))
        (* delta *settle-speed*)
        delta)))

(defun settling-value (body index time)
  "The value at TIME of BODY's channel INDEX, driven by nobody: its held
angle, or, when it settles, that angle eased toward the settled pose."
  (let ((held (aref (body-held body) index)))
    (if (svref (body-settling body) index)
        (let ((seconds (aref (body-blends body) index)))
          (+ held (* (if (<= seconds 0d0)
                         1d0
                         (minimum-jerk (/ (- time (aref (body-handovers body) index)) seconds)))
                     (- (aref (body-target body) index) held))))
        held)))

(defun restart-settling (body indices time)
  "Start channels INDICES of BODY (driven by nobody) settling at TIME from
where they are now, all over the seconds the largest travel among them takes,
so a body comes to rest as one."
  (when indices
    (let ((held (body-held body)) (base (body-base body)))
      (dolist (i indices)
        (setf (aref held i) (aref base i)))
      (let ((seconds (settle-seconds (loop for i in indices maximize (channel-travel body i)))))
        (dolist (i indices)
          (setf (svref (body-settling body) i) t
                (aref (body-handovers body) i) time
                (aref (body-blends body) i) seconds))))))

(defun check-settle-arguments (function body time)
  "Check BODY and TIME for FUNCTION: an ARGUMENT-ERROR for the first of the wrong kind."
  (check-argument function 'body body #'body-p "a body (from make-body)")
  (check-seconds function 'time time))

(defun body-settle-channels (body drivers time)
  "From TIME on, every channel of BODY last driven by one of DRIVERS settles
when nobody drives it: at once if nobody does at TIME, else when it is let
go.  What a performance says when the script those drivers played is over."
  (check-settle-arguments 'body-settle-channels body time)
  (let ((time (float time 1d0)))
    (body-evaluate body time)
    (restart-settling body
                      (loop for i below (length (body-owners body))
                            when (member (svref (body-last-owners body) i) drivers :test #'eq)
                              if (svref (body-owners body) i)
                                do (setf (svref (body-settling body) i) t)
                              else collect i)
                      time)
    (compose-pose body time)))

(defun body-settle-to (body pose time)
  "Make POSE (a pose of BODY's skeleton) BODY's settled pose from TIME on:
the channels settling then turn toward it from where they are."
  (check-settle-arguments 'body-settle-to body time)
  (check-argument 'body-settle-to 'pose pose (lambda (x) (pose-of-p (body-skeleton body) x))
                  (pose-phrase (body-skeleton body)))
  (let ((time (float time 1d0)))
    (body-evaluate body time)
    (replace (body-target body) pose)
    (%clamp-pose (body-skeleton body) (body-target body))
    (restart-settling body
                      (loop for i below (length (body-owners body))
                            when (and (svref (body-settling body) i) (null (svref (body-owners body) i)))
                              collect i)
                      time)
    (compose-pose body time)))

(defun body-settled-time (body)
  "The time by which every channel of BODY that settles has arrived, as far
as is known at its last evaluation (channels still driven are not counted);
its last evaluation's time when none is on the way."
  (check-argument 'body-settled-time 'body body #'body-p "a body (from make-body)")
  (let ((latest (or (body-time body) 0d0)))
    (dotimes (i (length (body-owners body)) latest)
      (when (and (svref (body-settling body) i) (null (svref (body-owners body) i)))
        (setf latest (max latest (+ (aref (body-handovers body) i) (aref (body-blends body) i))))))))
