;;;; gesture-space.lisp -- where an arm reaches in Pantomime's terms: its
;;;; gesture space ("gs": the origin between the shoulders, 1.0 in y and z an
;;;; arm's length, 1.0 in x an arm's length and half the shoulders' width), the
;;;; zones McNeill drew on it (Hand and Mind, 1992: centre-centre, centre,
;;;; periphery, extreme periphery), the elbow's swivel about the
;;;; shoulder-wrist line (phi) and the forearm's twist (rho).

(in-package #:player.body)

(defparameter *gesture-zones*
  '((:center-center 0 -0.3 0.35) (:center 0.25 -0.2 0.45)
    (:periphery-upper 0.2 0.25 0.5) (:periphery-lower 0.2 -0.6 0.4) (:periphery-side 0.55 -0.2 0.4)
    (:extreme-periphery-upper 0.3 0.65 0.55) (:extreme-periphery-lower 0.4 -0.85 0.3)
    (:extreme-periphery-side 0.85 0 0.3))
  "McNeill's gesture-space zones as points of gesture space (X Y Z), X toward
the reaching arm's side: the centre-centre before the chest, the centre around
it, the periphery beyond, the extreme periphery at the arm's reach.")

(defun zone-form-p (x)
  "Is X a zone target, (:zone NAME) with NAME one of *GESTURE-ZONES*?"
  (and (alexandria:proper-list-p x) (= (length x) 2) (eq (first x) :zone)
       (assoc (second x) *gesture-zones*) t))

(defun arm-side (driver)
  "1 for DRIVER's :arm :left (the figure's +x), -1 for :right."
  (if (eq (driver-arg driver :arm) :left) 1d0 -1d0))

(defun joint-rest-position (joint)
  "JOINT's centre in the skeleton's rest frame, as a vec3."
  (let ((c (body-joint-center joint)))
    (make-vec3 (svref c 0) (svref c 1) (svref c 2))))

(defun gesture-space-point (driver pose x y z)
  "The world point at gesture-space (X Y Z) of DRIVER's body in POSE: between
the shoulders at rest, scaled by the arm's length, carried by the root joint
\(so a body that turned to face someone gestures in front of itself)."
  (let* ((skeleton (driver-skeleton driver))
         (left (first (skeleton-role skeleton :left-arm)))
         (right (first (skeleton-role skeleton :right-arm)))
         (arm (role-joint driver (if (plusp (arm-side driver)) :left-arm :right-arm)))
         (origin (v* (v+ (joint-rest-position left) (joint-rest-position right)) 0.5d0))
         (length (+ (vdistance (joint-rest-position (first arm)) (joint-rest-position (second arm)))
                    (vdistance (joint-rest-position (second arm)) (joint-rest-position (third arm)))))
         (half-width (* 0.5d0 (vdistance (joint-rest-position left) (joint-rest-position right))))
         (root (skeleton-root skeleton))
         (frame (joint-world-transform skeleton pose root (object-world-transform (driver-body driver)))))
    (transform-point frame (v- (v+ origin (make-vec3 (* x (+ length half-width)) (* y length) (* z length)))
                               (joint-rest-position root)))))

(defun reach-target-point (driver pose)
  "The world point DRIVER reaches for in POSE: a zone, a gesture-space point
\(:space :gesture), or a target resolved in the world."
  (let ((target (driver-arg driver :target)))
    (cond ((zone-form-p target)
           (destructuring-bind (x y z) (rest (assoc (second target) *gesture-zones*))
             (gesture-space-point driver pose (* (arm-side driver) x) y z)))
          ((and (eq (driver-arg driver :space) :gesture) (eq (first target) :point))
           (destructuring-bind (x y z) (subseq target 1 4)
             (gesture-space-point driver pose (to-double x) (to-double y) (to-double z))))
          (t (%resolve-target target (driver-body driver) pose)))))

(defun swivel-arm (chain pose angles target degrees side)
  "Turn the shoulder of CHAIN's solved ANGLES (POSE holding the other joints)
about the line from the shoulder to TARGET (its parent frame) by DEGREES, the
elbow swinging outward (toward SIDE, 1 the figure's left) for positive DEGREES;
the hand stays where it is on the line.  Returns ANGLES."
  (multiple-value-bind (before w) (arm-chain-held chain pose)
    (let* ((shoulder (arm-chain-shoulder-offset chain))
           (axis (vnormalize (v- target shoulder)))
           (out (arm-chain-evaluate chain angles before w (make-evaluation chain)))
           (elbow (make-vec3 (aref out 3) (aref out 4) (aref out 5)))
           (outward (if (minusp (* side (vec3-x (vcross axis (v- elbow shoulder))))) -1d0 1d0))
           (count (1- (arm-chain-size chain)))
           (rs (quat)))
      (loop for dof in (body-joint-dofs (arm-chain-shoulder chain))
            for i from 0
            do (setf rs (q* rs (dof-rotation dof (aref angles i)))))
      (let ((turned (joint-angles-for-rotation
                     (arm-chain-shoulder chain)
                     (q* (quat-from-axis-angle axis (* outward degrees (/ pi 180))) rs)
                     (loop for i below count collect (aref angles i)))))
        (loop for angle in turned for i from 0 do (setf (aref angles i) angle)))
      angles)))

(defun forearm-twist-index (chain)
  "The pose index of the elbow's DOF that twists the forearm (not the hinge), or NIL."
  (let ((elbow (arm-chain-elbow chain)))
    (loop for dof in (body-joint-dofs elbow)
          for k from 0
          unless (= k (arm-chain-hinge chain))
            return (+ (body-joint-dof-start elbow) k))))
