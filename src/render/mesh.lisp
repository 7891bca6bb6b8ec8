;;;; mesh.lisp -- triangle meshes as flat float vectors, and the primitives the
;;;; bodies are built from: spheres, ellipsoids, tapered capsules, discs, boxes.
;;;; Pure geometry, no GL: a renderer copies the vectors into its buffers.

(in-package #:player.render)

;;; A MESH holds its vertices in three flat vectors: POSITIONS and NORMALS,
;;; three single-floats per vertex, and INDICES, three per triangle, wound
;;; counter-clockwise seen from outside (OpenGL's default front face).
;;; COLOURS, three per vertex, is optional.  Everything solid is closed: each
;;; edge of a sphere, ellipsoid, capsule or box is shared by exactly two
;;; triangles, so nothing behind it shows through a crack.
;;;
;;; The round shapes are all lathes: a PROFILE of (AXIAL RADIAL NORMAL-AXIAL
;;; NORMAL-RADIAL) points swept about an axis.  An end point with RADIAL 0 is a
;;; pole (one vertex, a fan of triangles); any other end is an open rim (discs).

(deftype float-vector () "Flat vertex data." '(simple-array single-float (*)))
(deftype index-vector () "Flat triangle indices." '(simple-array (unsigned-byte 32) (*)))

(defconstant +vertex-floats+ 9
  "Floats per vertex in an interleaved buffer: position (3), normal (3), colour (3).")

(defstruct (mesh (:constructor %make-mesh (positions normals indices &optional colours)))
  "A triangle mesh: POSITIONS, NORMALS (and optional COLOURS) three floats per
vertex, INDICES three per triangle."
  (positions nil :type float-vector)
  (normals nil :type float-vector)
  (indices nil :type index-vector)
  (colours nil :type (or null float-vector)))

(defun mesh-vertex-count (mesh)
  "The number of vertices of MESH."
  (floor (length (mesh-positions mesh)) 3))

(defun mesh-triangle-count (mesh)
  "The number of triangles of MESH."
  (floor (length (mesh-indices mesh)) 3))

(defun float-vector (contents)
  "A FLOAT-VECTOR of the reals in the sequence CONTENTS."
  (map 'float-vector (lambda (x) (float x 1f0)) contents))

;;;# Building

;;; Generators push doubles into adjustable vectors, then freeze them; the
;;; meshes are built once per body, so clarity wins over speed here.

(defstruct (mesh-builder (:constructor make-mesh-builder ()))
  "Vertices and triangles collected while a mesh is generated."
  (positions (make-array 96 :adjustable t :fill-pointer 0))
  (normals (make-array 96 :adjustable t :fill-pointer 0))
  (indices (make-array 96 :adjustable t :fill-pointer 0)))

(defun add-vertex (builder point normal)
  "Add a vertex at the vec3 POINT with the vec3 NORMAL (normalized here) to
BUILDER; return its index."
  (let ((n (vnormalize normal)))
    (prog1 (floor (length (mesh-builder-positions builder)) 3)
      (dolist (x (list (vec3-x point) (vec3-y point) (vec3-z point)))
        (vector-push-extend x (mesh-builder-positions builder)))
      (dolist (x (list (vec3-x n) (vec3-y n) (vec3-z n)))
        (vector-push-extend x (mesh-builder-normals builder))))))

(defun add-triangle (builder a b c)
  "Add the triangle of vertex indices A B C (counter-clockwise from outside) to BUILDER."
  (dolist (i (list a b c))
    (vector-push-extend i (mesh-builder-indices builder))))

(defun builder-mesh (builder)
  "The MESH BUILDER has collected."
  (%make-mesh (float-vector (mesh-builder-positions builder))
              (float-vector (mesh-builder-normals builder))
              (coerce (mesh-builder-indices builder) 'index-vector)))

;;;# Lathes

(defun axis-basis (axis)
  "Unit vectors U (along AXIS), E1 and E2 with E1 x E2 = U, as three values."
  (let* ((u (vnormalize axis))
         (helper (if (< (abs (vec3-x u)) 0.9d0) (vec3 1d0 0d0 0d0) (vec3 0d0 1d0 0d0)))
         (e1 (vnormalize (vcross helper u))))
    (values u e1 (vcross u e1))))

(defun lathe-mesh (profile slices &key (origin (vec3)) (axis (vec3 0d0 0d0 1d0)))
  "Sweep PROFILE, a list of (AXIAL RADIAL NORMAL-AXIAL NORMAL-RADIAL), about AXIS
through ORIGIN in SLICES steps.  End points with RADIAL 0 become poles.  The
solid lies to the left of the profile's direction (the normals of the faces
point right of it), so a profile running from the -AXIS end to the +AXIS end
gives outward normals.  Triangles: 2 SLICES (rings - 1) + SLICES per pole."
  (multiple-value-bind (u e1 e2) (axis-basis axis)
    (let ((builder (make-mesh-builder))
          (previous nil))
      (flet ((direction (axial radial angle)
               (v+ (v* u (float axial 1d0))
                   (v+ (v* e1 (* (float radial 1d0) (cos angle)))
                       (v* e2 (* (float radial 1d0) (sin angle)))))))
        (loop for (axial radial n-axial n-radial) in profile
              for ring = (if (zerop radial)
                             (make-list slices :initial-element
                                        (add-vertex builder (v+ origin (direction axial 0 0))
                                                    (direction n-axial 0 0)))
                             (loop for j below slices
                                   for angle = (/ (* 2 pi j) slices)
                                   collect (add-vertex builder
                                                       (v+ origin (direction axial radial angle))
                                                       (direction n-axial n-radial angle))))
              do (when previous (lathe-band builder previous ring))
                 (setf previous ring))
        (builder-mesh builder)))))

(defun lathe-band (builder lower upper)
  "Join the rings LOWER and UPPER (vertex lists, one per slice) with triangles,
skipping the degenerate ones at a pole."
  (let ((n (length lower)))
    (dotimes (j n)
      (let ((a (nth j lower)) (b (nth (mod (1+ j) n) lower))
            (c (nth (mod (1+ j) n) upper)) (d (nth j upper)))
        (unless (= a b) (add-triangle builder a b c))
        (unless (= c d) (add-triangle builder a c d))))))

;;;# Round primitives

(defun sphere-profile (radius stacks)
  "The profile of a sphere of RADIUS about the origin: two poles, STACKS - 1 rings."
  (loop for k from 0 to stacks
        for theta = (/ (* pi k) stacks)
        collect (list (* radius (- (cos theta))) (if (< 0 k stacks) (* radius (sin theta)) 0)
                      (- (cos theta)) (sin theta))))

(defun make-sphere-mesh (radius &key (center (vec3)) (slices 16) (stacks 8))
  "A closed sphere of RADIUS around the vec3 CENTER: SLICES around, STACKS from
pole to pole; 2 SLICES (STACKS - 1) triangles."
  (lathe-mesh (sphere-profile radius stacks) slices :origin center))

(defun make-ellipsoid-mesh (radii &key (center (vec3)) (axes nil) (slices 16) (stacks 8))
  "A closed ellipsoid around CENTER with the three RADII (a list) along AXES, a
list of three orthonormal vec3s (default x, y, z); as many triangles as the
sphere of SLICES and STACKS."
  (destructuring-bind (a1 a2 a3) (or axes (list (vec3 1d0 0d0 0d0) (vec3 0d0 1d0 0d0)
                                                (vec3 0d0 0d0 1d0)))
    (destructuring-bind (r1 r2 r3) (mapcar (lambda (r) (float r 1d0)) radii)
      (affine-mesh (make-sphere-mesh 1d0 :slices slices :stacks stacks)
                   (columns-matrix (v* a1 r1) (v* a2 r2) (v* a3 r3))
                   center))))

(defun capsule-profile (length ra rb stacks)
  "The profile of a tapered capsule from the origin (sphere RA) to AXIAL LENGTH
(sphere RB): each cap STACKS rings, joined by the cone tangent to both spheres."
  (let* ((phi (asin (/ (- ra rb) length)))
         (tangent (+ (/ pi 2) phi)))
    (flet ((on-sphere (theta radius base)
             (list (- base (* radius (cos theta))) (* radius (sin theta))
                   (- (cos theta)) (sin theta))))
      (append (list (list (- ra) 0 -1 0))
              (loop for k from 1 to stacks
                    collect (on-sphere (* tangent (/ k stacks)) ra 0))
              (loop for k from 0 below stacks
                    collect (on-sphere (+ tangent (* (- pi tangent) (/ k stacks))) rb length))
              (list (list (+ length rb) 0 1 0))))))

(defun make-capsule-mesh (a b ra rb &key (slices 12) (stacks 3))
  "A closed tapered capsule (a rounded cone): the sphere of radius RA at the
vec3 A, the sphere of RB at B, and the cone tangent to both.  Each cap has
STACKS rings; 4 SLICES STACKS triangles.  When one sphere holds the other it
is just the larger sphere (with as many triangles)."
  (let ((length (vdistance a b))
        (ra (float ra 1d0)) (rb (float rb 1d0)))
    (if (<= length (+ (abs (- ra rb)) 1d-9))
        (make-sphere-mesh (max ra rb) :center (if (>= ra rb) a b)
                                      :slices slices :stacks (1+ (* 2 stacks)))
        (lathe-mesh (capsule-profile length ra rb stacks) slices
                    :origin a :axis (v- b a)))))

(defun make-disc-mesh (radius &key inner-radius (center (vec3)) (normal (vec3 0d0 0d0 1d0))
                                   (slices 16) (rings 1) sphere-radius)
  "A disc of RADIUS around CENTER facing NORMAL (one-sided), or with
INNER-RADIUS an annulus.  With SPHERE-RADIUS it is bent onto the sphere of that
radius whose front point is CENTER (an iris on an eyeball).  RINGS bands;
triangles: SLICES (2 RINGS - 1) for a disc, 2 SLICES RINGS for an annulus."
  (let* ((inner (float (or inner-radius 0) 1d0))
         (profile
           (loop for k from 0 to rings
                 for rho = (+ radius (* (- inner radius) (/ k rings)))
                 for height = (if sphere-radius
                                  (- (sqrt (- (expt sphere-radius 2) (* rho rho))) sphere-radius)
                                  0)
                 collect (if sphere-radius
                             (list height rho (+ sphere-radius height) rho)
                             (list 0 rho 1 0)))))
    (lathe-mesh profile slices :origin center :axis normal)))

(defun make-shell-mesh (inner-radius outer-radius angle &key (center (vec3))
                                                          (axis (vec3 0d0 1d0 0d0))
                                                          (slices 16) (stacks 6))
  "A closed spherical shell between INNER-RADIUS and OUTER-RADIUS around CENTER,
the cap within ANGLE radians of AXIS (an eyelid).  STACKS rings per surface;
4 SLICES STACKS triangles."
  (flet ((ring (radius k sign)
           (let ((beta (* angle (/ k stacks))))
             (list (* radius (cos beta)) (* radius (sin beta))
                   (* sign (cos beta)) (* sign (sin beta))))))
    (lathe-mesh (append (list (list inner-radius 0 -1 0))
                        ;; Down the inside to the rim, then up the outside.
                        (loop for k from 1 to stacks collect (ring inner-radius k -1))
                        (loop for k from stacks downto 1 collect (ring outer-radius k 1))
                        (list (list outer-radius 0 1 0)))
                slices :origin center :axis axis)))

;;;# Flat primitives

(defun make-box-mesh (size &key (center (vec3)))
  "A closed box of SIZE (a list of three edge lengths along x, y, z) around
CENTER, with flat faces: 24 vertices, 12 triangles."
  (let ((builder (make-mesh-builder))
        (half (mapcar (lambda (s) (/ (float s 1d0) 2)) size))
        (units (list (vec3 1d0 0d0 0d0) (vec3 0d0 1d0 0d0) (vec3 0d0 0d0 1d0))))
    (dotimes (i 3 (builder-mesh builder))
      (dolist (sign '(1d0 -1d0))
        (let* ((j (mod (+ i 1) 3)) (k (mod (+ i 2) 3))
               (n (v* (nth i units) sign))
               (face (v+ center (v* n (nth i half))))
               (t1 (v* (nth j units) (nth j half)))
               (t2 (v* (nth k units) (* sign (nth k half))))
               (corners (loop for (s1 s2) in '((-1 -1) (1 -1) (1 1) (-1 1))
                              collect (add-vertex builder
                                                  (v+ face (v+ (v* t1 (float s1 1d0))
                                                               (v* t2 (float s2 1d0))))
                                                  n))))
          (add-triangle builder (first corners) (second corners) (third corners))
          (add-triangle builder (first corners) (third corners) (fourth corners)))))))

(defun make-quad-mesh (width depth &key (center (vec3)))
  "A flat WIDTH (x) by DEPTH (z) rectangle around CENTER facing +y: 2 triangles."
  (let ((builder (make-mesh-builder))
        (up (vec3 0d0 1d0 0d0)))
    (let ((corners (loop for (sz sx) in '((-1 -1) (1 -1) (1 1) (-1 1))
                         collect (add-vertex builder
                                             (v+ center (vec3 (* sx width 0.5d0) 0d0
                                                              (* sz depth 0.5d0)))
                                             up))))
      (add-triangle builder (first corners) (second corners) (third corners))
      (add-triangle builder (first corners) (third corners) (fourth corners))
      (builder-mesh builder))))

;;;# Moving, merging, painting

(defun columns-matrix (c1 c2 c3)
  "The 3x3 matrix (a list of rows) whose columns are the vec3s C1, C2, C3."
  (flet ((row (f) (list (funcall f c1) (funcall f c2) (funcall f c3))))
    (list (row #'vec3-x) (row #'vec3-y) (row #'vec3-z))))

(defun cofactor-rows (m)
  "The cofactor matrix of the 3x3 row list M: det(M) times its inverse transpose,
which carries normals under M when the determinant is positive."
  (flet ((at (i j) (nth (mod j 3) (nth (mod i 3) m))))
    (loop for i below 3
          collect (loop for j below 3
                        collect (- (* (at (+ i 1) (+ j 1)) (at (+ i 2) (+ j 2)))
                                   (* (at (+ i 1) (+ j 2)) (at (+ i 2) (+ j 1))))))))

(defun determinant (rows)
  "The determinant of the 3x3 matrix ROWS (a list of rows)."
  (reduce #'+ (mapcar #'* (first rows) (first (cofactor-rows rows)))))

(defun affine-mesh (mesh rows &optional (translation (vec3)))
  "A new mesh: MESH's positions p moved to ROWS p + TRANSLATION (ROWS an
invertible 3x3 matrix as a list of rows), normals carried along; a mirroring
ROWS also turns the triangles over, so they still face outward."
  (let ((normal-rows (cofactor-rows rows))
        (flip (minusp (determinant rows)))
        (positions (copy-seq (mesh-positions mesh)))
        (normals (copy-seq (mesh-normals mesh))))
    (flet ((apply-rows (m v i offset)
             (let ((x (aref v i)) (y (aref v (+ i 1))) (z (aref v (+ i 2))))
               (loop for row in m
                     for k from 0
                     do (setf (aref v (+ i k))
                              (float (+ (nth k offset) (* (first row) x) (* (second row) y)
                                        (* (third row) z))
                                     1f0))))))
      (loop for i from 0 below (length positions) by 3
            do (apply-rows rows positions i (list (vec3-x translation) (vec3-y translation)
                                                  (vec3-z translation)))
               (apply-rows normal-rows normals i '(0 0 0))
               ;; The cofactors carry normals up to the determinant's sign.
               (when flip
                 (dotimes (k 3) (setf (aref normals (+ i k)) (- (aref normals (+ i k))))))
               (let ((n (sqrt (+ (expt (aref normals i) 2) (expt (aref normals (+ i 1)) 2)
                                 (expt (aref normals (+ i 2)) 2)))))
                 (dotimes (k 3) (setf (aref normals (+ i k)) (/ (aref normals (+ i k)) n))))))
    (%make-mesh positions normals
                (if flip (reverse (mesh-indices mesh)) (mesh-indices mesh))
                (mesh-colours mesh))))

(defun translate-mesh (mesh offset)
  "A new mesh: MESH moved by the vec3 OFFSET."
  (affine-mesh mesh '((1 0 0) (0 1 0) (0 0 1)) offset))

(defun scale-mesh (mesh sx sy sz &optional (center (vec3)))
  "A new mesh: MESH scaled by positive SX, SY, SZ about the vec3 CENTER (a
flattened capsule for a brow)."
  (affine-mesh (translate-mesh mesh (vnegate center))
               (list (list sx 0 0) (list 0 sy 0) (list 0 0 sz)) center))

(defun colour-list (colour)
  "COLOUR (a list or vec3 of red, green, blue in [0, 1]) as a list of single-floats."
  (mapcar (lambda (c) (float c 1f0))
          (if (vec3-p colour) (list (vec3-x colour) (vec3-y colour) (vec3-z colour)) colour)))

(defun paint-mesh (mesh colour)
  "A new mesh sharing MESH's vertices, every vertex coloured COLOUR."
  (let ((rgb (colour-list colour))
        (colours (make-array (length (mesh-positions mesh)) :element-type 'single-float)))
    (loop for i from 0 below (length colours) by 3
          do (setf (subseq colours i (+ i 3)) rgb))
    (%make-mesh (mesh-positions mesh) (mesh-normals mesh) (mesh-indices mesh) colours)))

(defun merge-meshes (meshes)
  "One mesh holding all of MESHES (a list), indices renumbered; it has colours
when every one of MESHES has."
  (flet ((join (key) (apply #'concatenate 'float-vector (mapcar key meshes))))
    (let ((indices (make-array (reduce #'+ meshes :key (lambda (m) (length (mesh-indices m))))
                               :element-type '(unsigned-byte 32)))
          (at 0) (base 0))
      (dolist (mesh meshes)
        (loop for i across (mesh-indices mesh)
              do (setf (aref indices at) (+ i base)) (incf at))
        (incf base (mesh-vertex-count mesh)))
      (%make-mesh (join #'mesh-positions) (join #'mesh-normals) indices
                  (and (every #'mesh-colours meshes) (join #'mesh-colours))))))

(defun mesh-bounds (thing)
  "The corners of the box around THING's vertices, as two vec3s (values MIN MAX):
THING is a MESH or an interleaved FLOAT-VECTOR of +VERTEX-FLOATS+ per vertex
(as POSE-BODY-MESH fills).  An empty THING gives zero vectors."
  (multiple-value-bind (data stride)
      (etypecase thing
        (mesh (values (mesh-positions thing) 3))
        (float-vector (values thing +vertex-floats+)))
    (if (zerop (length data))
        (values (vec3) (vec3))
        (let ((low (list (aref data 0) (aref data 1) (aref data 2)))
              (high (list (aref data 0) (aref data 1) (aref data 2))))
          (loop for i from 0 below (length data) by stride
                do (dotimes (k 3)
                     (setf (nth k low) (min (nth k low) (aref data (+ i k)))
                           (nth k high) (max (nth k high) (aref data (+ i k))))))
          (values (apply #'make-vec3 low) (apply #'make-vec3 high))))))
