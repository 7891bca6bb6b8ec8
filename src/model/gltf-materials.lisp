;;;; gltf-materials.lisp -- a mesh's look in glTF: a material per distinct
;;;; texture, the texture file's bytes embedded in the buffer (with its MIME
;;;; type) so the written file stands alone, one sampler with mipmaps, and
;;;; a plain material (white, not metallic, fully rough) for a mesh without
;;;; a texture.
;;;;
;;;; glTF holds PNG and JPEG images only, so a texture of another kind (TGA,
;;;; BMP), or one missing or unreadable, is a MODEL-WRITE-ERROR naming it;
;;;; writing with :TEXTURES NIL gives every mesh the plain material instead.
;;;; A texture embedded in the imported file (Assimp's "*0") is written from
;;;; the bytes the import kept, under the same rule: PNG or JPEG, else an
;;;; error (raw texels, an undecodable texture).

(in-package #:player.model)

(defconstant +gltf-linear+ 9729 "A sampler's filter LINEAR.")
(defconstant +gltf-linear-mipmap-linear+ 9987 "A sampler's filter LINEAR_MIPMAP_LINEAR (trilinear).")
(defconstant +gltf-repeat+ 10497 "A sampler's wrap mode REPEAT.")

(defun image-mime-type (octets)
  "\"image/png\" or \"image/jpeg\" when OCTETS start as that kind of file does, else NIL."
  (flet ((starts-with (signature)
           (and (>= (length octets) (length signature))
                (every #'= signature octets))))
    (cond ((starts-with '(#x89 #x50 #x4E #x47 #x0D #x0A #x1A #x0A)) "image/png")
          ((starts-with '(#xFF #xD8 #xFF)) "image/jpeg"))))

(defun texture-octets (path)
  "The bytes of the texture file PATH and their MIME type; a MODEL-WRITE-ERROR
naming PATH when it cannot be read or is neither PNG nor JPEG."
  (let ((octets (handler-case (file-octets path)
                  (io-error (e) (write-fail "its texture ~A cannot be read: ~A" path (io-error-reason e))))))
    (values octets
            (or (image-mime-type octets)
                (write-fail "its texture ~A is neither PNG nor JPEG, the only images glTF holds" path)))))

(defun plain-material ()
  "The material of a mesh without a texture: white, not metallic, fully rough."
  (json-object "pbrMetallicRoughness" (json-object "baseColorFactor" '(1 1 1 1)
                                                   "metallicFactor" 0 "roughnessFactor" 1)))

(defun textured-material (texture)
  "The material whose base colour is the glTF texture TEXTURE (an index)."
  (json-object "pbrMetallicRoughness" (json-object "baseColorTexture" (json-object "index" texture)
                                                   "metallicFactor" 0 "roughnessFactor" 1)))

(defstruct (gltf-looks (:constructor make-gltf-looks (embed)) (:conc-name looks-))
  "The materials, textures and images of a file being made, newest first:
EMBED says whether texture files are embedded (else meshes get the plain
material); MATERIAL-OF maps a texture path (or NIL) to its material's index."
  (embed t :type boolean)
  (material-of (make-hash-table :test 'equal) :type hash-table)
  (materials '() :type list)
  (textures '() :type list)
  (images '() :type list))

(defun mesh-material (looks buffer mesh)
  "The index of MESH's material among LOOKS, made (with its texture's bytes
stored in BUFFER) when it is the first mesh to use it.  An embedded texture
is keyed by itself, a file by its path."
  (let ((key (and (looks-embed looks) (model-mesh-texture mesh)
                  (or (model-mesh-embedded-texture mesh)
                      (and (not (embedded-texture-p (model-mesh-texture mesh)))
                           (model-mesh-texture mesh))))))
    (or (gethash key (looks-material-of looks))
        (setf (gethash key (looks-material-of looks))
              (prog1 (length (looks-materials looks))
                (push (if key (textured-material (add-texture looks buffer key)) (plain-material))
                      (looks-materials looks)))))))

(defun embedded-texture-octets-checked (texture)
  "The bytes of the embedded TEXTURE and their MIME type; a MODEL-WRITE-ERROR
when it is not a PNG or JPEG file (raw texels, another format) or could not
be decoded at import."
  (let ((octets (embedded-texture-octets texture)))
    (when (typep (embedded-texture-image texture) 'condition)
      (write-fail "its embedded texture ~A cannot be decoded: ~A"
                  (embedded-texture-name texture) (embedded-texture-image texture)))
    (values octets
            (or (and octets (image-mime-type octets))
                (write-fail "its embedded texture ~A is neither PNG nor JPEG, the only images glTF holds"
                            (embedded-texture-name texture))))))

(defun add-texture (looks buffer source)
  "A new texture of LOOKS showing SOURCE, an image file's path or an
EMBEDDED-TEXTURE, its bytes stored in BUFFER; its index."
  (multiple-value-bind (octets mime-type) (if (stringp source)
                                              (texture-octets source)
                                              (embedded-texture-octets-checked source))
    (push (json-object "bufferView" (add-octets buffer octets) "mimeType" mime-type) (looks-images looks))
    (push (json-object "sampler" 0 "source" (1- (length (looks-images looks)))) (looks-textures looks))
    (1- (length (looks-textures looks)))))

(defun looks-members (looks)
  "The top-level members of a glTF document that LOOKS makes, as alternating keys and values."
  (list "materials" (reverse (looks-materials looks))
        "textures" (reverse (looks-textures looks))
        "images" (reverse (looks-images looks))
        "samplers" (and (looks-textures looks)
                        (list (json-object "magFilter" +gltf-linear+ "minFilter" +gltf-linear-mipmap-linear+
                                           "wrapS" +gltf-repeat+ "wrapT" +gltf-repeat+)))))
