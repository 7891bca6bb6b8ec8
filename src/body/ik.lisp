;;;; ik.lisp -- inverse kinematics of an arm (or a wing) to a point, within the
;;;; joint limits: analytic two-bone first; where limits or reach leave a gap,
;;;; damped least squares, then a coarse search for better starts.

(in-package #:player.body)

;;; The solver works in the frame P of the shoulder's parent, where the
;;; shoulder's centre S stays put: there the effector is S + Rs (a + Re u), Rs
;;; and Re the shoulder's and elbow's local rotations, a the elbow's offset, u
;;; the effector in the elbow's frame (joints between keep their angles).  It
;;; solves the shoulder's DOFs and the elbow's hinge; the elbow's other DOFs
;;; (a forearm twist) stay: Re = BEFORE R(hinge) AFTER, W = AFTER u.  Degrees.

(defparameter *reach-tolerance* 1d-4
  "Metres: an analytic solution that misses by more than this is refined.")

(defparameter *reach-refinement-iterations* 100
  "The most damped-least-squares steps one refinement takes.")

(defparameter *reach-search-distance* 1d-3
  "Metres: a refined solution still this far off is compared with a search's.")

(defparameter *reach-search-steps* 5
  "Search grid points per angle, from limit to limit (arms out of reach end at limits).")

(defparameter *reach-search-seeds* 4
  "How many of the search grid's best local minima are refined.")

(defparameter *reach-swivel-steps* 12
  "Swivels of the arm about the shoulder-target line tried each way, 15 degrees apart.")

(deftype angle-vector () '(simple-array double-float (*)))

;;;# The chain

(defstruct (arm-chain (:constructor %make-arm-chain))
  "A shoulder, its child the elbow, and an effector below the elbow, for
SOLVE-ARM-CHAIN.  INDICES are the pose indices of the solved angles: the
shoulder's DOFs in file order, then the elbow's HINGE-th DOF; AXES their unit
axes (three numbers each), MINIMA and MAXIMA their limits."
  (shoulder nil :type body-joint :read-only t)
  (elbow nil :type body-joint :read-only t)
  (effector nil :type body-joint :read-only t)
  (hinge 0 :type fixnum :read-only t)
  (indices #() :type simple-vector :read-only t)
  (axes nil :type angle-vector :read-only t)
  (minima nil :type angle-vector :read-only t)
  (maxima nil :type angle-vector :read-only t)
  (shoulder-offset nil :type vec3 :read-only t)
  (elbow-offset nil :type vec3 :read-only t))

(defun dof-axis-vec3 (dof)
  "DOF's unit axis as a new vec3."
  (apply #'make-vec3 (dof-axis-vector dof)))

(defun make-arm-chain (shoulder elbow effector)
  "The arm chain of the joints SHOULDER, ELBOW and EFFECTOR, or NIL and a
sentence saying why they make none.  The hinge is the elbow's DOF most across
the forearm at rest: the one that bends it rather than twists it."
  (flet ((name (joint) (lisp-text (body-joint-name joint)))
         (center (joint) (apply #'make-vec3 (coerce (body-joint-center joint) 'list))))
    (cond ((not (and shoulder elbow effector))
           (values nil "an arm needs a shoulder, an elbow and a hand"))
          ((not (eq (body-joint-parent elbow) shoulder))
           (values nil (format nil "~A is not a child of ~A" (name elbow) (name shoulder))))
          ((not (and (body-joint-dofs shoulder) (body-joint-dofs elbow)))
           (values nil (format nil "~A or ~A has no DOFs" (name shoulder) (name elbow))))
          ((not (loop for j = (body-joint-parent effector) then (body-joint-parent j)
                      while j thereis (eq j elbow)))
           (values nil (format nil "~A is not below ~A" (name effector) (name elbow))))
          (t
           (let* ((forearm (v- (center effector) (center elbow)))
                  (across (mapcar (lambda (dof) (vnorm (vcross (dof-axis-vec3 dof) forearm)))
                                  (body-joint-dofs elbow)))
                  (hinge (position (reduce #'max across) across))
                  (dofs (append (body-joint-dofs shoulder) (list (nth hinge (body-joint-dofs elbow))))))
             (flet ((numbers (key) (map 'angle-vector (lambda (x) (float x 1d0)) (mapcan key dofs))))
               (%make-arm-chain
                :shoulder shoulder :elbow elbow :effector effector :hinge hinge
                :indices (coerce (append (joint-dof-indices shoulder)
                                         (list (+ (body-joint-dof-start elbow) hinge)))
                                 'simple-vector)
                :axes (numbers (lambda (dof) (copy-list (dof-axis-vector dof))))
                :minima (numbers (lambda (dof) (list (body-dof-min dof))))
                :maxima (numbers (lambda (dof) (list (body-dof-max dof))))
                :shoulder-offset (joint-offset shoulder) :elbow-offset (joint-offset elbow))))))))

(defun arm-chain-size (chain)
  "How many angles CHAIN solves."
  (length (arm-chain-indices chain)))

(defun arm-chain-angles (chain pose)
  "CHAIN's solved angles as they are in POSE, as a new angle vector."
  (map 'angle-vector (lambda (i) (aref pose i)) (arm-chain-indices chain)))

(defun arm-chain-parent-transform (chain pose &optional (placement (identity-transform)) skeleton)
  "The world transform of the frame CHAIN is solved in (its shoulder's
parent's) in POSE, the body placed by PLACEMENT; SKELETON, CHAIN's when
given, makes it cheaper (see JOINT-WORLD-TRANSFORM)."
  (let ((parent (body-joint-parent (arm-chain-shoulder chain))))
    (if parent (joint-world-transform skeleton pose parent placement) placement)))

(defun arm-chain-held (chain pose)
  "What POSE holds fixed in CHAIN's elbow, two values: BEFORE, the product of
its DOF rotations before the hinge, and W, the effector in the frame after the
hinge (the later elbow DOFs and the joints down to the effector as in POSE)."
  (let ((before (quat)) (after (quat)) (elbow (arm-chain-elbow chain))
        (w (joint-offset (arm-chain-effector chain))))
    (loop for joint = (body-joint-parent (arm-chain-effector chain)) then (body-joint-parent joint)
          until (eq joint elbow)
          do (setf w (nv+ (qrotate (joint-local-rotation joint pose) w) (joint-offset joint))))
    (loop for dof in (body-joint-dofs elbow)
          for i from (body-joint-dof-start elbow)
          for k from 0
          do (cond ((< k (arm-chain-hinge chain)) (nq* before (dof-rotation dof (aref pose i))))
                   ((> k (arm-chain-hinge chain)) (nq* after (dof-rotation dof (aref pose i))))))
    (values before (qrotate after w))))

;;;# Forward kinematics

(defun make-evaluation (chain)
  "A vector for ARM-CHAIN-EVALUATE to fill."
  (make-array (+ 6 (* 3 (arm-chain-size chain))) :element-type 'double-float))

(defun arm-chain-evaluate (chain angles before w out)
  "CHAIN in its parent frame for ANGLES, BEFORE and W, without consing.  OUT
(see MAKE-EVALUATION) receives the effector (0-2), the elbow (3-5) and the
axis of each angle (from 6), for the Jacobian.  Returns OUT."
  (declare #.*anim-optimize* (type angle-vector angles out) (type quat before) (type vec3 w))
  (let ((axes (arm-chain-axes chain)) (s (arm-chain-shoulder-offset chain))
        (a (arm-chain-elbow-offset chain)) (last (1- (length angles)))
        (qw 1d0) (qx 0d0) (qy 0d0) (qz 0d0))
    (declare (type double-float qw qx qy qz) (type fixnum last))
    (macrolet ((turn (bw bx by bz)      ; q <- q b
                 `(%quat-product (qw qx qy qz) (,bw ,bx ,by ,bz)
                                 (lambda (w* x y z) (setf qw w* qx x qy y qz z))))
               (rotate ((x y z) at)     ; out[at ... at+2] <- q (x y z)
                 `(%quat-rotation (qw qx qy qz) (,x ,y ,z)
                                  (lambda (rx ry rz)
                                    (setf (aref out ,at) rx (aref out (+ 1 ,at)) ry (aref out (+ 2 ,at)) rz)))))
      (flet ((axis-turn (i)             ; store angle I's axis, then turn by it
               (let* ((h (* (aref angles i) (/ pi 360d0))) (sine (sin h)) (cosine (cos h))
                      (ax (aref axes (* 3 i))) (ay (aref axes (+ 1 (* 3 i)))) (az (aref axes (+ 2 (* 3 i))))
                      (bx (* sine ax)) (by (* sine ay)) (bz (* sine az)))
                 (rotate (ax ay az) (+ 6 (* 3 i)))
                 (turn cosine bx by bz))))
        (declare (inline axis-turn))
        (dotimes (i last) (axis-turn i))
        (let ((ax (vec3-x a)) (ay (vec3-y a)) (az (vec3-z a)))
          (rotate (ax ay az) 3))
        (incf (aref out 3) (vec3-x s)) (incf (aref out 4) (vec3-y s)) (incf (aref out 5) (vec3-z s))
        (let ((bw (quat-w before)) (bx (quat-x before)) (by (quat-y before)) (bz (quat-z before)))
          (turn bw bx by bz))
        (axis-turn last)
        (let ((wx (vec3-x w)) (wy (vec3-y w)) (wz (vec3-z w)))
          (rotate (wx wy wz) 0))
        (dotimes (k 3 out) (incf (aref out k) (aref out (+ 3 k))))))))

(declaim (inline evaluation-distance))
(defun evaluation-distance (out target)
  "How far the effector in OUT (see ARM-CHAIN-EVALUATE) is from TARGET."
  (declare #.*anim-optimize* (type angle-vector out) (type vec3 target))
  (let ((dx (- (vec3-x target) (aref out 0))) (dy (- (vec3-y target) (aref out 1)))
        (dz (- (vec3-z target) (aref out 2))))
    (sqrt (+ (* dx dx) (* dy dy) (* dz dz)))))

;;;# Analytic steps

(declaim (inline fit-angle))
(defun fit-angle (degrees minimum maximum current)
  "DEGREES moved by whole turns into [MINIMUM, MAXIMUM] (the turn nearest
CURRENT when several fit), else clamped from the turn needing least clamping:
two values, that angle and how far clamping moved it.  All double-floats."
  (declare (type double-float degrees minimum maximum current))
  (let ((best 0d0) (best-violation -1d0) (best-gap 0d0))
    (declare (type double-float best best-violation best-gap))
    (loop for k of-type fixnum from -2 to 2
          do (let* ((a (+ degrees (* 360d0 k)))
                    (clamped (max minimum (min maximum a)))
                    (violation (abs (- a clamped)))
                    (gap (abs (- clamped current))))
               (when (or (< best-violation 0d0) (< violation (- best-violation 1d-9))
                         (and (<= violation (+ best-violation 1d-9)) (< gap best-gap)))
                 (setf best clamped best-violation violation best-gap gap))))
    (values best best-violation)))

(defun solve-hinge (a w axis current minimum maximum distance)
  "The angle in [MINIMUM, MAXIMUM] (degrees) of a hinge about the unit AXIS that
brings |A + R(angle) W| nearest DISTANCE; of equally near ones, the nearest
CURRENT.  |A + R W|^2 = C + P cos + Q sin, so the exact angles are closed-form;
when neither is within limits the best lies at a limit or an extreme."
  (declare #.*anim-optimize* (type vec3 a w axis) (type double-float current minimum maximum distance))
  (let* ((w-along (v* axis (vdot axis w)))
         (c (+ (vnorm-squared a) (vnorm-squared w) (* 2 (vdot a w-along))))
         (p (* 2 (vdot a (v- w w-along))))
         (q (* 2 (vdot a (vcross axis w))))
         (r (sqrt (+ (* p p) (* q q))))
         (phi (atan q p))
         (delta (if (< r 1d-12)
                    0d0
                    (acos (the (double-float -1d0 1d0)
                               (max -1d0 (min 1d0 (/ (- (* distance distance) c) r)))))))
         (best 0d0) (best-error -1d0) (best-gap 0d0))
    (declare (type double-float c p q phi delta best best-error best-gap))
    (flet ((try (radians)
             (let* ((angle (fit-angle (* radians (/ 180 pi)) minimum maximum current))
                    (radians (* angle (/ pi 180)))
                    (error (abs (- (sqrt (max 0d0 (+ c (* p (cos radians)) (* q (sin radians))))) distance)))
                    (gap (abs (- angle current))))
               (when (or (< best-error 0d0) (< error (- best-error 1d-9))
                         (and (<= error (+ best-error 1d-9)) (< gap best-gap)))
                 (setf best angle best-error error best-gap gap)))))
      (declare (inline try))
      (try (+ phi delta)) (try (- phi delta)) (try phi) (try (+ phi pi))
      (try (* minimum (/ pi 180))) (try (* maximum (/ pi 180)))
      best)))

(defun rotation-between (from to)
  "The smallest rotation turning the direction FROM to the direction TO, a new
unit quaternion (about some axis across FROM when they are opposite)."
  (let ((axis (vcross from to)))
    (when (< (vnorm axis) (* 1d-12 (vnorm from) (vnorm to)))
      (setf axis (let ((x (vcross from (vec3 1d0 0d0 0d0))))
                   (if (> (vnorm x) (* 1d-6 (vnorm from))) x (vcross from (vec3 0d0 1d0 0d0))))))
    (quat-from-axis-angle axis (atan (vnorm (vcross from to)) (vdot from to)))))

(defun joint-angles-for-rotation (joint rotation &optional current)
  "Angles (degrees) of JOINT's DOFs whose product R(dof1) R(dof2) R(dof3) in file
order is the unit quaternion ROTATION, clamped into the limits, as a list -- for
a joint with three DOFs about three different axes; NIL for others.  Of the two
exact solutions the one needing less clamping wins, then the one nearer
CURRENT (a list of degrees; zeros by default).  The second value is the
clamping needed, in degrees summed over the DOFs."
  (declare #.*anim-optimize* (type quat rotation))
  (let* ((dofs (body-joint-dofs joint))
         (axes (mapcar (lambda (dof) (position (dof-axis-line dof) '(:x :y :z))) dofs))
         (current (or current '(0d0 0d0 0d0))))
    (unless (and (= (length dofs) 3) (/= (first axes) (second axes) (third axes)))
      (return-from joint-angles-for-rotation nil))
    (destructuring-bind (i j k) axes
      (declare (type (integer 0 2) i j k))
      (let* ((m (the mat3 (quat-to-matrix rotation)))
             (e (if (= (mod (- j i) 3) 1) 1d0 -1d0)) ; a cyclic order (x y z, y z x, z x y) or not
             (signs (mapcar (lambda (dof) (float (reduce #'+ (dof-axis-vector dof)) 1d0)) dofs))
             (beta (asin (the (double-float -1d0 1d0) (max -1d0 (min 1d0 (* e (aref m i k)))))))
             ;; At gimbal lock only the outer angles' sum is defined: keep the
             ;; first where it is and let the third take the rest.
             (alpha (if (< (cos beta) 1d-7)
                        (* (the double-float (first signs)) (the double-float (first current)) (/ pi 180))
                        (atan (- (* e (aref m j k))) (aref m k k))))
             (best nil) (best-violation 0d0) (best-gap 0d0))
        (declare (type double-float e beta alpha best-violation best-gap))
        (flet ((unturn (n radians q)    ; R(axis n, radians)^-1 q
                 (let* ((h (* -0.5d0 radians)) (s (sin h)))
                   (q* (quat (cos h) (if (= n 0) s 0d0) (if (= n 1) s 0d0) (if (= n 2) s 0d0)) q))))
          (loop for (a b) of-type (double-float double-float) in (list (list alpha beta) (list (+ alpha pi) (- pi beta)))
                ;; The third angle from what the first two leave: robust at gimbal lock.
                for rest = (unturn j b (unturn i a rotation))
                for g = (* 2 (atan (ecase k (0 (quat-x rest)) (1 (quat-y rest)) (2 (quat-z rest)))
                                   (quat-w rest)))
                do (let* ((violation 0d0) (gap 0d0)
                          (fitted (loop for radians of-type double-float in (list a b g)
                                        for sign of-type double-float in signs
                                        for dof in dofs
                                        for now of-type double-float in current
                                        collect (multiple-value-bind (angle v)
                                                    (fit-angle (* sign radians (/ 180 pi))
                                                               (float (body-dof-min dof) 1d0)
                                                               (float (body-dof-max dof) 1d0) now)
                                                  (incf violation v)
                                                  (incf gap (expt (- angle now) 2))
                                                  angle))))
                     (declare (type double-float violation gap))
                     (when (or (null best) (< violation (- best-violation 1d-6))
                               (and (<= violation (+ best-violation 1d-6)) (< gap best-gap)))
                       (setf best fitted best-violation violation best-gap gap)))))
        (values best best-violation)))))

(defun aim-shoulder (chain angles reach goal)
  "Set the shoulder's angles in ANGLES so that REACH (shoulder to effector, in
its parent's frame) turns to point along GOAL: the smallest turn, else, when
that breaks the limits, it and the least swivel about GOAL that keeps within
them (or breaks them least)."
  (let ((rs (quat)) (best nil) (best-violation 0d0)
        (current (loop for i below (1- (arm-chain-size chain)) collect (aref angles i))))
    (loop for dof in (body-joint-dofs (arm-chain-shoulder chain))
          for angle in current
          do (nq* rs (dof-rotation dof angle)))
    (loop with aimed = (nq* (rotation-between reach goal) rs)
          for m from 0 to (* 2 *reach-swivel-steps*)
          for swivel = (* (if (evenp m) (- (/ m 2)) (/ (1+ m) 2)) (/ pi 12)) ; 0, 15, -15, 30 ...
          do (multiple-value-bind (solution violation)
                 (joint-angles-for-rotation (arm-chain-shoulder chain)
                                            (q* (quat-from-axis-angle goal swivel) aimed) current)
               (when (and solution (or (null best) (< violation best-violation)))
                 (setf best solution best-violation violation))
               (when (or (null solution) (< best-violation 1d-9))
                 (return))))
    (loop for angle in best for i from 0 do (setf (aref angles i) angle))
    angles))
