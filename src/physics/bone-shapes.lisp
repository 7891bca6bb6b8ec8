;;;; bone-shapes.lisp -- a body as collision shapes: its hands as probes (a
;;;; sphere at the hand joint and one at each joint it carries, fingers or a
;;;; wing's primaries) and its trunk as obstacles (a capsule along each bone
;;;; of the spine, from the root up, and a sphere for the head), each as
;;;; thick as its joint's :radius.  They are ODE geoms without bodies, placed
;;;; where the pose puts the joints, and disabled: only queries test them.

(in-package #:player.physics)

(defstruct (probe (:constructor make-probe (joint hand geom radius first)))
  "A sphere of GEOM (RADIUS metres) at JOINT of a HAND (:left or :right);
FIRST when JOINT is the hand joint itself (its hand's first probe)."
  joint hand geom (radius 0d0 :type double-float) (first nil))

(defstruct (trunk-part (:constructor make-trunk-part (body joint child geom radius)))
  "A part of BODY's trunk: a capsule GEOM from JOINT to CHILD, or a sphere at
JOINT when CHILD is NIL; RADIUS metres thick."
  body joint child geom (radius 0d0 :type double-float)
  ;; Where it was last placed: its axis FROM .. TO (TO unused for a sphere),
  ;; and whether its GEOM was put there yet (only a depth query needs it).
  (from (make-vec3 0d0 0d0 0d0) :type vec3) (to (make-vec3 0d0 0d0 0d0) :type vec3)
  (placed nil))

(defstruct (collider (:constructor make-collider (body probes trunk)))
  "BODY's collision shapes: its hands' PROBES and its TRUNK-PARTs.  SHOWN is
the pose shown last (a copy), where a correction starts from, at SHOWN-TIME.
CENTRE and REACH are a sphere holding the trunk as last placed (REACH NIL:
not placed yet), so a hand far from a body skips its parts."
  body probes trunk (shown nil) (shown-time nil)
  (centre (make-vec3 0d0 0d0 0d0) :type vec3) (reach nil))

(defun hand-joints (skeleton role)
  "The joint filling ROLE (:left-hand, :right-hand) of SKELETON and the joints it carries."
  (let ((joint (skeleton-role skeleton role)))
    (when (consp joint) (setf joint (car (last joint))))
    (and joint (cons joint (copy-list (body-joint-children joint))))))

(defun joint-radius (joint)
  "JOINT's thickness, metres."
  (float (body-joint-radius joint) 1d0))

(defun make-body-collider (world body)
  "BODY's collision shapes in WORLD: probes for both hands, its trunk as obstacles."
  (let* ((skeleton (body-skeleton body))
         (probes (loop for (role hand) in '((:left-hand :left) (:right-hand :right))
                       append (loop for joint in (hand-joints skeleton role)
                                    for first = t then nil
                                    collect (make-probe joint hand
                                                        (make-ode-geom world (list :sphere (joint-radius joint))
                                                                       :data (cons body joint))
                                                        (joint-radius joint) first))))
         (spine (let ((chain (skeleton-role skeleton :spine))) (if (consp chain) chain (and chain (list chain)))))
         (root (aref (skeleton-joints skeleton) 0))
         (bones (loop for (joint child) on (cons root spine)
                      while child
                      unless (eq joint child) collect (cons joint child)))
         (head (skeleton-role skeleton :head))
         (trunk (append
                 (loop for (joint . child) in bones
                       for radius = (joint-radius joint)
                       collect (make-trunk-part body joint child
                                                (make-ode-geom world (list :capsule radius 0.01) :data (cons body joint))
                                                radius))
                 (and (body-joint-p head)
                      (list (make-trunk-part body head nil
                                             (make-ode-geom world (list :sphere (joint-radius head)) :data (cons body head))
                                             (joint-radius head)))))))
    ;; Tested one by one (dCollide), never by the stepping's sweep: a note let
    ;; go inside the hand's sphere falls rather than sitting on it.
    (dolist (geom (append (mapcar #'probe-geom probes) (mapcar #'trunk-part-geom trunk)))
      (setf (ode-geom-enabled-p geom) nil))
    (make-collider body probes trunk)))

;;;# Placing

(defmacro with-joint-point (((x y z) transforms joint) &body body)
  "Run BODY with X, Y and Z bound to where JOINT is, from the world TRANSFORMS of a pose."
  (let ((m (gensym "M")))
    `(let ((,m (svref ,transforms (body-joint-index ,joint))))
       (declare (type mat4 ,m))
       (let ((,x (aref ,m 0 3)) (,y (aref ,m 1 3)) (,z (aref ,m 2 3)))
         (declare (type double-float ,x ,y ,z))
         ,@body))))

(defun joint-point (transforms joint)
  "Where JOINT is, from the world TRANSFORMS of a pose, as a new vec3."
  (with-joint-point ((x y z) transforms joint)
    (make-vec3 x y z)))

(defun set-vec3 (v x y z)
  "Set the vec3 V to (X Y Z); return V."
  (declare (type vec3 v) (type double-float x y z))
  (setf (vec3-x v) x (vec3-y v) y (vec3-z v) z)
  v)

(defun place-probe (probe x y z)
  "Put PROBE's sphere at (X Y Z)."
  (set-ode-geom-position (probe-geom probe) x y z))

(defun place-probes (collider transforms)
  "Put COLLIDER's probes where TRANSFORMS (a pose's joint world transforms) put their joints."
  (dolist (probe (collider-probes collider))
    (with-joint-point ((x y z) transforms (probe-joint probe))
      (place-probe probe x y z))))

(defun place-trunk (collider transforms)
  "Note where TRANSFORMS put the joints of COLLIDER's trunk parts; each part's
geom follows when a query needs it (PLACE-TRUNK-GEOM)."
  (dolist (part (collider-trunk collider))
    (with-joint-point ((x y z) transforms (trunk-part-joint part))
      (set-vec3 (trunk-part-from part) x y z))
    (when (trunk-part-child part)
      (with-joint-point ((x y z) transforms (trunk-part-child part))
        (set-vec3 (trunk-part-to part) x y z)))
    (setf (trunk-part-placed part) nil))
  (enclose-trunk collider))

(defun enclose-trunk (collider)
  "Set COLLIDER's CENTRE and REACH to a sphere holding its trunk parts as placed:
about the mean of their axes' ends, out to the farthest end plus its part's radius."
  (let ((parts (collider-trunk collider))
        (centre (collider-centre collider))
        (count 0) (x 0d0) (y 0d0) (z 0d0) (reach 0d0))
    (declare (type fixnum count) (type double-float x y z reach))
    (macrolet ((do-ends ((end part) &body body)
                 `(dolist (,part parts)
                    (let ((,end (trunk-part-from ,part))) ,@body)
                    (when (trunk-part-child ,part)
                      (let ((,end (trunk-part-to ,part))) ,@body)))))
      (do-ends (end part)
        (incf count) (incf x (vec3-x end)) (incf y (vec3-y end)) (incf z (vec3-z end)))
      (when (plusp count)
        (set-vec3 centre (/ x count) (/ y count) (/ z count))
        (do-ends (end part)
          (setf reach (max reach (+ (vdistance centre end) (trunk-part-radius part)))))))
    (setf (collider-reach collider) (and (plusp count) reach))))

(defun place-trunk-geom (part)
  "Put PART's geom where PLACE-TRUNK last put its axis (a capsule's length is
its bone's, so a stretched spine stays covered), once per placing."
  (unless (trunk-part-placed part)
    (let ((from (trunk-part-from part)) (to (trunk-part-to part)) (geom (trunk-part-geom part)))
      (if (null (trunk-part-child part))
          (set-ode-geom-position geom (vec3-x from) (vec3-y from) (vec3-z from))
          (let* ((dx (- (vec3-x to) (vec3-x from))) (dy (- (vec3-y to) (vec3-y from))) (dz (- (vec3-z to) (vec3-z from)))
                 (length (max 1d-4 (sqrt (+ (* dx dx) (* dy dy) (* dz dz))))))
            (declare (type double-float dx dy dz length))
            (set-ode-capsule-size geom (trunk-part-radius part) length)
            (set-ode-geom-position geom (* 0.5d0 (+ (vec3-x from) (vec3-x to))) (* 0.5d0 (+ (vec3-y from) (vec3-y to)))
                                   (* 0.5d0 (+ (vec3-z from) (vec3-z to))))
            ;; The rotation turning +z onto the bone's direction (the capsule's axis).
            (let ((ux (/ dx length)) (uy (/ dy length)) (uz (/ dz length)))
              (if (< (+ 1d0 uz) 1d-9)
                  (set-ode-geom-rotation geom 0 1 0 0)
                  (set-ode-geom-rotation geom (+ 1d0 uz) (- uy) ux 0))))))
    (setf (trunk-part-placed part) t)))

(declaim (inline axis-distance))
(defun axis-distance (part x y z)
  "How far the point (X Y Z) is from PART's axis (the segment it was last placed along, or its centre)."
  (declare (type double-float x y z))
  (let* ((a (trunk-part-from part))
         (ax (vec3-x a)) (ay (vec3-y a)) (az (vec3-z a))
         (px (- x ax)) (py (- y ay)) (pz (- z az)))
    (declare (type double-float ax ay az px py pz))
    (if (null (trunk-part-child part))
        (sqrt (+ (* px px) (* py py) (* pz pz)))
        (let* ((b (trunk-part-to part))
               (bx (- (vec3-x b) ax)) (by (- (vec3-y b) ay)) (bz (- (vec3-z b) az))
               (u (max 0d0 (min 1d0 (/ (+ (* px bx) (* py by) (* pz bz))
                                       (max 1d-12 (+ (* bx bx) (* by by) (* bz bz)))))))
               (qx (- px (* u bx))) (qy (- py (* u by))) (qz (- pz (* u bz))))
          (declare (type double-float bx by bz u qx qy qz))
          (sqrt (+ (* qx qx) (* qy qy) (* qz qz)))))))
