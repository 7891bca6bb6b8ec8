;;;; bone-shapes.lisp -- a body as collision shapes: its hands as probes (a
;;;; sphere at the hand joint and one at each joint it carries, fingers or a
;;;; wing's primaries) and its trunk as obstacles (a capsule along each bone
;;;; of the spine, from the root up, and a sphere for the head), each as
;;;; thick as its joint's :radius.  They are ODE geoms without bodies, placed
;;;; where the pose puts the joints, and disabled: only queries test them.

(in-package #:player.physics)

(defstruct (probe (:constructor make-probe (joint hand geom radius)))
  "A sphere of GEOM (RADIUS metres) at JOINT of a HAND (:left or :right)."
  joint hand geom (radius 0d0 :type double-float))

(defstruct (trunk-part (:constructor make-trunk-part (body joint child geom radius)))
  "A part of BODY's trunk: a capsule GEOM from JOINT to CHILD, or a sphere at
JOINT when CHILD is NIL; RADIUS metres thick."
  body joint child geom (radius 0d0 :type double-float)
  ;; Where it was last placed: its axis FROM .. TO (TO NIL for a sphere).
  (from (make-vec3 0d0 0d0 0d0)) (to nil))

(defstruct (collider (:constructor make-collider (body probes trunk)))
  "BODY's collision shapes: its hands' PROBES and its TRUNK-PARTs.  SHOWN is
the pose shown last (a copy), where a correction starts from, at SHOWN-TIME."
  body probes trunk (shown nil) (shown-time nil))

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
                                    collect (make-probe joint hand
                                                        (make-ode-geom world (list :sphere (joint-radius joint))
                                                                       :data (cons body joint))
                                                        (joint-radius joint)))))
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

(defun joint-point (transforms joint)
  "Where JOINT is, from the world TRANSFORMS of a pose."
  (transform-translation (svref transforms (body-joint-index joint))))

(defun place-probes (collider transforms)
  "Put COLLIDER's probes where TRANSFORMS (a pose's joint world transforms) put their joints."
  (dolist (probe (collider-probes collider))
    (set-ode-geom-placement (probe-geom probe) (vec3-list (joint-point transforms (probe-joint probe))))))

(defun capsule-rotation (direction)
  "The rotation (w x y z) turning +z onto the unit vector DIRECTION."
  (let ((dx (vec3-x direction)) (dy (vec3-y direction)) (dz (vec3-z direction)))
    (if (< (+ 1 dz) 1d-9)
        (list 0 1 0 0)
        (list (+ 1 dz) (- dy) dx 0))))

(defun place-trunk (collider transforms)
  "Put COLLIDER's trunk parts where TRANSFORMS put their joints (a capsule's
length is its bone's, so a stretched spine stays covered)."
  (dolist (part (collider-trunk collider))
    (let* ((from (joint-point transforms (trunk-part-joint part)))
           (child (trunk-part-child part)))
      (setf (trunk-part-from part) from)
      (if (null child)
          (progn (set-ode-geom-placement (trunk-part-geom part) (vec3-list from))
                 (setf (trunk-part-to part) nil))
          (let* ((to (joint-point transforms child))
                 (length (max 1d-4 (vdistance from to)))
                 (centre (v* (v+ from to) 0.5d0)))
            (set-ode-capsule-size (trunk-part-geom part) (trunk-part-radius part) length)
            (set-ode-geom-placement (trunk-part-geom part) (vec3-list centre)
                                    (capsule-rotation (v* (v- to from) (/ 1 length))))
            (setf (trunk-part-to part) to))))))

(defun axis-distance (part point)
  "How far POINT is from PART's axis (the segment it was last placed along, or its centre)."
  (let ((a (trunk-part-from part)) (b (trunk-part-to part)))
    (if (null b)
        (vdistance point a)
        (let* ((ab (v- b a))
               (u (max 0d0 (min 1d0 (/ (vdot (v- point a) ab) (max 1d-12 (vdot ab ab)))))))
          (vdistance point (v+ a (v* ab u)))))))
