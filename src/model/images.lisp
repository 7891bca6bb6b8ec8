;;;; images.lisp -- texture images (PNG, JPEG, TGA, BMP) decoded by stb_image
;;;; (Debian's libstb0): the raw %STBI- bindings, then READ-IMAGE, the checked
;;;; layer (the file checked before C sees it, C's answer checked before its
;;;; pixels are copied into Lisp and freed), then MODEL-TEXTURE-IMAGES, which
;;;; decodes the textures a model names so a missing or broken one is found
;;;; before a render starts.  Every failure is one IMAGE-ERROR naming the file.

(in-package #:player.model)

;;;# Conditions and limits

(define-condition image-error (player-error)
  ((file :initarg :file :reader image-error-file
         :documentation "The image file, as given.")
   (reason :initarg :reason :reader image-error-reason
           :documentation "What is wrong with it, a clause without a capital."))
  (:report (lambda (condition stream)
             (format stream "cannot decode the image ~A: ~A"
                     (image-error-file condition) (image-error-reason condition))))
  (:documentation "An image file could not be decoded: it is missing, not a
readable file, stb_image refused it, or it is past *IMAGE-PIXEL-LIMIT*."))

(define-condition image-library-missing (image-error)
  ((package :initarg :package :reader image-library-missing-package
            :documentation "The Debian package that provides the library."))
  (:documentation "libstb is not installed; the reason names the Debian package."))

(defun image-fail (file control &rest arguments)
  "Signal an IMAGE-ERROR about FILE whose reason is CONTROL applied to ARGUMENTS."
  (error 'image-error :file file :reason (apply #'format nil control arguments)))

(defparameter *image-pixel-limit* (expt 2 28)
  "The most pixels (width times height) an image may have: 16384 x 16384,
a gigabyte as RGBA, far past any texture a character wears.")

;;;# The library, raw (stb_image.h)

(defvar *stb-library-names* '("libstb.so.0")
  "Sonames tried, in order, for stb (the versioned name: the unversioned one
comes only with libstb-dev).")

(defvar *stb-library* nil
  "The CFFI library stb was loaded from, once loaded.")

(defun load-stb-library (file)
  "Make sure libstb is loaded, once.  Signals IMAGE-LIBRARY-MISSING about
FILE, naming the Debian package libstb0, when it is not installed."
  (or *stb-library*
      (setf *stb-library*
            (or (load-first-foreign-library *stb-library-names*)
                (error 'image-library-missing
                       :file file :package "libstb0"
                       :reason (format nil "decoding images needs stb_image, which is not installed: install the Debian package libstb0 (tried ~{~A~^, ~})"
                                       *stb-library-names*))))))

(cffi:defcfun ("stbi_load" %stbi-load) :pointer
  (filename :string) (x :pointer) (y :pointer) (channels-in-file :pointer) (desired-channels :int))
(cffi:defcfun ("stbi_load_from_memory" %stbi-load-from-memory) :pointer
  (buffer :pointer) (length :int) (x :pointer) (y :pointer) (channels-in-file :pointer) (desired-channels :int))
(cffi:defcfun ("stbi_image_free" %stbi-image-free) :void (pixels :pointer))
(cffi:defcfun ("stbi_failure_reason" %stbi-failure-reason) :pointer) ; read with C-MESSAGE
(cffi:defcfun ("stbi_info" %stbi-info) :int
  (filename :string) (x :pointer) (y :pointer) (channels-in-file :pointer))
(cffi:defcfun ("stbi_info_from_memory" %stbi-info-from-memory) :int
  (buffer :pointer) (length :int) (x :pointer) (y :pointer) (channels-in-file :pointer))

(defvar *stb-lock* (bt:make-lock "player stb_image")
  "Held around each use of stb_image: its failure reason is one global of the
library, which two threads decoding at once would each read as their own.")

;;;# Images, checked

(defstruct (image (:constructor make-image (width height channels pixels)))
  "A decoded image: WIDTH x HEIGHT pixels of CHANNELS bytes each (1 grey,
2 grey and alpha, 3 RGB, 4 RGBA), rows top to bottom in PIXELS."
  (width 0 :type (integer 1) :read-only t)
  (height 0 :type (integer 1) :read-only t)
  (channels 4 :type (integer 1 4) :read-only t)
  (pixels nil :type (simple-array (unsigned-byte 8) (*)) :read-only t))

(defun check-image-file (file)
  "FILE's native namestring when it is a regular, readable, non-empty file;
else an IMAGE-ERROR naming FILE.  Checked before stb sees it, so that a
folder, a FIFO or a device never reaches C."
  (let ((path (ignore-errors (probe-file file))))
    (unless path (image-fail file "the file does not exist"))
    (let ((name (sb-ext:native-namestring path)))
      (unless (ignore-errors (sb-posix:s-isreg (sb-posix:stat-mode (sb-posix:stat name))))
        (image-fail file "it is not a regular file"))
      (handler-case (with-input-file (in path :element-type '(unsigned-byte 8))
                      (when (zerop (file-length in))
                        (image-fail file "the file is empty")))
        (io-error (e) (image-fail file "the file cannot be read: ~A" (io-error-reason e))))
      name)))

(defun copy-stb-pixels (file pointer width height channels)
  "A fresh IMAGE of the WIDTH x HEIGHT x CHANNELS bytes at POINTER, which stb
returned for FILE; its size is checked before anything is copied."
  (unless (and (plusp width) (plusp height))
    (image-fail file "stb_image gave a size of ~Dx~D" width height))
  (when (> (* width height) *image-pixel-limit*)
    (image-fail file "it is ~Dx~D, more than ~:D pixels (*image-pixel-limit*)"
                width height *image-pixel-limit*))
  (let ((pixels (make-array (* width height channels) :element-type '(unsigned-byte 8))))
    (sb-sys:with-pinned-objects (pixels)
      (cffi:foreign-funcall "memcpy" :pointer (sb-sys:vector-sap pixels)
                                     :pointer pointer :size (length pixels) :pointer))
    (make-image width height channels pixels)))

(defun read-image (file &key (channels 4))
  "The IMAGE decoded from FILE (PNG, JPEG, TGA, BMP, whatever stb_image reads),
converted to CHANNELS bytes a pixel (1 to 4; 4 is RGBA), rows top to bottom.
Signals an IMAGE-ERROR naming FILE when it is missing, not a readable
non-empty regular file, not an image stb can decode (with stb's reason), or
more than *IMAGE-PIXEL-LIMIT* pixels; IMAGE-LIBRARY-MISSING when libstb0 is
not installed; an ARGUMENT-ERROR for CHANNELS outside 1 to 4."
  (check-argument 'read-image 'channels channels (lambda (x) (typep x '(integer 1 4))) "an integer from 1 to 4")
  (let ((name (check-image-file file)))
    (load-stb-library file)
    (bt:with-lock-held (*stb-lock*)
      (check-stb-header file name)
      (cffi:with-foreign-objects ((width :int) (height :int) (in-file :int))
        (let ((pointer (sb-int:with-float-traps-masked (:invalid :divide-by-zero :overflow :inexact)
                         (%stbi-load name width height in-file channels))))
          (when (cffi:null-pointer-p pointer)
            (image-fail file "stb_image cannot decode it: ~A"
                        (or (c-message (%stbi-failure-reason)) "no reason given")))
          ;; Freed whatever happens: a refused size must not leak the decoded pixels.
          (unwind-protect
               (copy-stb-pixels file pointer (cffi:mem-ref width :int) (cffi:mem-ref height :int) channels)
            (%stbi-image-free pointer)))))))

(defun check-image-size (file width height)
  "Refuse, as an IMAGE-ERROR naming FILE, a WIDTH x HEIGHT that stb gave and
that is no size or more than *IMAGE-PIXEL-LIMIT* pixels."
  (unless (and (plusp width) (plusp height))
    (image-fail file "stb_image gave a size of ~Dx~D" width height))
  (when (> (* width height) *image-pixel-limit*)
    (image-fail file "it is ~Dx~D, more than ~:D pixels (*image-pixel-limit*)"
                width height *image-pixel-limit*)))

(defun check-stb-header (file name)
  "Read only the header of the image NAME (FILE's native namestring) and refuse
it, as an IMAGE-ERROR naming FILE, when stb cannot tell its size or it is
more than *IMAGE-PIXEL-LIMIT* pixels: a huge image is refused before a byte
of it is decoded.  Called with *STB-LOCK* held."
  (cffi:with-foreign-objects ((width :int) (height :int) (in-file :int))
    (when (zerop (sb-int:with-float-traps-masked (:invalid :divide-by-zero :overflow :inexact)
                   (%stbi-info name width height in-file)))
      (image-fail file "stb_image cannot decode it: ~A" (or (c-message (%stbi-failure-reason)) "no reason given")))
    (check-image-size file (cffi:mem-ref width :int) (cffi:mem-ref height :int))))

;;;# Images in memory (textures embedded in a model file)

(defun decode-image-octets (octets file &key (channels 4))
  "The IMAGE decoded from OCTETS, the bytes of an image file (PNG, JPEG...)
that FILE names (a model's embedded texture), converted to CHANNELS bytes a
pixel.  stb is given the vector's own length, so it never reads past it; the
header is read first, so a huge image is refused before it is decoded.
Signals an IMAGE-ERROR naming FILE when OCTETS are empty, undecodable or
more than *IMAGE-PIXEL-LIMIT* pixels; IMAGE-LIBRARY-MISSING without libstb0."
  (check-type octets (simple-array (unsigned-byte 8) (*)))
  (when (zerop (length octets)) (image-fail file "it holds no bytes"))
  (unless (< (length octets) (expt 2 31))
    (image-fail file "it is ~:D bytes, more than stb_image reads" (length octets)))
  (load-stb-library file)
  (bt:with-lock-held (*stb-lock*)
    (cffi:with-foreign-objects ((width :int) (height :int) (in-file :int))
      (flet ((reason () (or (c-message (%stbi-failure-reason)) "no reason given")))
        (sb-sys:with-pinned-objects (octets)
          (let ((buffer (sb-sys:vector-sap octets)))
            (when (zerop (sb-int:with-float-traps-masked (:invalid :divide-by-zero :overflow :inexact)
                           (%stbi-info-from-memory buffer (length octets) width height in-file)))
              (image-fail file "stb_image cannot decode it: ~A" (reason)))
            (check-image-size file (cffi:mem-ref width :int) (cffi:mem-ref height :int))
            (let ((pointer (sb-int:with-float-traps-masked (:invalid :divide-by-zero :overflow :inexact)
                             (%stbi-load-from-memory buffer (length octets) width height in-file channels))))
              (when (cffi:null-pointer-p pointer)
                (image-fail file "stb_image cannot decode it: ~A" (reason)))
              (unwind-protect
                   (copy-stb-pixels file pointer (cffi:mem-ref width :int) (cffi:mem-ref height :int) channels)
                (%stbi-image-free pointer)))))))))

;;;# A model's textures

(defun embedded-texture-p (path)
  "Is PATH (a mesh's texture) one embedded in the model file, Assimp's \"*N\"?"
  (and (plusp (length path)) (char= (char path 0) #\*)))

(defun embedded-texture-result (model path)
  "The IMAGE of MODEL's embedded texture PATH (\"*N\"), or the IMAGE-ERROR
saying why there is none: undecodable, or N not one of its textures.
Re-signals IMAGE-LIBRARY-MISSING."
  (let* ((textures (model-embedded-textures model))
         (index (ignore-errors (parse-integer path :start 1)))
         (texture (and index (< -1 index (length textures)) (aref textures index))))
    (if texture
        (let ((result (embedded-texture-image texture)))
          (if (typep result 'image-library-missing) (error result) result))
        (make-condition 'image-error
                        :file (format nil "~A's embedded texture ~A" (model-file model) path)
                        :reason (format nil "the model embeds ~D texture~:P, not one numbered ~A"
                                        (length textures) (subseq path 1))))))

(defun mesh-texture-image (mesh &key (channels 4))
  "The IMAGE of MESH's texture: the one embedded in its model file, decoded at
import, or its texture file decoded now (CHANNELS bytes a pixel; an embedded
one is always RGBA).  Signals the IMAGE-ERROR saying why there is none."
  (let ((embedded (model-mesh-embedded-texture mesh)))
    (if embedded
        (let ((result (embedded-texture-image embedded)))
          (if (typep result 'condition) (error result) result))
        (read-image (model-mesh-texture mesh) :channels channels))))

(defun model-texture-images (model &key (channels 4))
  "For each distinct texture MODEL's meshes name, (PATH . RESULT): RESULT is
the IMAGE decoded from it (CHANNELS bytes a pixel; a texture embedded in the
model file, \"*N\", was decoded as RGBA at import), or the IMAGE-ERROR
saying why it could not be (missing, undecodable, too large), so a caller
finds every broken texture before a render starts instead of the first.
Signals IMAGE-LIBRARY-MISSING when libstb0 is not installed."
  (loop for path in (model-textures model)
        collect (cons path (if (embedded-texture-p path)
                               (embedded-texture-result model path)
                               (handler-case (read-image path :channels channels)
                                 (image-library-missing (condition) (error condition))
                                 (image-error (condition) condition))))))
