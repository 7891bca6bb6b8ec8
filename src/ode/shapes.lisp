;;;; shapes.lisp -- the shapes Player collides: spheres, boxes, capsules and
;;;; planes, written as lists so they read in data and print in reports.
;;;;
;;;;   (:sphere RADIUS)   (:box X Y Z)   (:capsule RADIUS LENGTH)   (:plane A B C D)
;;;;
;;;; Metres.  A box is centred on its origin, X Y Z its edges; a capsule's axis
;;;; is its local z, LENGTH between the centres of its end caps; a plane is the
;;;; half-space A·x + B·y + C·z <= D, its normal (A B C) pointing out.

(in-package #:player.ode)

(defun ode-shape-p (x)
  "Is X a shape: (:sphere R), (:box X Y Z), (:capsule R LENGTH) with positive
sizes, or (:plane A B C D) with a nonzero normal?"
  (and (consp x) (alexandria:proper-list-p x)
       (every #'finite-real-p (rest x))
       (case (first x)
         (:sphere (and (= (length x) 2) (plusp (second x))))
         (:box (and (= (length x) 4) (every #'plusp (rest x))))
         (:capsule (and (= (length x) 3) (plusp (second x)) (not (minusp (third x)))))
         (:plane (and (= (length x) 5) (some (lambda (c) (/= c 0)) (subseq x 1 4))))
         (t nil))))

(defparameter *shape-phrase*
  "a shape: (:sphere R), (:box X Y Z), (:capsule R LENGTH) with positive sizes, or (:plane A B C D)"
  "What a shape argument must be, for errors.")

(defun set-mass-of-shape (mass-pointer shape total)
  "Fill the dMass at MASS-POINTER: TOTAL kilograms spread over SHAPE."
  (let ((total (float total 1d0))
        (sizes (mapcar (lambda (x) (float x 1d0)) (rest shape))))
    (with-ode-traps-masked
      (%d-mass-set-zero mass-pointer)
      (ecase (first shape)
        (:sphere (%d-mass-set-sphere-total mass-pointer total (first sizes)))
        (:box (apply #'%d-mass-set-box-total mass-pointer total sizes))
        ;; direction 3: the capsule's axis is its local z, as dCreateCapsule makes it.
        (:capsule (%d-mass-set-capsule-total mass-pointer total 3 (first sizes) (second sizes)))))))

(defun create-shape-geom (space shape)
  "A new dGeom of SHAPE in SPACE (the raw pointer)."
  (let ((sizes (mapcar (lambda (x) (float x 1d0)) (rest shape))))
    (with-ode-traps-masked
      (ecase (first shape)
        (:sphere (%d-create-sphere space (first sizes)))
        (:box (apply #'%d-create-box space sizes))
        (:capsule (%d-create-capsule space (first sizes) (second sizes)))
        (:plane (let* ((normal (subseq sizes 0 3))
                       (length (sqrt (reduce #'+ (mapcar #'* normal normal)))))
                  ;; ODE wants a unit normal; D scales with it.
                  (apply #'%d-create-plane space (mapcar (lambda (x) (/ x length)) sizes))))))))
