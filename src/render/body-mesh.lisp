;;;; body-mesh.lisp -- how a skeleton looks: rigid mesh parts hung on its joints,
;;;; built once from the skeleton and an appearance table, then posed each frame
;;;; into one interleaved vertex buffer without allocating.

(in-package #:player.render)

;;; Every part is rigid and hangs from one joint, its vertices in that joint's
;;; rest frame (the rest pose's world axes, origin at the joint's centre), so
;;; the joint's world transform from POSE-WORLD-TRANSFORMS poses it.  Limbs are
;;; tapered capsules from a joint to each child, the joint's radius at the
;;; start and the child's at the end: the parent's end sphere and the child's
;;; start sphere are one sphere about the child's centre, which no rotation
;;; about that centre moves, so no pose opens a gap.  The face is built so its
;;; DOFs show: eyeballs whose iris and pupil (on the eye's +z) turn with the eye,
;;; upper lids that are shells around the eyeball turning with 'close', brows
;;; reaching in front of their pivot so that tilting raises them.

;;;# Parts

(defstruct (mesh-part (:constructor make-mesh-part (joint kind mesh colour &key child capsule)))
  "A rigid piece of a body: MESH in the rest frame of the joint with index
JOINT, painted COLOUR (R G B).  KIND says what it is (:bone :leaf :head :eyeball
:iris :pupil :lid :brow or a shape kind).  A :bone runs to the joint with index
CHILD; CAPSULE is its (A B RA RB), both ends in JOINT's frame."
  (joint 0 :type fixnum) (kind :bone :type keyword) (mesh nil :type mesh)
  (colour '(0.7 0.7 0.7) :type list) (child nil) (capsule nil))

(defun round-resolution (radius)
  "Slices and stacks per cap (two values) for a round part of RADIUS metres:
finer for big parts, where facets show, coarse for fingers and feathers."
  (cond ((>= radius 0.06) (values 16 4)) ((>= radius 0.025) (values 12 3)) (t (values 8 2))))

(defun ellipsoid-resolution (radii)
  "Slices and stacks (two values) for an ellipsoid with RADII: a chest needs
more facets than a palm."
  (let ((size (reduce #'max radii)))
    (cond ((>= size 0.1) (values 24 12)) ((>= size 0.05) (values 16 8)) (t (values 12 6)))))

(defun capsule-between (a b ra rb)
  "A tapered capsule mesh from the vec3 A (radius RA) to B (radius RB)."
  (multiple-value-bind (slices stacks) (round-resolution (max ra rb))
    (make-capsule-mesh a b ra rb :slices slices :stacks stacks)))

(defun centre-difference (joint from)
  "JOINT's rest centre minus FROM's, as a vec3: where JOINT is in FROM's frame."
  (apply #'make-vec3 (map 'list #'- (body-joint-center joint) (body-joint-center from))))

(defun drawn-apart-p (skeleton appearance joint)
  "Is JOINT drawn by face parts instead of a limb capsule from its parent?  Eyes,
lids and brows always are; a jaw or crest when the appearance gives it a shape."
  (let ((role (find-if (lambda (role) (eq (skeleton-role skeleton role) joint)) *face-roles*)))
    (and role
         (or (not (member role '(:jaw :crest)))
             (find (body-joint-name joint) (getf appearance :shapes) :key #'second
                                                                     :test #'string-equal)))))

(defun bone-parts (skeleton appearance colours)
  "A capsule from every joint to each of its children, but those DRAWN-APART-P."
  (loop for joint across (skeleton-joints skeleton)
        for index = (body-joint-index joint)
        nconc (loop for child in (body-joint-children joint)
                    for a = (vec3)
                    for b = (centre-difference child joint)
                    for ra = (drawn-radius joint appearance)
                    for rb = (drawn-radius child appearance)
                    unless (drawn-apart-p skeleton appearance child)
                      collect (make-mesh-part index :bone (capsule-between a b ra rb)
                                              (svref colours index)
                                              :child (body-joint-index child)
                                              :capsule (list a b ra rb)))))

(defun leaf-parts (skeleton appearance colours)
  "The :leaves capsules: fingers and toes beyond the last joint."
  (loop for (name length direction) in (getf appearance :leaves)
        for joint = (find-joint skeleton name t)
        for r = (drawn-radius joint appearance)
        for way = (vnormalize (if direction
                                  (apply #'make-vec3 direction)
                                  (centre-difference joint (body-joint-parent joint))))
        collect (make-mesh-part (body-joint-index joint) :leaf
                                (capsule-between (vec3) (v* way (float length 1d0)) r (* 0.8d0 r))
                                (svref colours (body-joint-index joint)))))

(defun head-part (skeleton appearance)
  "The head ellipsoid on the :head joint, or NIL without one."
  (let ((head (skeleton-role skeleton :head)))
    (when head
      (destructuring-bind (&key (offset '(0 0 0)) radii colour) (getf appearance :head)
        (let* ((r (body-joint-radius head))
               (center (apply #'make-vec3 offset))
               (rx (float (or (first radii) r) 1d0))
               (ry (float (or (second radii) (* 1.1 r)) 1d0))
               (rz (or (third radii) (head-depth skeleton head center rx ry) rx)))
          (make-mesh-part (body-joint-index head) :head
                          (make-ellipsoid-mesh (list rx ry rz) :center center :slices 24 :stacks 14)
                          (appearance-colour appearance (or colour '(0.8 0.8 0.8)))))))))

(defun head-depth (skeleton head center rx ry)
  "The front-to-back radius of a head ellipsoid at CENTER (in HEAD's frame) with
radii RX, RY that puts the eye centres on its surface, sinking the eyeballs
halfway; NIL when there are no eyes or they lie outside its outline."
  (let ((depths (loop for role in '(:left-eye :right-eye)
                      for eye = (skeleton-role skeleton role)
                      when eye
                        collect (let* ((e (v- (centre-difference eye head) center))
                                       (left (- 1 (expt (/ (vec3-x e) rx) 2)
                                                (expt (/ (vec3-y e) ry) 2))))
                                  (and (plusp left) (plusp (vec3-z e))
                                       (/ (vec3-z e) (sqrt left)))))))
    (and depths (every #'identity depths) (reduce #'max depths))))

(defun eye-radius (eye appearance)
  "The eyeball radius of EYE: the :eyes :radius, else the joint's."
  (float (getf (getf appearance :eyes) :radius (body-joint-radius eye)) 1d0))

(defun eye-parts (skeleton appearance)
  "Eyeball, iris and pupil on each eye joint and a lid on each upper-lid joint."
  (loop for (eye-role lid-role) in '((:left-eye :left-upper-lid) (:right-eye :right-upper-lid))
        for eye = (skeleton-role skeleton eye-role)
        for lid = (skeleton-role skeleton lid-role)
        when eye
          nconc (eyeball-parts eye appearance)
        when (and eye lid)
          collect (lid-part eye lid appearance)))

(defun eyeball-parts (eye appearance)
  "A white sphere on EYE, with an iris annulus and a pupil disc bent onto
spheres just outside it on its +z front, so they turn with the eye's DOFs."
  (let* ((r (eye-radius eye appearance))
         (spec (getf appearance :eyes))
         (index (body-joint-index eye)))
    (flet ((colour (key default) (appearance-colour appearance (getf spec key default)))
           (front (scale) (vec3 0d0 0d0 (* scale r))))
      (list (make-mesh-part index :eyeball (make-sphere-mesh r :slices 16 :stacks 8)
                            (colour :white '(0.97 0.97 0.95)))
            (make-mesh-part index :iris (make-disc-mesh (* 0.5d0 r) :inner-radius (* 0.24d0 r)
                                                        :rings 2 :center (front 1.012d0)
                                                        :sphere-radius (* 1.012d0 r))
                            (colour :iris '(0.35 0.22 0.1)))
            (make-mesh-part index :pupil (make-disc-mesh (* 0.26d0 r) :center (front 1.02d0)
                                                         :sphere-radius (* 1.02d0 r))
                            (colour :pupil '(0.03 0.03 0.03)))))))

(defun lid-part (eye lid appearance)
  "A shell just outside EYE's eyeball on the LID joint.  Its cap axis is the
eye's front turned :lid-tilt degrees back against the lid's closing rotation,
so at rest it covers the top of the eye, and closing by more than tilt minus
:lid-angle degrees brings it over the front."
  (let* ((r (eye-radius eye appearance))
         (spec (getf appearance :eyes))
         (dof (or (body-joint-dof lid 'close) (first (body-joint-dofs lid))))
         (axis (if dof (apply #'make-vec3 (dof-axis-vector dof)) (vec3 1d0 0d0 0d0)))
         (tilt (float (getf spec :lid-tilt 110) 1d0))
         (cap-axis (qrotate (quat-from-axis-angle axis (- (* tilt (/ pi 180))))
                            (vec3 0d0 0d0 1d0))))
    (make-mesh-part (body-joint-index lid) :lid
                    (make-shell-mesh (* 1.06d0 r) (* 1.15d0 r)
                                     (* (getf spec :lid-angle 80) (/ pi 180))
                                     :center (centre-difference eye lid) :axis cap-axis
                                     :slices 16 :stacks 5)
                    (appearance-colour appearance (getf spec :lid '(0.8 0.8 0.8))))))

(defun brow-parts (skeleton appearance)
  "A flat ellipsoid on each brow joint, reaching in front of it: a brow pivots
about its joint, so only what lies in front of the pivot rises with 'raise'."
  (destructuring-bind (&key (offset '(0 0 0.004)) (radii '(0.016 0.0035 0.014))
                         (colour '(0.3 0.2 0.12)))
      (getf appearance :brows)
    (loop for role in '(:left-brow :right-brow)
          for brow = (skeleton-role skeleton role)
          when brow
            collect (make-mesh-part (body-joint-index brow) :brow
                                    (make-ellipsoid-mesh radii :center (apply #'make-vec3 offset)
                                                               :slices 12 :stacks 6)
                                    (appearance-colour appearance colour)))))

;;;# Decorative shapes

(defun unit-across (vector axis)
  "The unit part of the vec3 VECTOR perpendicular to the unit vec3 AXIS."
  (vnormalize (v- vector (v* axis (vdot vector axis)))))

(defun shape-mesh (skeleton kind joint options)
  "The mesh, in JOINT's frame, of the shape (KIND JOINT . OPTIONS); see *BODY-APPEARANCES*."
  (flet ((option-vec3 (key &optional (default '(0 0 0)))
           (apply #'make-vec3 (getf options key default)))
         (option (key &optional default) (float (getf options key default) 1d0)))
    (ecase kind
      (:ellipsoid
       (multiple-value-bind (slices stacks) (ellipsoid-resolution (getf options :radii))
         (make-ellipsoid-mesh (getf options :radii) :center (option-vec3 :offset)
                                                    :slices slices :stacks stacks)))
      (:segment
       (let* ((to (centre-difference (find-joint skeleton (getf options :child) t) joint))
              (u (vnormalize to))
              (n (unit-across (option-vec3 :normal '(1 0 0)) u)))
         (make-ellipsoid-mesh (list (* 0.55d0 (vnorm to)) (/ (option :width 0.04) 2)
                                    (/ (option :thickness 0.01) 2))
                              :center (v* to 0.5d0) :axes (list u (vcross n u) n)
                              :slices 12 :stacks 6)))
      (:chain
       (merge-meshes (loop for ((x1 y1 z1 r1) (x2 y2 z2 r2)) on (getf options :points)
                           while x2
                           collect (capsule-between (make-vec3 x1 y1 z1) (make-vec3 x2 y2 z2)
                                                    (float r1 1d0) (float r2 1d0)))))
      (:fan (fan-mesh (option-vec3 :offset) (vnormalize (option-vec3 :direction '(0 -1 0)))
                      (option-vec3 :normal '(1 0 0)) (option :length 0.08) (option :width 0.015)
                      (option :thickness 0.003) (getf options :count 3) (option :spread 30))))))

(defun fan-mesh (base direction normal length width thickness count spread)
  "COUNT flat feathers (ellipsoids LENGTH by WIDTH by THICKNESS) from BASE,
fanned SPREAD degrees about DIRECTION in the plane across NORMAL."
  (let ((n (unit-across normal direction)))
    (merge-meshes
     (loop for i below count
           for degrees = (if (= count 1) 0d0 (* spread (- (/ i (1- count)) 1/2)))
           for way = (qrotate (quat-from-axis-angle n (* degrees (/ pi 180))) direction)
           collect (make-ellipsoid-mesh (list (/ length 2) (/ width 2) (/ thickness 2))
                                        :center (v+ base (v* way (/ length 2)))
                                        :axes (list way (vcross n way) n) :slices 8 :stacks 4)))))

(defun shape-parts (skeleton appearance colours)
  "The parts of the appearance's :shapes, each coloured by its :colour or its joint's."
  (loop for (kind name . options) in (getf appearance :shapes)
        for joint = (find-joint skeleton name t)
        collect (make-mesh-part (body-joint-index joint) kind
                                (shape-mesh skeleton kind joint options)
                                (if (getf options :colour)
                                    (appearance-colour appearance (getf options :colour))
                                    (svref colours (body-joint-index joint))))))

;;;# Body meshes

(deftype index-array () "Per-part vertex ranges and joints." '(simple-array fixnum (*)))

(defstruct (body-mesh (:constructor %make-body-mesh))
  "A skeleton's parts merged for drawing: rest POSITIONS and NORMALS (joint-local),
COLOURS and INDICES as in a MESH, and per part its JOINT and vertex range
[START, END)."
  (skeleton nil) (parts '() :type list)
  (positions nil :type float-vector) (normals nil :type float-vector)
  (colours nil :type float-vector) (indices nil :type index-vector)
  (joints nil :type index-array) (starts nil :type index-array) (ends nil :type index-array))

(defun make-body-mesh (skeleton)
  "The BODY-MESH of SKELETON (a SKELETON or a name for LOAD-SKELETON), looking as
*BODY-APPEARANCES* says.  Signals SKELETON-ERROR when the table names a joint
or colour the skeleton lacks."
  (let* ((skeleton (if (skeleton-p skeleton) skeleton (load-skeleton skeleton)))
         (appearance (skeleton-appearance skeleton))
         (colours (joint-colours skeleton appearance)))
    (parts-body-mesh skeleton
                     (remove nil (append (bone-parts skeleton appearance colours)
                                         (leaf-parts skeleton appearance colours)
                                         (list (head-part skeleton appearance))
                                         (eye-parts skeleton appearance)
                                         (brow-parts skeleton appearance)
                                         (shape-parts skeleton appearance colours))))))

(defun parts-body-mesh (skeleton parts)
  "A BODY-MESH of SKELETON (or NIL for a prop) made of PARTS (a list of MESH-PARTs)."
  (let* ((meshes (mapcar (lambda (part)
                           (let ((mesh (mesh-part-mesh part)) (colour (mesh-part-colour part)))
                             ;; A part without a colour keeps its mesh's own (a prop's).
                             (if (or colour (null (mesh-colours mesh)))
                                 (paint-mesh mesh (or colour '(0.7 0.7 0.7)))
                                 mesh)))
                         parts))
         (merged (merge-meshes meshes))
         (ends (loop for mesh in meshes
                     sum (mesh-vertex-count mesh) into end
                     collect end)))
    (flet ((fixnums (list) (coerce list 'index-array)))
      (%make-body-mesh :skeleton skeleton :parts parts
                       :positions (mesh-positions merged) :normals (mesh-normals merged)
                       :colours (mesh-colours merged) :indices (mesh-indices merged)
                       :joints (fixnums (mapcar #'mesh-part-joint parts))
                       :starts (fixnums (cons 0 (butlast ends))) :ends (fixnums ends)))))

(defun body-mesh-triangle-count (body-mesh)
  "The number of triangles BODY-MESH draws."
  (floor (length (body-mesh-indices body-mesh)) 3))

(defun body-mesh-vertex-count (body-mesh)
  "The number of vertices of BODY-MESH."
  (floor (length (body-mesh-positions body-mesh)) 3))

(defun make-body-mesh-buffer (body-mesh)
  "A fresh interleaved vertex buffer for BODY-MESH, +VERTEX-FLOATS+ per vertex:
colours filled in, positions and normals zero until POSE-BODY-MESH writes them."
  (let ((out (make-array (* +vertex-floats+ (body-mesh-vertex-count body-mesh))
                         :element-type 'single-float :initial-element 0f0))
        (colours (body-mesh-colours body-mesh)))
    (dotimes (v (body-mesh-vertex-count body-mesh) out)
      (replace out colours :start1 (+ (* v +vertex-floats+) 6)
                           :start2 (* v 3) :end2 (* (1+ v) 3)))))

(declaim (ftype (function (mat4 float-vector float-vector float-vector fixnum fixnum) (values))
                pose-vertices))

(defun pose-vertices (m positions normals out start end)
  "Write the vertices START to END of POSITIONS and NORMALS moved by the MAT4 M
(points by R p + t, normals by R) into the interleaved buffer OUT."
  (declare (optimize (speed 3) (safety 1)))
  (macrolet ((entry (i j) `(float (aref m ,i ,j) 1f0)))
    (let ((r00 (entry 0 0)) (r01 (entry 0 1)) (r02 (entry 0 2)) (tx (entry 0 3))
          (r10 (entry 1 0)) (r11 (entry 1 1)) (r12 (entry 1 2)) (ty (entry 1 3))
          (r20 (entry 2 0)) (r21 (entry 2 1)) (r22 (entry 2 2)) (tz (entry 2 3)))
      (loop for v of-type fixnum from start below end
            for i of-type fixnum = (* 3 v)
            for o of-type fixnum = (* +vertex-floats+ v)
            do (let ((x (aref positions i)) (y (aref positions (+ i 1)))
                     (z (aref positions (+ i 2))))
                 (setf (aref out o) (+ (* r00 x) (* r01 y) (* r02 z) tx)
                       (aref out (+ o 1)) (+ (* r10 x) (* r11 y) (* r12 z) ty)
                       (aref out (+ o 2)) (+ (* r20 x) (* r21 y) (* r22 z) tz)))
               (let ((x (aref normals i)) (y (aref normals (+ i 1))) (z (aref normals (+ i 2))))
                 (setf (aref out (+ o 3)) (+ (* r00 x) (* r01 y) (* r02 z))
                       (aref out (+ o 4)) (+ (* r10 x) (* r11 y) (* r12 z))
                       (aref out (+ o 5)) (+ (* r20 x) (* r21 y) (* r22 z)))))))
  (values))

(defun pose-body-mesh (body-mesh transforms &optional (out (make-body-mesh-buffer body-mesh)))
  "Pose BODY-MESH by TRANSFORMS (a simple-vector of joint world MAT4s, as from
POSE-WORLD-TRANSFORMS or BODY-TRANSFORMS): write each vertex's world position
and normal into OUT, an interleaved buffer from MAKE-BODY-MESH-BUFFER (or an
earlier call), whose colours stay as they are.  Returns OUT and the index
vector, ready for a vertex and an element buffer.  Conses nothing when OUT is given."
  (declare (type simple-vector transforms) (type float-vector out))
  (let ((joints (body-mesh-joints body-mesh))
        (starts (body-mesh-starts body-mesh))
        (ends (body-mesh-ends body-mesh))
        (positions (body-mesh-positions body-mesh))
        (normals (body-mesh-normals body-mesh)))
    (dotimes (p (length joints))
      (pose-vertices (svref transforms (aref joints p)) positions normals out
                     (aref starts p) (aref ends p))))
  (values out (body-mesh-indices body-mesh)))
