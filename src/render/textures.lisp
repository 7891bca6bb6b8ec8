;;;; textures.lisp -- a model's diffuse textures in GL: decoded by READ-IMAGE
;;;; (stb_image) or at import for one embedded in the model file, uploaded once per renderer with mipmaps and sampled
;;;; trilinearly, and a 1x1 white one for meshes without a texture.

(in-package #:player.render)

;;; Rows.  READ-IMAGE gives rows top to bottom, and glTexImage2D takes the
;;; first row it is given as t = 0.  Assimp leaves UVs as the file has them,
;;; which for the formats it reads is OpenGL's way (v = 0 at the image's
;;; bottom; Assimp's aiProcess_FlipUVs exists to turn them into Direct3D's).
;;; So the rows are uploaded bottom first.  Checked on Collada's duck.dae,
;;; whose eye, beak and wing land where they belong (flipped, they do not).

(define-gl-constants
  +gl-linear-mipmap-linear+ #x2703  +gl-repeat+ #x2901  +gl-texture0+ #x84C0)

(define-gl-function gl-generate-mipmap "glGenerateMipmap" :void (target :uint32))
(define-gl-function gl-active-texture "glActiveTexture" :void (texture :uint32))

(defun bottom-up-rows (pixels width height)
  "The RGBA PIXELS of a WIDTH x HEIGHT image with its rows in reverse order, fresh."
  (let ((out (make-array (length pixels) :element-type '(unsigned-byte 8)))
        (row (* 4 width)))
    (dotimes (y height out)
      (replace out pixels :start1 (* row (- height 1 y)) :start2 (* row y) :end2 (* row (1+ y))))))

(defun upload-texture (pixels width height &key (mipmaps t))
  "A new GL texture of the RGBA PIXELS (WIDTH x HEIGHT, rows bottom first):
repeating, with mipmaps and trilinear filtering when MIPMAPS, else linear."
  (let ((texture (gl-gen-object #'gl-gen-textures)))
    (gl-bind-texture +gl-texture-2d+ texture)
    (gl-pixel-storei +gl-unpack-alignment+ 1)
    (cffi:with-pointer-to-vector-data (pointer pixels)
      (gl-tex-image-2d +gl-texture-2d+ 0 +gl-rgba8+ width height 0 +gl-rgba+ +gl-unsigned-byte+ pointer))
    (when mipmaps (gl-generate-mipmap +gl-texture-2d+))
    (loop for (name value) in `((,+gl-texture-min-filter+ ,(if mipmaps +gl-linear-mipmap-linear+ +gl-linear+))
                                (,+gl-texture-mag-filter+ ,+gl-linear+)
                                (,+gl-texture-wrap-s+ ,+gl-repeat+) (,+gl-texture-wrap-t+ ,+gl-repeat+))
          do (gl-tex-parameteri +gl-texture-2d+ name value))
    (check-gl-error "uploading a texture")
    texture))

(defun white-texture ()
  "A new 1x1 white GL texture: what an untextured mesh samples."
  (upload-texture (make-array 4 :element-type '(unsigned-byte 8) :initial-element 255) 1 1 :mipmaps nil))

(defun texture-image (path mesh)
  "The RGBA IMAGE of MESH's texture PATH (a file, or one embedded in the model
file and decoded at import); a RENDER-ERROR saying why when it is missing or
undecodable, or stb_image is not installed."
  (flet ((fail (reason)
           (render-fail "cannot draw the mesh ~S: its texture ~A ~A" (model-mesh-name mesh) path reason)))
    (handler-case (mesh-texture-image mesh :channels 4)
      (image-library-missing (condition) (fail (format nil "cannot be decoded: ~A" condition)))
      (image-error (condition) (fail (format nil "cannot be read: ~A" (image-error-reason condition)))))))

(defun load-texture (path mesh)
  "A new GL texture of MESH's texture PATH (see TEXTURE-IMAGE), mipmapped."
  (let ((image (texture-image path mesh)))
    (upload-texture (bottom-up-rows (image-pixels image) (image-width image) (image-height image))
                    (image-width image) (image-height image))))

(defun delete-texture (texture)
  "Free the GL TEXTURE."
  (gl-delete-object #'gl-delete-textures texture))
