;;;; embedded-textures.lisp -- textures a model file holds itself (a .glb's
;;;; images, a .gltf's data: URIs, an .fbx's embedded media): Assimp's
;;;; aiTexture array copied out of its scene, checked before a byte is read,
;;;; and decoded by stb_image (images.lisp) into the MODEL, so that the
;;;; meshes that name "*N" are drawn, summarised and written like any other.

(in-package #:player.model)

;;; What is checked, and why.  Assimp hands us a pointer and a length it took
;;; from the file: a compressed texture's MWIDTH is a byte count, a raw one's
;;; MWIDTH x MHEIGHT a texel count.  We cannot ask C how much it allocated, so
;;; a length is believed only when it could be true: the bytes of a file
;;; embedded in the model cannot outnumber the model file's own, and a raw
;;; texture is within *IMAGE-PIXEL-LIMIT*.  A NULL data pointer is refused
;;; before it is read.  A texture that fails is not a failed import: its
;;; EMBEDDED-TEXTURE holds the IMAGE-ERROR, which `check`, `model` and the
;;; renderer report as they report a broken texture file.

(defmethod print-object ((texture embedded-texture) stream)
  (print-unreadable-object (texture stream :type t)
    (let ((image (embedded-texture-image texture)))
      (format stream "~A ~:[undecodable~;~:*~Dx~D~]" (embedded-texture-name texture)
              (and (typep image 'image) (image-width image)) (and (typep image 'image) (image-height image))))))

(defun embedded-texture-file (path index)
  "What an error about the INDEXth texture embedded in the model PATH calls it."
  (format nil "~A's embedded texture *~D" (file-namestring path) index))

(defun texture-format-hint (texture)
  "The aiTexture TEXTURE's format hint (\"png\", \"jpg\"...), at most 8 characters."
  (let ((hint (cffi:foreign-slot-pointer texture '(:struct %ai-texture) 'format-hint)))
    (coerce (loop for i below 8
                  for code = (cffi:mem-aref hint :uint8 i)
                  until (zerop code)
                  collect (code-char (min code 127)))
            'string)))

(defun copy-foreign-octets (pointer count)
  "A fresh octet vector of the COUNT bytes at POINTER."
  (let ((octets (make-array count :element-type '(unsigned-byte 8))))
    (sb-sys:with-pinned-objects (octets)
      (cffi:foreign-funcall "memcpy" :pointer (sb-sys:vector-sap octets)
                                     :pointer pointer :size count :pointer))
    octets))

(defun texels-image (pointer width height)
  "The RGBA IMAGE of the WIDTH x HEIGHT aiTexels (B G R A bytes) at POINTER."
  (let ((pixels (copy-foreign-octets pointer (* 4 width height))))
    (loop for i from 0 below (length pixels) by 4
          do (rotatef (aref pixels i) (aref pixels (+ i 2))))
    (make-image width height 4 pixels)))

(defun copy-embedded-texture (texture index file-size file)
  "The EMBEDDED-TEXTURE \"*INDEX\" copied from the aiTexture TEXTURE of the
model FILE, FILE-SIZE bytes long; its IMAGE is the IMAGE-ERROR saying why it
cannot be decoded, when it cannot."
  (let* ((width (cffi:foreign-slot-value texture '(:struct %ai-texture) 'width))
         (height (cffi:foreign-slot-value texture '(:struct %ai-texture) 'height))
         (data (cffi:foreign-slot-value texture '(:struct %ai-texture) 'data))
         (name (format nil "*~D" index))
         (label (embedded-texture-file file index))
         (octets nil))
    (flet ((refuse (control &rest arguments)
             (make-embedded-texture name nil (make-condition 'image-error :file label
                                                                          :reason (apply #'format nil control arguments)))))
      (cond ((cffi:null-pointer-p data) (refuse "Assimp gave no data for it"))
            ((zerop width) (refuse "it holds no bytes"))
            ((and (zerop height) (> width file-size))
             (refuse "it claims ~:D bytes, more than the whole model file's ~:D" width file-size))
            ((and (plusp height) (> (* width height) *image-pixel-limit*))
             (refuse "it is ~Dx~D, more than ~:D pixels (*image-pixel-limit*)" width height *image-pixel-limit*))
            (t
             (when (zerop height) (setf octets (copy-foreign-octets data width)))
             (make-embedded-texture
              name octets
              (handler-case (if octets
                                (decode-image-octets octets label :channels 4)
                                (texels-image data width height))
                (image-error (condition) condition))))))))

(defun copy-embedded-textures (textures path)
  "The EMBEDDED-TEXTUREs copied from TEXTURES, the aiTexture pointers of the
scene imported from PATH, as a vector (empty when the file embeds none)."
  (let ((file-size (with-input-file (in path :element-type '(unsigned-byte 8)) (file-length in))))
    (coerce (loop for texture in textures
                  for index from 0
                  collect (copy-embedded-texture texture index file-size (namestring path)))
            'simple-vector)))

(defun attach-embedded-textures (meshes textures)
  "Give each of MESHES whose texture is \"*N\" the Nth of TEXTURES (when there
is one: a number past them is reported by MODEL-TEXTURE-IMAGES)."
  (dolist (mesh meshes meshes)
    (let* ((path (model-mesh-texture mesh))
           (index (and path (embedded-texture-p path) (ignore-errors (parse-integer path :start 1)))))
      (when (and index (< -1 index (length textures)))
        (setf (model-mesh-embedded-texture mesh) (aref textures index))))))
