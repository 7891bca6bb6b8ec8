;;;; renderer.lisp -- drawing a scene with the GL bindings: every visible body
;;;; and prop (posed on the CPU by SCENE-MESHES and streamed to a vertex buffer
;;;; each frame), the floor with contact shadows, and the sky, into an offscreen
;;;; target that is antialiased into the current framebuffer.  Only gl-* calls:
;;;; the same renderer draws in an OSMesa context or in a window.

(in-package #:player.render)

;;;# Meshes in GL buffers

(defstruct (gpu-mesh (:constructor %make-gpu-mesh))
  "Vertices and triangles in GL: the vertex array VAO over VERTEX-BUFFER
(interleaved position, normal, colour) and INDEX-BUFFER holding COUNT indices."
  (vao 0) (vertex-buffer 0) (index-buffer 0) (count 0))

(defun make-gpu-mesh (vertices indices &key (usage +gl-static-draw+))
  "Copy VERTICES (a FLOAT-VECTOR, +VERTEX-FLOATS+ per vertex) and INDICES (an
INDEX-VECTOR) into new GL buffers; USAGE is the vertex buffer's hint."
  (let ((mesh (%make-gpu-mesh :vao (gl-gen-object #'gl-gen-vertex-arrays)
                              :vertex-buffer (gl-gen-object #'gl-gen-buffers)
                              :index-buffer (gl-gen-object #'gl-gen-buffers)
                              :count (length indices)))
        (stride (* 4 +vertex-floats+)))
    (gl-bind-vertex-array (gpu-mesh-vao mesh))
    (gl-bind-buffer +gl-array-buffer+ (gpu-mesh-vertex-buffer mesh))
    (cffi:with-pointer-to-vector-data (pointer vertices)
      (gl-buffer-data +gl-array-buffer+ (* 4 (length vertices)) pointer usage))
    ;; The element buffer binding is part of the vertex array's state.
    (gl-bind-buffer +gl-element-array-buffer+ (gpu-mesh-index-buffer mesh))
    (cffi:with-pointer-to-vector-data (pointer indices)
      (gl-buffer-data +gl-element-array-buffer+ (* 4 (length indices)) pointer +gl-static-draw+))
    (loop for (location offset) in '((0 0) (1 3) (2 6))
          do (gl-vertex-attrib-pointer location 3 +gl-float+ +gl-false+ stride
                                       (cffi:make-pointer (* 4 offset)))
             (gl-enable-vertex-attrib-array location))
    (gl-bind-vertex-array 0)
    mesh))

(defun update-gpu-mesh (mesh vertices)
  "Replace MESH's vertices by VERTICES (as many as it was made with)."
  (gl-bind-buffer +gl-array-buffer+ (gpu-mesh-vertex-buffer mesh))
  (cffi:with-pointer-to-vector-data (pointer vertices)
    (gl-buffer-sub-data +gl-array-buffer+ 0 (* 4 (length vertices)) pointer)))

(defun draw-gpu-mesh (mesh)
  "Draw MESH's triangles with the current program."
  (gl-bind-vertex-array (gpu-mesh-vao mesh))
  (gl-draw-elements +gl-triangles+ (gpu-mesh-count mesh) +gl-unsigned-int+ (cffi:null-pointer)))

(defun delete-gpu-mesh (mesh)
  "Free MESH's GL buffers and vertex array."
  (gl-delete-object #'gl-delete-buffers (gpu-mesh-vertex-buffer mesh))
  (gl-delete-object #'gl-delete-buffers (gpu-mesh-index-buffer mesh))
  (gl-delete-object #'gl-delete-vertex-arrays (gpu-mesh-vao mesh)))

(defgeneric delete-drawable (drawable)
  (:documentation "Free the GL objects of DRAWABLE, what the renderer made to draw a scene mesh.")
  (:method ((mesh gpu-mesh)) (delete-gpu-mesh mesh)))

;;;# The renderer

(defclass renderer ()
  ((width :initarg :width :reader renderer-width)
   (height :initarg :height :reader renderer-height)
   (antialias :initarg :antialias :initform :fxaa :reader renderer-antialias
              :documentation ":FXAA (a post-process), :MSAA (4 samples a pixel) or NIL.")
   (target :initform nil :accessor renderer-target
           :documentation "The FXAA-SOURCE texture, the MSAA-TARGET drawn into, or NIL.")
   (programs :initform '() :accessor renderer-programs
             :documentation "Plist of program name to (PROGRAM-ID . UNIFORM-TABLE).")
   (meshes :initform (make-hash-table :test #'eq :weakness :key) :reader renderer-meshes
           :documentation "SCENE-MESHES' cache: CPU meshes and buffers per scene object.")
   (buffers :initform (make-hash-table :test #'eq) :reader renderer-buffers
            :documentation "SCENE-MESH to its GPU-MESH (a GPU-MODEL when skinned), for the objects of the last frame.")
   (textures :initform (make-hash-table :test #'equal) :reader renderer-textures
             :documentation "Texture file path (or :WHITE) to its GL texture.")
   (skinning :initform :cpu :accessor renderer-skinning
             :documentation ":GPU when skins are skinned in the vertex shader, :CPU when GL cannot (SETUP-MODEL-PROGRAMS).")
   (floor :initform nil :accessor renderer-floor :documentation "The floor grid's GPU-MESH.")
   (empty :initform 0 :accessor renderer-empty
          :documentation "A vertex array without attributes, for the screen-covering passes.")
   (floor-p :initarg :floor :initform t :accessor renderer-floor-p)
   (floor-colour :initarg :floor-colour :accessor renderer-floor-colour)
   (horizon-colour :initarg :horizon-colour :accessor renderer-horizon-colour)
   (zenith-colour :initarg :zenith-colour :accessor renderer-zenith-colour)
   (orbit :initarg :orbit :initform nil :accessor renderer-orbit
          :documentation "An ORBIT moving the camera (the viewer's), or NIL.")
   (view :initform nil :accessor renderer-view :documentation "The VIEW of the last frame drawn."))
  (:default-initargs :floor-colour '(0.78 0.76 0.72) :horizon-colour '(0.86 0.87 0.88)
                     :zenith-colour '(0.62 0.71 0.82))
  (:documentation "Draws scenes in the current GL context at WIDTH x HEIGHT: holds
the shader programs, the buffers of the objects drawn and the offscreen target.
Make with MAKE-RENDERER, free with DELETE-RENDERER."))

(defun make-renderer (width height &rest options)
  "A RENDERER drawing WIDTH x HEIGHT frames in the current GL context.  OPTIONS:
:antialias (:fxaa, the default; :msaa; or NIL), :floor (NIL for none),
:floor-colour, :horizon-colour, :zenith-colour (lists R G B), :orbit (an ORBIT).
Signals a RENDER-ERROR when a shader does not build or GL refuses the target."
  (let ((renderer (apply #'make-instance 'renderer :width width :height height options)))
    (setf (renderer-programs renderer)
          (loop for (name vertex fragment) in *renderer-programs*
                for program = (compile-shader-program (symbol-value vertex) (symbol-value fragment))
                for uniforms = (make-hash-table :test #'equal)
                do (setf (gethash :program uniforms) program)
                append (list name (cons program uniforms)))
          (renderer-empty renderer) (gl-gen-object #'gl-gen-vertex-arrays)
          (renderer-floor renderer) (multiple-value-call #'make-gpu-mesh (floor-grid))
          (renderer-target renderer)
          (ecase (renderer-antialias renderer)
            (:fxaa (make-fxaa-source width height))
            (:msaa (make-msaa-target width height 4))
            ((nil) nil)))
    (setup-model-programs renderer)
    (check-gl-error "making the renderer")
    renderer))

(defun delete-renderer (renderer)
  "Free RENDERER's GL objects (in the context it was made in)."
  (loop for (nil entry) on (renderer-programs renderer) by #'cddr
        do (gl-delete-program (car entry)))
  (loop for mesh being the hash-values of (renderer-buffers renderer) do (delete-drawable mesh))
  (loop for texture being the hash-values of (renderer-textures renderer) do (delete-texture texture))
  (setf (renderer-programs renderer) '())
  (clrhash (renderer-buffers renderer))
  (clrhash (renderer-textures renderer))
  (delete-gpu-mesh (renderer-floor renderer))
  (gl-delete-object #'gl-delete-vertex-arrays (renderer-empty renderer))
  (let ((target (renderer-target renderer)))
    (etypecase target
      (null)
      (fxaa-source (delete-fxaa-source target))
      (msaa-target (delete-msaa-target target))))
  nil)

(defun use-program (renderer name)
  "Make RENDERER's program NAME current; return its table of uniform locations."
  (destructuring-bind (program . uniforms) (getf (renderer-programs renderer) name)
    (gl-use-program program)
    uniforms))

(defun uniform (uniforms name)
  "The location of uniform NAME in the program of UNIFORMS (whose :PROGRAM entry
is the program's id), looked up once."
  (or (gethash name uniforms)
      (setf (gethash name uniforms) (gl-get-uniform-location (gethash :program uniforms) name))))

(defun set-vec3 (uniforms name value)
  "Set vec3 uniform NAME to VALUE, a VEC3 or a list of three reals."
  (if (vec3-p value)
      (gl-uniform3f (uniform uniforms name) (vec3-x value) (vec3-y value) (vec3-z value))
      (destructuring-bind (x y z) value (gl-uniform3f (uniform uniforms name) x y z))))

(defun set-shading (uniforms view lights)
  "Set the mesh program's camera and light uniforms."
  (upload-matrix (uniform uniforms "view_projection") (view-view-projection view))
  (destructuring-bind ((key-direction key-colour) (fill-direction fill-colour)) lights
    (set-vec3 uniforms "key_direction" key-direction)
    (set-vec3 uniforms "key_colour" key-colour)
    (set-vec3 uniforms "fill_direction" fill-direction)
    (set-vec3 uniforms "fill_colour" fill-colour))
  (set-vec3 uniforms "ambient_colour" *ambient-colour*)
  (set-vec3 uniforms "eye_position" (view-eye view)))

;;;# Drawing

(defun mesh-buffer (renderer scene-mesh)
  "The GPU-MESH of SCENE-MESH, made on first sight, holding its vertices as posed now."
  (let ((vertices (scene-mesh-vertices scene-mesh))
        (gpu (gethash scene-mesh (renderer-buffers renderer))))
    (if gpu
        (update-gpu-mesh gpu vertices)
        (setf gpu (setf (gethash scene-mesh (renderer-buffers renderer))
                        (make-gpu-mesh vertices (scene-mesh-indices scene-mesh)
                                       :usage +gl-dynamic-draw+))))
    gpu))

(defun forget-buffers (renderer drawn)
  "Free the GPU meshes of scene meshes not in DRAWN (this frame's): objects gone
from the scene, or a scene replayed from the start with fresh objects."
  (let ((buffers (renderer-buffers renderer)))
    (when (> (hash-table-count buffers) (length drawn))
      (loop for scene-mesh in (loop for key being the hash-keys of buffers
                                    unless (member key drawn) collect key)
            do (delete-drawable (gethash scene-mesh buffers))
               (remhash scene-mesh buffers)))))

(defun draw-meshes (renderer scene-meshes view lights)
  "Draw SCENE-MESHES, lit: those posed on the CPU here, the skinned ones by
DRAW-SKINNED-MESHES."
  (let ((uniforms (use-program renderer :mesh)))
    (set-shading uniforms view lights)
    (dolist (scene-mesh scene-meshes)
      (unless (skinned-scene-mesh-p scene-mesh)
        (draw-gpu-mesh (mesh-buffer renderer scene-mesh)))))
  (draw-skinned-meshes renderer (remove-if-not #'skinned-scene-mesh-p scene-meshes) view lights))

(defun draw-floor (renderer view lights height)
  "Draw the floor at HEIGHT, fading into the horizon from 4 to 25 m from the eye."
  (let ((uniforms (use-program renderer :floor)))
    (upload-matrix (uniform uniforms "view_projection") (view-view-projection view))
    (set-vec3 uniforms "eye_position" (view-eye view))
    (gl-uniform1f (uniform uniforms "floor_height") height)
    (gl-uniform1f (uniform uniforms "fade_start") 4)
    (gl-uniform1f (uniform uniforms "fade_end") 25)
    (set-vec3 uniforms "floor_lit" (lit-floor-colour (renderer-floor-colour renderer) lights))
    (set-vec3 uniforms "horizon_colour" (renderer-horizon-colour renderer))
    (draw-gpu-mesh (renderer-floor renderer))))

(defun draw-shadows (renderer view scene-meshes ground)
  "Darken the surface under each body with a soft blob (see CONTACT-SHADOW)."
  (let ((uniforms (use-program renderer :shadow))
        (props (remove-if (lambda (m) (typep (scene-mesh-object m) 'body)) scene-meshes)))
    (upload-matrix (uniform uniforms "view_projection") (view-view-projection view))
    (gl-enable +gl-blend+)
    (gl-blend-func +gl-zero+ +gl-src-color+)  ; multiply what is there
    (gl-depth-mask +gl-false+)
    (gl-bind-vertex-array (renderer-empty renderer))
    (dolist (mesh scene-meshes)
      ;; A one-joint skeleton has no limb to draw, and casts no shadow.
      (when (and (typep (scene-mesh-object mesh) 'body) (plusp (length (scene-mesh-vertices mesh))))
        (let ((bounds (vertex-bounds (scene-mesh-vertices mesh))))
          (destructuring-bind (x z radius height strength)
              (contact-shadow bounds (shadow-surface bounds props ground))
            (when (plusp strength)
              (gl-uniform4f (uniform uniforms "caster") x z radius height)
              (gl-uniform1f (uniform uniforms "strength") strength)
              (gl-draw-arrays +gl-triangle-strip+ 0 4))))))
    (gl-depth-mask +gl-true+)
    (gl-disable +gl-blend+)))

(defun draw-sky (renderer view)
  "Fill what nothing covered with the background gradient."
  (let ((uniforms (use-program renderer :sky)))
    (upload-matrix (uniform uniforms "inverse_view_projection") (view-inverse-view-projection view))
    (set-vec3 uniforms "horizon_colour" (renderer-horizon-colour renderer))
    (set-vec3 uniforms "zenith_colour" (renderer-zenith-colour renderer))
    (gl-bind-vertex-array (renderer-empty renderer))
    (gl-draw-arrays +gl-triangles+ 0 3)))

(defun begin-frame (renderer)
  "Bind what RENDERER draws into -- its multisampled target, or the current
context's framebuffer -- and clear its depth.  The colour needs no clearing:
the sky covers whatever nothing else does."
  (let ((target (renderer-target renderer)))
    (if (msaa-target-p target)
        (bind-msaa-target target)
        (progn (gl-bind-framebuffer +gl-framebuffer+ 0)
               (gl-viewport 0 0 (renderer-width renderer) (renderer-height renderer)))))
  (gl-clear +gl-depth-buffer-bit+))

(defun end-frame (renderer view scene-meshes)
  "Finish the frame in the current context's framebuffer: resolve the
multisampled target, or smooth the edges of SCENE-MESHES seen through VIEW."
  (let ((target (renderer-target renderer)))
    (etypecase target
      (null)
      (msaa-target (resolve-msaa-target target))
      (fxaa-source (fxaa-pass (car (getf (renderer-programs renderer) :fxaa)) target
                              (renderer-empty renderer)
                              (screen-box view scene-meshes (renderer-width renderer)
                                          (renderer-height renderer)))))))

(defun render-scene (renderer scene &key camera)
  "Draw SCENE as it is now -- every visible body and prop, the floor with their
contact shadows, and the background, then its caption if it has one -- seen
through CAMERA (default: the scene's camera, else one framing the bodies) moved by the renderer's orbit,
into the current context's framebuffer, where RENDERER-PIXELS reads it.
Returns the VIEW used."
  (let* ((view (scene-view scene (/ (renderer-width renderer) (renderer-height renderer))
                           :orbit (renderer-orbit renderer) :camera camera))
         (lights (scene-lights scene (scene-focus scene)))
         (scene-meshes (scene-meshes scene :cache (renderer-meshes renderer)))
         (ground (floor-height scene-meshes)))
    (begin-frame renderer)
    ;; Nearest first, so the depth test spares the shading of the floor
    ;; behind the bodies and of the sky behind everything.
    (gl-enable +gl-depth-test+)
    (gl-depth-func +gl-lequal+)
    (gl-enable +gl-cull-face+)
    (draw-meshes renderer scene-meshes view lights)
    (gl-disable +gl-cull-face+)
    (when (renderer-floor-p renderer)
      (draw-floor renderer view lights ground))
    (draw-shadows renderer view scene-meshes ground)
    (draw-sky renderer view)
    (gl-bind-vertex-array 0)
    (end-frame renderer view scene-meshes)
    (when (scene-caption scene)
      (draw-caption (scene-caption scene) (renderer-width renderer) (renderer-height renderer)))
    (forget-buffers renderer scene-meshes)
    (setf (renderer-view renderer) view)))

(defun renderer-pixels (renderer)
  "The last frame RENDERER drew: WIDTH*HEIGHT RGBA bytes, rows top-down."
  (read-frame-pixels (renderer-width renderer) (renderer-height renderer)))
