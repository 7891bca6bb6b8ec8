;;;; skinned-mesh.lisp -- drawing a body from its model's skins: each mesh's
;;;; vertices, UVs, colours, palette slots and weights in GL buffers once, and
;;;; each frame only the palette (GPU skinning) or, where the vertex shader
;;;; cannot hold the palette, the vertices SKIN-VERTICES poses (CPU skinning).

(in-package #:player.render)

;;; Why two paths.  A palette of up to +PALETTE-SIZE+ matrices fits the
;;; uniforms of any GL 3.3 (which promises 1024 vertex uniform vectors); a
;;; skin with more joints, or a GL that refuses the skinning program, falls
;;; back to the CPU, which the rig layer already does as the reference.  Both
;;; paths end in the same fragment shader (model-shaders.lisp).

(defvar *gpu-skinning* t
  "When NIL, renderers made afterwards skin every mesh on the CPU: the
fallback, forced (to compare the two paths, or to time them).")

(define-gl-constants +gl-max-vertex-uniform-components+ #x8B4A)

(defstruct (gpu-skin (:constructor %make-gpu-skin))
  "One skin in GL: the vertex array VAO over BUFFERS (the attributes) and
INDEX-BUFFER holding COUNT indices, its TEXTURE, and MODE, :GPU or :CPU.  On
the CPU path POSITIONS and NORMALS are the posed vertices, which go to
POSITION-BUFFER and NORMAL-BUFFER each frame."
  (vao 0) (buffers '()) (index-buffer 0) (count 0) (texture 0) (textured nil) (mode :gpu)
  (positions nil) (normals nil) (position-buffer 0) (normal-buffer 0))

(defstruct (gpu-model (:constructor make-gpu-model (skins)))
  "A skinned body in GL: a GPU-SKIN per skin of its rig, in the rig's order."
  (skins '() :type list))

;;;# Programs

(defun gpu-skinning-possible-p ()
  "Can the current GL hold the skinning vertex shader's palette in its uniforms?"
  (>= (gl-get-integer +gl-max-vertex-uniform-components+) (+ (* 16 +palette-size+) 64)))

(defun add-program (renderer name vertex-source fragment-source)
  "Link a program from the sources and add it to RENDERER's programs as NAME."
  (let ((program (compile-shader-program vertex-source fragment-source))
        (uniforms (make-hash-table :test #'equal)))
    (setf (gethash :program uniforms) program)
    (setf (renderer-programs renderer) (list* name (cons program uniforms) (renderer-programs renderer)))))

(defun setup-model-programs (renderer)
  "Link RENDERER's programs for models: the one drawing CPU-posed skins always,
the skinning one when *GPU-SKINNING* and GL allow it (it sets RENDERER-SKINNING
to :GPU then, else :CPU).  A skinning program GL refuses is no error: the CPU
path draws the same picture."
  (add-program renderer :model-posed *posed-model-vertex-shader* *model-fragment-shader*)
  (setf (renderer-skinning renderer)
        (if (and *gpu-skinning* (gpu-skinning-possible-p)
                 (handler-case (progn (add-program renderer :model-skinned *skinned-vertex-shader*
                                                   *model-fragment-shader*)
                                      t)
                   (render-error () nil)))
            :gpu
            :cpu)))

;;;# Buffers

(defun vector-bytes (data)
  "The size in bytes of the specialised vector DATA (single-floats, ub16 or ub32)."
  (* (length data) (if (typep data '(simple-array (unsigned-byte 16) (*))) 2 4)))

(defun attribute-buffer (location data size type usage)
  "A new array buffer holding DATA, fed to the bound vertex array's attribute
LOCATION as SIZE values of TYPE a vertex (integers converted to floats)."
  (let ((buffer (gl-gen-object #'gl-gen-buffers)))
    (gl-bind-buffer +gl-array-buffer+ buffer)
    (cffi:with-pointer-to-vector-data (pointer data)
      (gl-buffer-data +gl-array-buffer+ (vector-bytes data) pointer usage))
    (gl-vertex-attrib-pointer location size type +gl-false+ 0 (cffi:null-pointer))
    (gl-enable-vertex-attrib-array location)
    buffer))

(defun filled-floats (count values)
  "A single-float vector of COUNT copies of the list VALUES, one after another."
  (let ((out (make-array (* count (length values)) :element-type 'single-float)))
    (dotimes (i count out)
      (loop for value in values for k from 0
            do (setf (aref out (+ k (* i (length values)))) (float value 1f0))))))

(defun mesh-tints (mesh textured)
  "MESH's colour a vertex, RGBA: its vertex colours, else white under a texture
\(TEXTURED), else *MODEL-COLOUR*."
  (or (model-mesh-colours mesh)
      (filled-floats (model-mesh-vertex-count mesh) (append (if textured '(1 1 1) *model-colour*) '(1)))))

(defun mesh-texture (renderer mesh)
  "The GL texture MESH is drawn with: its diffuse texture, loaded once per
RENDERER (a RENDER-ERROR when it cannot be), or a white one when it has none
or no UVs to place it."
  (let* ((path (and (model-mesh-uvs mesh) (model-mesh-texture mesh)))
         ;; An embedded texture is keyed by itself: two models both have a "*0".
         (key (or (and path (model-mesh-embedded-texture mesh)) path :white))
         (textures (renderer-textures renderer)))
    (or (gethash key textures)
        (setf (gethash key textures)
              (if path (load-texture path mesh) (white-texture))))))

(defun make-gpu-skin (renderer skin)
  "SKIN's GL buffers and texture, skinned on the GPU when RENDERER can and its
palette fits +PALETTE-SIZE+, else on the CPU."
  (let* ((mesh (skin-mesh skin))
         (count (model-mesh-vertex-count mesh))
         ;; Morph targets are added on the CPU, before skinning.
         (mode (if (and (eq (renderer-skinning renderer) :gpu)
                        (<= (length (skin-palette skin)) +palette-size+)
                        (null (skin-morphs skin)))
                   :gpu :cpu))
         (normals (or (model-mesh-normals mesh) (filled-floats count '(0 1 0))))
         (texture (mesh-texture renderer mesh))
         (gpu (%make-gpu-skin :vao (gl-gen-object #'gl-gen-vertex-arrays) :mode mode :texture texture
                              :textured (and (model-mesh-uvs mesh) (model-mesh-texture mesh) t)
                              :count (length (model-mesh-triangles mesh)))))
    (gl-bind-vertex-array (gpu-skin-vao gpu))
    (flet ((add (location data size &optional (type +gl-float+) (usage +gl-static-draw+))
             (let ((buffer (attribute-buffer location data size type usage)))
               (push buffer (gpu-skin-buffers gpu))
               buffer)))
      (if (eq mode :gpu)
          (progn (add 0 (model-mesh-positions mesh) 3)
                 (add 1 normals 3)
                 (add 4 (skin-slots skin) 4 +gl-unsigned-short+)
                 (add 5 (skin-weights skin) 4))
          (setf (gpu-skin-positions gpu) (make-array (* 3 count) :element-type 'single-float :initial-element 0f0)
                (gpu-skin-normals gpu) (copy-seq normals)
                (gpu-skin-position-buffer gpu) (add 0 (gpu-skin-positions gpu) 3 +gl-float+ +gl-dynamic-draw+)
                (gpu-skin-normal-buffer gpu) (add 1 (gpu-skin-normals gpu) 3 +gl-float+ +gl-dynamic-draw+)))
      (add 2 (mesh-tints mesh (and (model-mesh-uvs mesh) (model-mesh-texture mesh) t)) 4)
      (when (model-mesh-uvs mesh) (add 3 (model-mesh-uvs mesh) 2)))
    ;; The element buffer binding is part of the vertex array's state.
    (setf (gpu-skin-index-buffer gpu) (gl-gen-object #'gl-gen-buffers))
    (gl-bind-buffer +gl-element-array-buffer+ (gpu-skin-index-buffer gpu))
    (cffi:with-pointer-to-vector-data (pointer (model-mesh-triangles mesh))
      (gl-buffer-data +gl-element-array-buffer+ (vector-bytes (model-mesh-triangles mesh)) pointer
                      +gl-static-draw+))
    (gl-bind-vertex-array 0)
    (check-gl-error "loading a skinned mesh")
    gpu))

(defmethod delete-drawable ((model gpu-model))
  (dolist (skin (gpu-model-skins model))
    (dolist (buffer (cons (gpu-skin-index-buffer skin) (gpu-skin-buffers skin)))
      (gl-delete-object #'gl-delete-buffers buffer))
    (gl-delete-object #'gl-delete-vertex-arrays (gpu-skin-vao skin))))

(defun model-buffer (renderer scene-mesh)
  "The GPU-MODEL of the SKINNED-SCENE-MESH, made on first sight."
  (or (gethash scene-mesh (renderer-buffers renderer))
      (setf (gethash scene-mesh (renderer-buffers renderer))
            (make-gpu-model (mapcar (lambda (skin) (make-gpu-skin renderer skin))
                                    (skinned-scene-mesh-skins scene-mesh))))))

;;;# Drawing

(defun upload-matrices (location matrices)
  "Set the mat4 array uniform at LOCATION to MATRICES (a vector of MAT4s)."
  (let ((n (length matrices)))
    (cffi:with-foreign-object (floats :float (* 16 n))
      (loop for m across matrices
            for base from 0 by 16
            do (dotimes (column 4)
                 (dotimes (row 4)
                   (setf (cffi:mem-aref floats :float (+ base row (* 4 column)))
                         (float (aref m row column) 1f0)))))
      (gl-uniform-matrix4fv location n +gl-false+ floats))))

(defun pose-on-cpu (gpu skin palette pose)
  "Skin SKIN's vertices by PALETTE on the CPU into GPU's buffers, its morph
targets first added at their weights in POSE (the body's)."
  (skin-vertices skin palette (gpu-skin-positions gpu) (and (model-mesh-normals (skin-mesh skin))
                                                            (gpu-skin-normals gpu))
                 pose)
  (loop for (buffer data) in (list (list (gpu-skin-position-buffer gpu) (gpu-skin-positions gpu))
                                   (list (gpu-skin-normal-buffer gpu) (gpu-skin-normals gpu)))
        do (gl-bind-buffer +gl-array-buffer+ buffer)
           (cffi:with-pointer-to-vector-data (pointer data)
             (gl-buffer-sub-data +gl-array-buffer+ 0 (vector-bytes data) pointer))))

(defun draw-skinned-meshes (renderer scene-meshes view lights)
  "Draw the SKINNED-SCENE-MESHES at their palettes, lit and textured."
  (let ((shaded '()))
    (gl-active-texture +gl-texture0+)
    ;; Files disagree on winding (Direct X's is clockwise), and a model may
    ;; be open: draw both sides, as the fragment shader lights the one seen.
    (gl-disable +gl-cull-face+)
    (dolist (scene-mesh scene-meshes)
      (loop for gpu in (gpu-model-skins (model-buffer renderer scene-mesh))
            for skin in (skinned-scene-mesh-skins scene-mesh)
            for palette in (skinned-scene-mesh-palettes scene-mesh)
            do (let* ((name (if (eq (gpu-skin-mode gpu) :gpu) :model-skinned :model-posed))
                      (uniforms (use-program renderer name)))
                 (unless (member name shaded)
                   (set-shading uniforms view lights)
                   (gl-uniform1i (uniform uniforms "diffuse") 0)
                   (push name shaded))
                 (if (eq (gpu-skin-mode gpu) :gpu)
                     (upload-matrices (uniform uniforms "palette") palette)
                     (pose-on-cpu gpu skin palette (body-pose (scene-mesh-object scene-mesh))))
                 (gl-uniform1i (uniform uniforms "textured") (if (gpu-skin-textured gpu) 1 0))
                 (gl-bind-texture +gl-texture-2d+ (gpu-skin-texture gpu))
                 (gl-bind-vertex-array (gpu-skin-vao gpu))
                 (gl-draw-elements +gl-triangles+ (gpu-skin-count gpu) +gl-unsigned-int+
                                   (cffi:null-pointer)))))
    (gl-enable +gl-cull-face+)))
