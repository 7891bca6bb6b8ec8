;;;; antialias.lisp -- smooth edges for the price llvmpipe can pay: FXAA, a
;;;; post-process that finds edges by their contrast and blends along them.
;;;; 4x multisampling is the other choice (framebuffer.lisp), but llvmpipe
;;;; shades every sample: at 640x480 a parrot frame took 15 ms with it against
;;;; 6 ms without, and FXAA over the box around the figure adds about 1 ms.

(in-package #:player.render)

;;;# Bindings the base lacks: textures, the scissor, a blend factor

(define-gl-constants
  +gl-texture-2d+ #x0DE1  +gl-texture-mag-filter+ #x2800  +gl-texture-min-filter+ #x2801
  +gl-texture-wrap-s+ #x2802  +gl-texture-wrap-t+ #x2803  +gl-clamp-to-edge+ #x812F
  +gl-src-color+ #x0300)

(define-gl-function gl-gen-textures "glGenTextures" :void (n :int32) (textures :pointer))
(define-gl-function gl-delete-textures "glDeleteTextures" :void (n :int32) (textures :pointer))
(define-gl-function gl-bind-texture "glBindTexture" :void (target :uint32) (texture :uint32))
(define-gl-function gl-tex-parameteri "glTexParameteri" :void (target :uint32) (pname :uint32) (param :int32))
(define-gl-function gl-tex-image-2d "glTexImage2D" :void
  (target :uint32) (level :int32) (internal-format :int32) (width :int32) (height :int32)
  (border :int32) (format :uint32) (type :uint32) (data :pointer))
(define-gl-function gl-copy-tex-sub-image-2d "glCopyTexSubImage2D" :void
  (target :uint32) (level :int32) (x-offset :int32) (y-offset :int32)
  (x :int32) (y :int32) (width :int32) (height :int32))

;;;# The frame as a texture

;;; The scene is drawn straight into the current framebuffer; the pixels FXAA
;;; treats are then copied into a texture of the frame's size at the same
;;; coordinates, and the pass writes them back smoothed.  Only the box around
;;; the bodies and props needs it (the floor and sky are soft), and copying
;;; just that box costs a fifth of blitting a whole offscreen frame.

(defstruct (fxaa-source (:constructor %make-fxaa-source))
  "The RGBA8 TEXTURE (linearly filtered, clamped) of WIDTH x HEIGHT that FXAA reads."
  (texture 0) (width 1) (height 1))

(defun make-fxaa-source (width height)
  "A WIDTH x HEIGHT FXAA-SOURCE."
  (let ((texture (gl-gen-object #'gl-gen-textures)))
    (gl-bind-texture +gl-texture-2d+ texture)
    (gl-tex-image-2d +gl-texture-2d+ 0 +gl-rgba8+ width height 0 +gl-rgba+ +gl-unsigned-byte+
                     (cffi:null-pointer))
    (loop for (name value) in `((,+gl-texture-min-filter+ ,+gl-linear+) (,+gl-texture-mag-filter+ ,+gl-linear+)
                                (,+gl-texture-wrap-s+ ,+gl-clamp-to-edge+) (,+gl-texture-wrap-t+ ,+gl-clamp-to-edge+))
          do (gl-tex-parameteri +gl-texture-2d+ name value))
    (%make-fxaa-source :texture texture :width width :height height)))

(defun delete-fxaa-source (source)
  "Free SOURCE's texture."
  (gl-delete-object #'gl-delete-textures (fxaa-source-texture source)))

;;;# Where the edges are

(defun projected-extent (vertices matrix extent)
  "Grow EXTENT, a (SIMPLE-ARRAY DOUBLE-FLOAT (4)) of the least and greatest x
and y in normalized device coordinates, by the interleaved VERTICES seen
through the 4x4 MATRIX.  False when a vertex lies behind the near plane."
  (declare (type float-vector vertices) (type mat4 matrix)
           (type (simple-array double-float (4)) extent) (optimize (speed 3) (safety 1)))
  (macrolet ((row (i) `(values (aref matrix ,i 0) (aref matrix ,i 1) (aref matrix ,i 2) (aref matrix ,i 3))))
    (multiple-value-bind (a0 a1 a2 a3) (row 0)
      (multiple-value-bind (b0 b1 b2 b3) (row 1)
        (multiple-value-bind (d0 d1 d2 d3) (row 3)
          (loop for i of-type fixnum from 0 below (length vertices) by +vertex-floats+
                always (let* ((x (float (aref vertices i) 1d0)) (y (float (aref vertices (+ i 1)) 1d0))
                              (z (float (aref vertices (+ i 2)) 1d0))
                              (w (+ (* d0 x) (* d1 y) (* d2 z) d3)))
                         (when (> w (the double-float *near-plane*))
                           (let ((u (/ (+ (* a0 x) (* a1 y) (* a2 z) a3) w))
                                 (v (/ (+ (* b0 x) (* b1 y) (* b2 z) b3) w)))
                             (setf (aref extent 0) (min (aref extent 0) u) (aref extent 1) (min (aref extent 1) v)
                                   (aref extent 2) (max (aref extent 2) u) (aref extent 3) (max (aref extent 3) v))
                             t)))))))))

(defun screen-box (view scene-meshes width height)
  "The pixels (X Y WIDTH HEIGHT, from the bottom left) of a WIDTH x HEIGHT frame
that SCENE-MESHES cover seen through VIEW, give or take 3, or NIL for the
whole frame (when something reaches behind the camera)."
  (let ((extent (make-array 4 :element-type 'double-float :initial-contents '(1d0 1d0 -1d0 -1d0))))
    (when (every (lambda (mesh)
                   (projected-extent (scene-mesh-vertices mesh) (view-view-projection view) extent))
                 scene-meshes)
      (flet ((pixel (ndc size) (* 0.5d0 (1+ (max -1d0 (min 1d0 ndc))) size)))
        (let ((left (max 0 (- (floor (pixel (aref extent 0) width)) 3)))
              (bottom (max 0 (- (floor (pixel (aref extent 1) height)) 3)))
              (right (min width (+ (ceiling (pixel (aref extent 2) width)) 3)))
              (top (min height (+ (ceiling (pixel (aref extent 3) height)) 3))))
          (if (and (< left right) (< bottom top))
              (list left bottom (- right left) (- top bottom))
              (list 0 0 1 1)))))))

;;;# The FXAA pass

(defparameter *fxaa-vertex-shader*
  "#version 330 core
void main() {
  vec2 corner = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2)) * 2.0 - 1.0;
  gl_Position = vec4(corner, 0.0, 1.0);
}"
  "A screen-covering triangle from gl_VertexID alone.")

(defparameter *fxaa-fragment-shader*
  "#version 330 core
// FXAA after Timothy Lottes' FXAA 3 console version: where the four diagonal
// neighbours' luma shows an edge, blend two or four taps along it.
uniform sampler2D frame;
out vec4 fragment;
const vec3 LUMA = vec3(0.299, 0.587, 0.114);
void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  vec3 m = texelFetch(frame, p, 0).rgb;
  float nw = dot(texelFetch(frame, p + ivec2(-1, 1), 0).rgb, LUMA);
  float ne = dot(texelFetch(frame, p + ivec2(1, 1), 0).rgb, LUMA);
  float sw = dot(texelFetch(frame, p + ivec2(-1, -1), 0).rgb, LUMA);
  float se = dot(texelFetch(frame, p + ivec2(1, -1), 0).rgb, LUMA);
  float lm = dot(m, LUMA);
  float low = min(lm, min(min(nw, ne), min(sw, se)));
  float high = max(lm, max(max(nw, ne), max(sw, se)));
  if (high - low < max(0.04, 0.125 * high)) { fragment = vec4(m, 1.0); return; }
  vec2 texel = 1.0 / vec2(textureSize(frame, 0));
  vec2 uv = gl_FragCoord.xy * texel;
  vec2 dir = vec2((nw + ne) - (sw + se), (nw + sw) - (ne + se));   // along the edge
  float reduce = max((nw + ne + sw + se) * 0.03125, 1.0 / 128.0);
  dir = clamp(dir / (min(abs(dir.x), abs(dir.y)) + reduce), -8.0, 8.0) * texel;
  vec3 a = 0.5 * (texture(frame, uv - dir / 6.0).rgb + texture(frame, uv + dir / 6.0).rgb);
  vec3 b = 0.5 * a + 0.25 * (texture(frame, uv - dir * 0.5).rgb + texture(frame, uv + dir * 0.5).rgb);
  float lb = dot(b, LUMA);
  fragment = vec4((lb < low || lb > high) ? a : b, 1.0);
}"
  "Fast approximate antialiasing of the texture FRAME into the bound framebuffer.")

(defconstant +fxaa-reach+ 6
  "How many pixels from the one it smooths the FXAA pass reads: one for the
neighbours plus half of the longest edge step (8).")

(defun fxaa-pass (program source vao &optional box)
  "Smooth the edges in the current framebuffer within BOX, a list (X Y WIDTH
HEIGHT) of pixels from the bottom left (default: everywhere): copy them and
the +FXAA-REACH+ pixels around them into SOURCE's texture and draw them back
through PROGRAM, linked from the FXAA shaders.  VAO is any vertex array: the
pass reads no attributes, but the core profile draws nothing without one bound."
  (let ((frame-width (fxaa-source-width source))
        (frame-height (fxaa-source-height source)))
    (destructuring-bind (x y width height) (or box (list 0 0 frame-width frame-height))
      (let ((x0 (max 0 (- x +fxaa-reach+))) (y0 (max 0 (- y +fxaa-reach+)))
            (x1 (min frame-width (+ x width +fxaa-reach+))) (y1 (min frame-height (+ y height +fxaa-reach+))))
        (gl-bind-texture +gl-texture-2d+ (fxaa-source-texture source))
        (gl-copy-tex-sub-image-2d +gl-texture-2d+ 0 x0 y0 x0 y0 (- x1 x0) (- y1 y0)))
      (gl-enable +gl-scissor-test+)
      (gl-scissor x y width height)))
  (gl-disable +gl-depth-test+)
  (gl-use-program program)
  (gl-uniform1i (gl-get-uniform-location program "frame") 0)
  (gl-bind-vertex-array vao)
  (gl-draw-arrays +gl-triangles+ 0 3)
  (gl-bind-vertex-array 0)
  (gl-disable +gl-scissor-test+))
