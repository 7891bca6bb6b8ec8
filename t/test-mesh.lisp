;;;; test-mesh.lisp -- the renderer's geometry: closed primitives with outward
;;;; unit normals and the promised triangle counts; body meshes that stay joined,
;;;; show every DOF, close their lids, and pose without allocating; props and
;;;; scene assembly.

(in-package #:player-tests)

(def-suite* mesh :in player-tests)

;;;# Helpers

(defun mesh-point (data i &optional (stride 3) (offset 0))
  "Vertex I of the flat float vector DATA (STRIDE floats per vertex, from OFFSET) as a vec3."
  (let ((o (+ offset (* i stride))))
    (player.body::make-vec3 (aref data o) (aref data (+ o 1)) (aref data (+ o 2)))))

(defun mesh-near-p (a b &optional (tolerance 1d-5))
  "Are the vec3s A and B within TOLERANCE metres?  (Meshes hold single floats.)"
  (< (player.body::vdistance a b) tolerance))

(defun mesh-closed-p (mesh)
  "Is MESH closed and consistently wound: every edge, its ends compared by
position, used once in each direction (so by exactly two triangles)?"
  (let ((edges (make-hash-table :test #'equal))
        (positions (player.render::mesh-positions mesh))
        (indices (player.render::mesh-indices mesh)))
    (flet ((key (i) (map 'list (lambda (x) (round x 1f-6))
                         (subseq positions (* 3 i) (+ 3 (* 3 i))))))
      (loop for tri from 0 below (length indices) by 3
            do (loop for (a b) in '((0 1) (1 2) (2 0))
                     do (incf (gethash (list (key (aref indices (+ tri a))) (key (aref indices (+ tri b))))
                                       edges 0))))
      (loop for (from to) being the hash-keys of edges using (hash-value count)
            always (and (= count 1) (eql 1 (gethash (list to from) edges)))))))

(defun mesh-normals-outward-p (mesh inside)
  "Are MESH's normals unit length, pointing away from the point INSIDE, and do
its triangles wind counter-clockwise seen from where they point?"
  (let ((positions (player.render::mesh-positions mesh))
        (normals (player.render::mesh-normals mesh))
        (indices (player.render::mesh-indices mesh)))
    (and (loop for i below (player.render::mesh-vertex-count mesh)
               for n = (mesh-point normals i)
               always (and (< (abs (- (player.body::vnorm n) 1)) 1d-5)
                           (plusp (player.body::vdot n (player.body::v- (mesh-point positions i) inside)))))
         (loop for tri from 0 below (length indices) by 3
               for (a b c) = (loop for k below 3 collect (aref indices (+ tri k)))
               for face = (player.body::vcross (player.body::v- (mesh-point positions b) (mesh-point positions a))
                                          (player.body::v- (mesh-point positions c) (mesh-point positions a)))
               always (plusp (player.body::vdot face (mesh-point normals a)))))))

(defun mesh-random-pose (skeleton state)
  "A pose of SKELETON with every DOF drawn uniformly within its limits from the random STATE."
  (let ((pose (player::make-pose skeleton)))
    (dotimes (i (length pose) pose)
      (multiple-value-bind (joint dof) (player.body::skeleton-dof skeleton i)
        (declare (ignore joint))
        (let ((range (float (- (player.body::body-dof-max dof) (player.body::body-dof-min dof)) 1d0)))
          (setf (aref pose i) (+ (player.body::body-dof-min dof)
                                 (if (plusp range) (random range state) 0d0))))))))

(defun mesh-posed (body-mesh pose)
  "BODY-MESH posed by POSE of its skeleton: the interleaved buffer and the transforms."
  (let ((transforms (player::pose-world-transforms (player.render::body-mesh-skeleton body-mesh) pose)))
    (values (player.render::pose-body-mesh body-mesh transforms) transforms)))

(defun ray-hits-triangle-p (origin direction a b c)
  "Does the ray from ORIGIN along DIRECTION meet the triangle A B C (Moeller-Trumbore)?"
  (let* ((e1 (player.body::v- b a)) (e2 (player.body::v- c a))
         (p (player.body::vcross direction e2))
         (det (player.body::vdot e1 p)))
    (unless (< (abs det) 1d-14)
      (let* ((s (player.body::v- origin a))
             (u (/ (player.body::vdot s p) det))
             (q (player.body::vcross s e1))
             (v (/ (player.body::vdot direction q) det)))
        (and (<= 0 u 1) (<= 0 v) (<= (+ u v) 1)
             (plusp (/ (player.body::vdot e2 q) det)))))))

(defun ray-hits-mesh-p (origin direction mesh transform)
  "Does the ray from ORIGIN along DIRECTION meet MESH moved by the MAT4 TRANSFORM?"
  (let ((positions (player.render::mesh-positions mesh))
        (indices (player.render::mesh-indices mesh)))
    (flet ((corner (k) (player.body::transform-point transform (mesh-point positions (aref indices k)))))
      (loop for tri from 0 below (length indices) by 3
              thereis (ray-hits-triangle-p origin direction (corner tri) (corner (+ tri 1))
                                           (corner (+ tri 2)))))))

(defparameter *mesh-skeletons* '("humanoid" "parrot")
  "The shipped skeletons every body-mesh test runs on.")

;;;# Primitives

(test primitives-are-closed-with-outward-normals
  (let ((origin (player::vec3)))
    (loop for (what mesh inside)
            in (list (list "sphere" (player.render::make-sphere-mesh 0.5 :slices 12 :stacks 7) origin)
                     (list "ellipsoid" (player.render::make-ellipsoid-mesh
                                        '(0.3 0.1 0.05) :center (player.body::make-vec3 1 2 3)
                                        :axes (list (player.body::make-vec3 0 0 1) (player.body::make-vec3 1 0 0)
                                                    (player.body::make-vec3 0 1 0)))
                           (player.body::make-vec3 1 2 3))
                     (list "tapered capsule" (player.render::make-capsule-mesh
                                              origin (player.body::make-vec3 0.1 0.4 0.2) 0.08 0.03)
                           (player.body::make-vec3 0.05 0.2 0.1))
                     (list "reverse taper" (player.render::make-capsule-mesh
                                            origin (player.body::make-vec3 0 -0.3 0) 0.01 0.06 :slices 9)
                           (player.body::make-vec3 0 -0.15 0))
                     (list "cylinder capsule" (player.render::make-capsule-mesh
                                               origin (player.body::make-vec3 0 0 1) 0.2 0.2) origin)
                     (list "swallowed capsule" (player.render::make-capsule-mesh
                                                origin (player.body::make-vec3 0 0.01 0) 0.1 0.02) origin)
                     (list "box" (player.render::make-box-mesh '(0.2 0.1 0.01)) origin)
                     (list "mirrored capsule" (player.render::scale-mesh (player.render::make-capsule-mesh
                                                                   origin (player.body::make-vec3 1 0 0) 0.2 0.1)
                                                                  -1 1 1)
                           (player.body::make-vec3 -0.5 0 0)))
          do (is (mesh-closed-p mesh) "the ~A is not closed" what)
             (is (mesh-normals-outward-p mesh inside) "the ~A's normals are not outward unit vectors" what))
    ;; The eyelid shell is closed but not convex.
    (is (mesh-closed-p (player.render::make-shell-mesh 1 1.1 1.3)))))

(test primitives-have-the-promised-triangle-counts
  (flet ((count-of (mesh) (player.render::mesh-triangle-count mesh)))
    (loop for (slices stacks) in '((8 2) (12 3) (16 5))
          do (is (= (* 2 slices (1- stacks)) (count-of (player.render::make-sphere-mesh 1 :slices slices :stacks stacks))))
             (is (= (* 2 slices (1- stacks)) (count-of (player.render::make-ellipsoid-mesh '(1 2 3) :slices slices :stacks stacks))))
             (is (= (* 4 slices stacks) (count-of (player.render::make-capsule-mesh (player::vec3) (player.body::make-vec3 0 1 0)
                                                                              0.2 0.1 :slices slices :stacks stacks))))
             (is (= (* 4 slices stacks) (count-of (player.render::make-capsule-mesh (player::vec3) (player.body::make-vec3 0 0.01 0)
                                                                              0.2 0.1 :slices slices :stacks stacks))))
             (is (= (* 4 slices stacks) (count-of (player.render::make-shell-mesh 1 1.1 1 :slices slices :stacks stacks))))
             (is (= (* slices (1- (* 2 stacks))) (count-of (player.render::make-disc-mesh 1 :slices slices :rings stacks))))
             (is (= (* 2 slices stacks) (count-of (player.render::make-disc-mesh 1 :inner-radius 0.5 :slices slices
                                                                            :rings stacks)))))
    (is (= 12 (count-of (player.render::make-box-mesh '(1 1 1)))))
    (is (= 2 (count-of (player.render::make-quad-mesh 1 1))))))

(test discs-face-their-normal-and-hug-their-sphere
  (let* ((n (player.body::vnormalize (player.body::make-vec3 1 1 0)))
         (flat (player.render::make-disc-mesh 0.5 :normal n :slices 10 :rings 2))
         (iris (player.render::make-disc-mesh 0.5 :inner-radius 0.2 :sphere-radius 1 :rings 3
                                           :center (player.body::make-vec3 0 0 1))))
    (is (loop for i below (player.render::mesh-vertex-count flat)
              always (and (< (abs (player.body::vdot (mesh-point (player.render::mesh-positions flat) i) n)) 1d-6)
                          (> (player.body::vdot (mesh-point (player.render::mesh-normals flat) i) n) 0.999))))
    (is (mesh-normals-outward-p iris (player::vec3)))
    (is (loop for i below (player.render::mesh-vertex-count iris)
              always (< (abs (- 1 (player.body::vnorm (mesh-point (player.render::mesh-positions iris) i)))) 1d-6)))))

(test merged-meshes-keep-their-triangles
  (let* ((a (player.render::paint-mesh (player.render::make-sphere-mesh 1) '(1 0 0)))
         (b (player.render::paint-mesh (player.render::make-box-mesh '(1 2 3)) '(0 1 0)))
         (merged (player.render::merge-meshes (list a b))))
    (is (= (+ (player.render::mesh-triangle-count a) (player.render::mesh-triangle-count b))
           (player.render::mesh-triangle-count merged)))
    (is (every (lambda (i) (< i (player.render::mesh-vertex-count merged))) (player.render::mesh-indices merged)))
    (is (mesh-closed-p merged))
    (is (= (length (player.render::mesh-positions merged)) (length (player.render::mesh-colours merged))))
    (multiple-value-bind (low high) (player.render::mesh-bounds b)
      (is (mesh-near-p (player.body::make-vec3 -0.5 -1 -1.5) low))
      (is (mesh-near-p (player.body::make-vec3 0.5 1 1.5) high)))))

;;;# Body meshes

(test body-meshes-hang-on-joints-within-budget
  (dolist (name *mesh-skeletons*)
    (let* ((body-mesh (player.render::make-body-mesh name))
           (skeleton (player.render::body-mesh-skeleton body-mesh))
           (joints (player::skeleton-joints skeleton)))
      (is (< 1000 (player.render::body-mesh-triangle-count body-mesh) 12000)
          "~A has ~D triangles" name (player.render::body-mesh-triangle-count body-mesh))
      (dolist (part (player.render::body-mesh-parts body-mesh))
        (is (< -1 (player.render::mesh-part-joint part) (length joints)))
        (when (eq (player.render::mesh-part-kind part) :bone)
          (is (eq (svref joints (player.render::mesh-part-joint part))
                  (player.body::body-joint-parent (svref joints (player.render::mesh-part-child part)))))))
      (dolist (kind '(:head :eyeball :iris :pupil :lid))
        (is (= (if (eq kind :head) 1 2)
               (count kind (player.render::body-mesh-parts body-mesh) :key #'player.render::mesh-part-kind))
            "~A should have ~A parts" name kind))
      (is (every (lambda (c) (<= 0 c 1)) (player.render::body-mesh-colours body-mesh))))))

(test body-mesh-limbs-never-part
  ;; Each limb capsule ends in the sphere the next one starts with, about the
  ;; joint between them, so in any pose they overlap.
  (let ((state (sb-ext:seed-random-state 6)))
    (dolist (name *mesh-skeletons*)
      (let* ((body-mesh (player.render::make-body-mesh name))
             (bones (remove :bone (player.render::body-mesh-parts body-mesh)
                            :key #'player.render::mesh-part-kind :test-not #'eq))
             (pairs (loop for parent in bones
                          nconc (loop for child in bones
                                      when (= (player.render::mesh-part-joint child) (player.render::mesh-part-child parent))
                                        collect (cons parent child)))))
        (is (< 10 (length pairs)))
        (dotimes (trial 20)
          (multiple-value-bind (buffer transforms)
              (mesh-posed body-mesh (mesh-random-pose (player.render::body-mesh-skeleton body-mesh) state))
            (declare (ignore buffer))
            (loop for (parent . child) in pairs
                  for (nil end nil end-radius) = (player.render::mesh-part-capsule parent)
                  for (start nil start-radius nil) = (player.render::mesh-part-capsule child)
                  for gap = (player.body::vdistance
                             (player.body::transform-point (svref transforms (player.render::mesh-part-joint parent)) end)
                             (player.body::transform-point (svref transforms (player.render::mesh-part-joint child)) start))
                  do (is (< gap (min end-radius start-radius))))))))))

(test body-mesh-posing-moves-parts-rigidly
  (let ((state (sb-ext:seed-random-state 7)))
    (dolist (name *mesh-skeletons*)
      (let ((body-mesh (player.render::make-body-mesh name)))
        (multiple-value-bind (buffer transforms)
            (mesh-posed body-mesh (mesh-random-pose (player.render::body-mesh-skeleton body-mesh) state))
          (is (= (length buffer) (* player.render::+vertex-floats+ (player.render::body-mesh-vertex-count body-mesh))))
          (is (loop with joints = (player.render::body-mesh-joints body-mesh)
                    for p below (length joints)
                    for m = (svref transforms (aref joints p))
                    always (loop for v from (aref (player.render::body-mesh-starts body-mesh) p)
                                   below (aref (player.render::body-mesh-ends body-mesh) p)
                                 always (and (mesh-near-p (player.body::transform-point
                                                           m (mesh-point (player.render::body-mesh-positions body-mesh) v))
                                                          (mesh-point buffer v player.render::+vertex-floats+))
                                             (mesh-near-p (player.body::transform-vector
                                                           m (mesh-point (player.render::body-mesh-normals body-mesh) v))
                                                          (mesh-point buffer v player.render::+vertex-floats+ 3))))))
          (is (equalp (player.render::body-mesh-colours body-mesh)
                      (coerce (loop for v below (player.render::body-mesh-vertex-count body-mesh)
                                    nconc (coerce (subseq buffer (+ 6 (* 9 v)) (+ 9 (* 9 v))) 'list))
                              'player.render::float-vector))))))))

(test body-mesh-posing-allocates-nothing
  (dolist (name *mesh-skeletons*)
    (let* ((body-mesh (player.render::make-body-mesh name))
           (skeleton (player.render::body-mesh-skeleton body-mesh))
           (transforms (player::pose-world-transforms skeleton (player::make-pose skeleton)))
           (out (player.render::make-body-mesh-buffer body-mesh)))
      (player.render::pose-body-mesh body-mesh transforms out)
      (let ((before (sb-ext:get-bytes-consed)))
        (dotimes (i 100) (player.render::pose-body-mesh body-mesh transforms out))
        (is (< (- (sb-ext:get-bytes-consed) before) 4096)
            "100 poses of ~A consed ~D bytes" name (- (sb-ext:get-bytes-consed) before))))))

(test every-dof-shows-in-the-body-mesh
  ;; Eyes, lids, brows, beak, crest, fingers: each DOF from its minimum to the
  ;; middle of its range moves some vertex by more than a millimetre.
  (dolist (name *mesh-skeletons*)
    (let* ((body-mesh (player.render::make-body-mesh name))
           (skeleton (player.render::body-mesh-skeleton body-mesh)))
      (dotimes (i (player.body::skeleton-dof-count skeleton))
        (multiple-value-bind (joint dof) (player.body::skeleton-dof skeleton i)
          (flet ((posed-at (angle)
                   (let ((pose (player::make-pose skeleton)))
                     (setf (aref pose i) (float angle 1d0))
                     (copy-seq (mesh-posed body-mesh pose)))))
            ;; Halfway, as -180 and 180 are one angle.
            (let ((low (posed-at (player.body::body-dof-min dof)))
                  (middle (posed-at (/ (+ (player.body::body-dof-min dof) (player.body::body-dof-max dof)) 2))))
              (is (loop for v below (player.render::body-mesh-vertex-count body-mesh)
                          thereis (> (player.body::vdistance (mesh-point low v 9) (mesh-point middle v 9)) 0.001))
                  "~A: moving ~A ~A shows nowhere" name (player.body::body-joint-name joint)
                  (player.body::body-dof-name dof)))))))))

(test lids-cover-the-eye-as-they-close
  (dolist (name *mesh-skeletons*)
    (let* ((body-mesh (player.render::make-body-mesh name))
           (skeleton (player.render::body-mesh-skeleton body-mesh)))
      (loop for (eye-role lid-role) in '((:left-eye :left-upper-lid) (:right-eye :right-upper-lid))
            for eye = (player::skeleton-role skeleton eye-role)
            for lid = (player::skeleton-role skeleton lid-role)
            for lid-part = (find-if (lambda (part) (and (eq (player.render::mesh-part-kind part) :lid)
                                                        (= (player.render::mesh-part-joint part)
                                                           (player.body::body-joint-index lid))))
                                    (player.render::body-mesh-parts body-mesh))
            for dof = (player.body::body-joint-dof lid 'close)
            do (flet ((blocked (close)
                        ;; Rays from the eye's centre within 30 degrees of straight ahead.
                        (let* ((pose (player::make-pose skeleton))
                               (transforms (progn (setf (aref pose (player::dof-index skeleton (player.body::body-joint-name lid) 'close))
                                                        (float close 1d0))
                                                  (player::pose-world-transforms skeleton pose)))
                               (centre (player::joint-world-position transforms eye)))
                          (loop for (dx dy) in '((0 0) (0.3 0) (-0.3 0) (0 0.3) (0 -0.3) (0.5 0.5) (-0.5 -0.5))
                                count (ray-hits-mesh-p centre (player.body::vnormalize (player.body::make-vec3 dx dy 1))
                                                       (player.render::mesh-part-mesh lid-part)
                                                       (svref transforms (player.body::body-joint-index lid)))))))
                 (let* ((low (player.body::body-dof-min dof)) (high (player.body::body-dof-max dof))
                        (counts (mapcar #'blocked (list low 0 (/ (+ low high) 2) high))))
                   (is (zerop (first counts)) "~A's ~A shuts the eye when open" name lid-role)
                   (is (zerop (second counts)) "~A's ~A hides the eye at rest" name lid-role)
                   (is (= 7 (fourth counts)) "~A's ~A leaves the eye open when shut: ~A" name lid-role counts)
                   (is (apply #'<= counts) "~A's ~A uncovers as it closes: ~A" name lid-role counts)))))))

;;;# Props and scenes

(test prop-meshes
  (let ((note (player.render::make-prop-mesh :note '(:size (0.1 0.15 0.002))))
        (floor (player.render::make-prop-mesh :floor '(:size 2))))
    (is (mesh-closed-p note))
    (multiple-value-bind (low high) (player.render::mesh-bounds note)
      (is (mesh-near-p (player.body::make-vec3 -0.05 -0.075 -0.001) low))
      (is (mesh-near-p (player.body::make-vec3 0.05 0.075 0.001) high)))
    (is (every (lambda (c) (> c 0.8)) (player.render::mesh-colours note)) "a note is white or cream")
    (is (= 2 (player.render::mesh-triangle-count floor)))
    (is (loop for i below 4 always (mesh-near-p (player.body::make-vec3 0 1 0) (mesh-point (player.render::mesh-normals floor) i))))
    (is (mesh-closed-p (player.render::make-prop-mesh :sphere)))
    (signals player::player-error (player.render::make-prop-mesh :planet))))

(test scene-meshes-follow-bodies-and-props
  (let* ((scene (make-instance 'player::scene))
         (peedy (player::make-body 'peedy 'parrot :scene scene :position (player.body::make-vec3 0 0.7 0)))
         (note (make-instance 'player::scene-object :name 'note :kind :prop))
         (hidden (make-instance 'player::scene-object :name 'box :kind :prop))
         (cache (player.render::make-scene-mesh-cache)))
    (dolist (object (list note hidden (make-instance 'player::scene-object :name 'cam :kind :camera)))
      (player::add-object scene object))
    (setf (player::property-value hidden 'visible) nil)
    (player::body-evaluate peedy 0)
    (player::reparent-object note (cons peedy 'r_primaries) :keep-world nil)
    (let ((meshes (player.render::scene-meshes scene :cache cache :floor t)))
      (is (equal (list nil peedy note) (mapcar #'player.render::scene-mesh-object meshes)))
      (flet ((centre-of (object)
               (multiple-value-bind (low high)
                   (player.render::mesh-bounds (player.render::scene-mesh-vertices
                                         (find object meshes :key #'player.render::scene-mesh-object)))
                 (player.body::v* (player.body::v+ low high) 0.5d0))))
        (is (mesh-near-p (player::body-joint-position peedy 'r_primaries) (centre-of note)))
        (is (< 0.7 (player.body::vec3-y (centre-of peedy)) 1.0))
        ;; Move the body: the same buffers follow, the note with the wing.
        (setf (player::property-value peedy 'position) (player.body::make-vec3 1 0.7 0))
        (player::body-evaluate peedy 1)
        (let ((again (player.render::scene-meshes scene :cache cache :floor t)))
          (is (every #'eq (mapcar #'player.render::scene-mesh-vertices meshes)
                     (mapcar #'player.render::scene-mesh-vertices again)))
          (is (mesh-near-p (player::body-joint-position peedy 'r_primaries) (centre-of note)))
          (is (< 0.9 (player.body::vec3-x (centre-of peedy)) 1.1)))))))
