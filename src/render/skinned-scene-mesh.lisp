;;;; skinned-scene-mesh.lisp -- what SCENE-MESHES keeps of a body whose skeleton
;;;; is an imported model's (it has a RIG), or of a prop drawn as a model: each skin's palette at the current
;;;; pose and a box around the posed skin.  No posed vertices: the renderer
;;;; skins them itself, on the GPU or, as a fallback, on the CPU.

(in-package #:player.render)

;;; The box stands in for the vertices wherever the renderer only needs to
;;; know where a body is (its contact shadow, the floor, the antialiased part
;;; of the frame).  It must hold the whole skin in any pose without skinning
;;; it: a vertex moved rigidly by palette entry k stays within |B_k v| (its
;;; rest distance from that joint's centre) of the joint, and a blended vertex
;;; is a convex sum of such points, so the box around each entry's joint grown
;;; by the largest such distance, the entry's REACH, holds it.  (One reach for
;;; the whole skin would be simpler, but a bison's reaches its length: the box
;;; then passed behind the camera, and the antialiasing pass took the whole
;;; frame, 40 ms on llvmpipe.)

(defstruct (skinned-scene-mesh (:include scene-mesh) (:constructor %make-skinned-scene-mesh))
  "A body drawn from its rig's SKINS (a list of MESH-SKINs): PALETTES, per skin
a simple-vector of its palette's MAT4s at the last pose (SKIN-PALETTE-MATRICES);
REACHES, per skin a vector of how far (metres) a vertex lies at most from the
joint of each palette entry weighing it.  VERTICES
holds the 8 corners of a box around the posed skin, +VERTEX-FLOATS+ each."
  (skins '() :type list)
  (palettes '() :type list)
  (reaches '() :type list))

(defun skin-reaches (skin)
  "For each palette entry k of SKIN, the farthest a vertex it weighs most
lies, at rest, from the centre of its joint: the largest |B_k v| over the
vertices whose largest weight is k's, a vector of doubles.  Counting every
vertex a joint weighs at all made the pelvis reach the tail; a blended vertex
lies near its main joint's sphere, and one a little outside only misses the
antialiasing pass at an edge (the picture stays right)."
  (let ((positions (model-mesh-positions (skin-mesh skin)))
        (slots (skin-slots skin))
        (weights (skin-weights skin))
        (palette (skin-palette skin))
        (reaches (make-array (length (skin-palette skin)) :element-type 'double-float :initial-element 0d0)))
    (dotimes (v (floor (length positions) 3) reaches)
      (let ((k (loop with best = 0
                     for j from 1 below 4
                     when (> (aref weights (+ (* 4 v) j)) (aref weights (+ (* 4 v) best)))
                       do (setf best j)
                     finally (return best))))
        (progn
          (let* ((slot (aref slots (+ (* 4 v) k)))
                 (m (svref palette slot)))
            (setf (aref reaches slot) (max (aref reaches slot)
                             (sqrt (loop for row below 3
                                         sum (expt (+ (loop for column below 3
                                                            sum (* (aref m row column)
                                                                   (aref positions (+ (* 3 v) column))))
                                                      (aref m row 3))
                                                   2)))))))))))

(defun make-skinned-scene-mesh (object skins)
  "The SKINNED-SCENE-MESH of OBJECT drawn from SKINS: a body whose skeleton has
a RIG (its RIG-SKINS), or a MODEL-PROP (its meshes as skins of one joint)."
  (%make-skinned-scene-mesh
   :object object :body-mesh nil
   :vertices (make-array (* 6 +vertex-floats+ (reduce #'+ skins :key (lambda (skin) (length (skin-palette skin)))))
                         :element-type 'single-float :initial-element 0f0)
   :skins skins
   :palettes (mapcar (lambda (skin) (make-array (length (skin-palette skin)) :initial-element nil)) skins)
   :reaches (mapcar #'skin-reaches skins)))

(defun write-sphere-points (vertices centre radius start)
  "Write the 6 points RADIUS from the vec3 CENTRE along +-x, +-y and +-z as
positions into the interleaved VERTICES from the float START on, normals up."
  (dotimes (point 6)
    (let ((at (+ start (* point +vertex-floats+)))
          (axis (floor point 2))
          (sign (if (evenp point) -1 1)))
      (dotimes (k 3)
        (setf (aref vertices (+ at k))
              (float (+ (ecase k (0 (vec3-x centre)) (1 (vec3-y centre)) (2 (vec3-z centre)))
                        (if (= k axis) (* sign radius) 0d0))
                     1f0)))
      (setf (aref vertices (+ at 4)) 1f0))))

(defmethod pose-scene-mesh ((mesh skinned-scene-mesh) transforms)
  "Compute each skin's palette at TRANSFORMS and the points bounding the posed
skin: the 6 points of the sphere around each palette entry's joint, its reach
across, along the axes.  Their box is the skin's box (the contact shadow's);
projected one by one they bound its outline on screen far more tightly than
that box's corners would (give or take the few pixels a sphere's outline
passes its axis points by, which the screen box's margin covers), and that
keeps the antialiasing pass to the pixels near it."
  (loop for skin in (skinned-scene-mesh-skins mesh)
        for palette in (skinned-scene-mesh-palettes mesh)
        do (skin-palette-matrices skin transforms palette))
  (let ((vertices (scene-mesh-vertices mesh))
        (start 0))
    (loop for skin in (skinned-scene-mesh-skins mesh)
          for reaches in (skinned-scene-mesh-reaches mesh)
          do (loop for joint across (skin-palette-joints skin)
                   for reach across reaches
                   for p = (transform-translation (svref transforms joint))
                   do (write-sphere-points vertices p reach start)
                      (incf start (* 6 +vertex-floats+)))))
  mesh)
