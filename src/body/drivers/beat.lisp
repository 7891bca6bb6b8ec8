;;;; beat.lisp -- Pantomime's BeatDriver: McNeill's beats, the small quick
;;;; down-and-up flicks of the hand that mark stressed words.  Around the arm's
;;;; pose at the start, the forearm and the hand dip at each beat time and
;;;; come back.  A parrot's wing beats the same way through its arm chain.

(in-package #:player.body)

(defparameter *beat-elbow-degrees* 12
  "How far the forearm dips in a beat of amplitude 1, in degrees.")

(defparameter *beat-wrist-degrees* 15
  "How far the hand dips at the wrist in a beat of amplitude 1, in degrees.")

(defclass beat-driver (driver)
  ((from :initform nil :accessor beat-from
         :documentation "The angles of the driven DOFs at the start.")
   (flicks :initform '() :accessor beat-flicks
           :documentation "(INDEX . DEGREES): the DOFs a beat turns and how far, chosen in DRIVER-BEGIN.")
   (time-vector :initform nil :accessor beat-time-vector
                :documentation "The :times as a vector, for bisection."))
  (:documentation "Beats an arm: at each time the forearm (elbow flexion) and the
hand (the wrist DOF that lowers it most) dip by a few degrees and return; all
other elbow and wrist DOFs hold their start angles."))

(define-motor-function :beat beat-driver
  "Beat gestures: at each of :times the forearm and hand flick down and back up,
around the arm's pose at the start; ends after the last beat."
  (:arm (:member :left :right) :right "the arm (or wing) that beats")
  (:times :list :required "increasing seconds from the start; the hand is lowest at each")
  (:amplitude :non-negative 1.0 "size: 1 dips the forearm 12 degrees and the hand 15")
  (:stroke :positive 0.1 "seconds of the down stroke, ending at each beat time")
  (:retract :positive 0.25 "seconds back to the start pose after each beat")
  (:additive :boolean t "add the flicks onto whatever holds the arm (a held reach, a pose); NIL takes the arm")
  (:priority :real 15 "arbitration priority; higher wins"))

(defun beat-arm-joints (driver)
  "The elbow and wrist of DRIVER's beating arm, as two values; a MOTOR-ERROR without the arm role."
  (let ((chain (role-joint driver (ecase (driver-arg driver :arm)
                                    (:left :left-arm) (:right :right-arm)))))
    (values (second chain) (third chain))))

(defmethod driver-setup ((driver beat-driver))
  (check-increasing-times driver (driver-arg driver :times) ":times")
  (multiple-value-bind (elbow wrist) (beat-arm-joints driver)
    (append (joint-dof-indices elbow) (joint-dof-indices wrist))))

;;;# Which way is down

(defun hand-point (skeleton pose wrist placement)
  "Where the hand beyond WRIST is in POSE, as a vec3: the middle of the wrist's
children (fingers, primaries), or the wrist itself when it has none."
  (let* ((transform (joint-world-transform skeleton pose wrist placement))
         (children (body-joint-children wrist)))
    (if (null children)
        (transform-translation transform)
        (let ((sum (vec3)))
          (dolist (child children)
            (nv+ sum (joint-offset child)))
          (transform-point transform (v* sum (/ 1d0 (length children))))))))

(defun flick-candidates (skeleton pose indices degrees)
  "For each DOF of INDICES and each direction, the turn (INDEX . DELTA) of up to
DEGREES that stays within the limits from POSE's angle."
  (loop for index in indices
        for dof = (nth-value 1 (skeleton-dof skeleton index))
        for angle = (aref pose index)
        nconc (list (cons index (max 0d0 (min (float degrees 1d0) (- (body-dof-max dof) angle))))
                    (cons index (- (max 0d0 (min (float degrees 1d0) (- angle (body-dof-min dof)))))))))

(defun choose-flick (skeleton pose wrist placement indices degrees)
  "The turn (INDEX . DELTA) among the DOFs INDICES that lowers the hand most; when
none lowers it by a millimetre (an arm hanging straight), the largest turn of
the first DOF, so the beat still shows."
  (let* ((rest-height (vec3-y (hand-point skeleton pose wrist placement)))
         (scored (mapcar (lambda (candidate)
                           (let ((turned (copy-pose pose)))
                             (incf (aref turned (car candidate)) (cdr candidate))
                             (cons candidate
                                   (- rest-height
                                      (vec3-y (hand-point skeleton turned wrist placement))))))
                         (flick-candidates skeleton pose indices degrees)))
         (best (first (stable-sort (copy-list scored) #'> :key #'cdr))))
    (if (> (cdr best) 1d-3)
        (car best)
        (first (stable-sort (remove-if-not (lambda (c) (= (car c) (first indices)))
                                    (mapcar #'car scored))
                     #'> :key (lambda (c) (abs (cdr c))))))))

(defmethod driver-begin ((driver beat-driver) pose time)
  (declare (ignore time))
  (let ((skeleton (driver-skeleton driver))
        (placement (object-world-transform (driver-body driver)))
        (amplitude (gesture-amplitude driver :amplitude)))
    (setf (beat-from driver) (capture-angles pose (driver-channels driver)))
    (multiple-value-bind (elbow wrist) (beat-arm-joints driver)
      ;; The forearm takes whichever elbow DOF lowers the hand (flexion on
      ;; Player's own skeletons; an imported arm may be anyhow turned: a
      ;; T-pose's x is a twist), the first when none does; the hand
      ;; whichever wrist DOF lowers it (deviation, with the palm in).
      (setf (beat-flicks driver)
            (list (choose-flick skeleton pose wrist placement
                                (joint-dof-indices elbow)
                                (* amplitude *beat-elbow-degrees*))
                  (choose-flick skeleton pose wrist placement (joint-dof-indices wrist)
                                (* amplitude *beat-wrist-degrees*)))))))

;;;# Driving

(defun beat-pulse (local at stroke retract)
  "How far into a beat at AT (local seconds) the arm is at LOCAL: 0 at rest, 1
at AT; the stroke eases down over STROKE seconds (not before the start), the
retraction eases back over RETRACT."
  (if (<= local at)
      (let ((begin (max 0d0 (- at stroke))))
        (eased-fraction local begin (- at begin)))
      (- 1d0 (eased-fraction local at retract))))

(defmethod driver-drive ((driver beat-driver) time pose)
  (let* ((local (driver-local-time driver time))
         (stroke (gesture-seconds driver :stroke))
         (retract (gesture-seconds driver :retract))
         ;; Beats closer than a stroke and retraction merge rather than add.
         (times (beat-times driver))
         ;; Only beats whose stroke or retraction covers LOCAL can move the arm.
         (pulse (loop for i from (first-time-after times (- local retract)) below (length times)
                      for at = (aref times i)
                      while (<= (- at stroke) local)
                      maximize (beat-pulse local at stroke retract))))
    (if (driver-additive-p driver)
        ;; Onto whatever holds the arm: only the flicking DOFs move.
        (loop with weight = (driver-weight driver)
              for (index . degrees) in (beat-flicks driver)
              do (incf (aref pose index) (* weight pulse degrees)))
        (loop for index in (driver-channels driver)
              for start across (beat-from driver)
              for flick = (assoc index (beat-flicks driver))
              do (setf (aref pose index) (if flick (+ start (* pulse (cdr flick))) start))))))

(defmethod driver-additive-p ((driver beat-driver))
  (driver-arg driver :additive))

(defmethod driver-end-time ((driver beat-driver))
  (let ((times (beat-times driver)))
    (+ (driver-start driver) (aref times (1- (length times))) (gesture-seconds driver :retract))))

(defmethod driver-default-blend ((driver beat-driver))
  ;; It eases from the angles it captured at its start: a crossfade would only slow it.
  0d0)

(defun beat-times (driver)
  "DRIVER's :times as a TIMES-VECTOR, made once."
  (or (beat-time-vector driver)
      (setf (beat-time-vector driver)
            (map 'times-vector (lambda (at) (float at 1d0)) (driver-arg driver :times)))))
