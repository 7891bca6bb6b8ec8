;;;; test-embedded-textures.lisp -- textures a model file embeds
;;;; (src/model/embedded-textures.lisp): a .glb's and a data: URI's PNG
;;;; decoded to the same pixels as the PNG file they were made from, a
;;;; truncated one reported as one error (import still works), `bin/player
;;;; model` printing their sizes, and the glTF writer embedding them again.

(in-package #:player-tests)

(def-suite* embedded-textures :in player-tests)

(defparameter *embedded-box-files*
  '("glTF2/BoxTextured-glTF-Binary/BoxTextured.glb" "glTF2/BoxTextured-glTF-Embedded/BoxTextured.gltf")
  "Khronos's textured box with its PNG in the .glb's BIN chunk, and in a data: URI.")

(defun cesium-logo-image ()
  "The IMAGE of the PNG file the textured box embeds, decoded from the file."
  (player.model:read-image (assimp-model "glTF2/BoxTextured-glTF/CesiumLogoFlat.png")))

(defmacro with-truncated-box ((path) &body body)
  "Run BODY with PATH naming a copy of BoxTextured.glb whose image's buffer
view is cut from 2,433 bytes to 1,200 (same length of JSON, so the file
stays a valid .glb that Assimp reads): its PNG ends half way."
  `(uiop:with-temporary-file (:pathname ,path :type "glb" :keep nil)
     (let* ((octets (alexandria:read-file-into-byte-vector
                     (assimp-model "glTF2/BoxTextured-glTF-Binary/BoxTextured.glb")))
            (text (map 'string #'code-char octets))
            (at (search "\"byteLength\":2433}" text)))
       (assert at)
       (replace octets (map 'vector #'char-code "\"byteLength\":1200}") :start1 at)
       (alexandria:write-byte-vector-into-file octets ,path :if-exists :supersede)
       ,@body)))

(test embedded-textures-decode-like-their-file
  "The PNG a .glb or a .gltf embeds is decoded at import to the very pixels
of the PNG file it was made from, and the box's mesh names it \"*0\"."
  (with-stb
    (with-assimp-models
      (let ((logo (cesium-logo-image)))
        (dolist (name *embedded-box-files*)
          (let* ((model (player:import-model (assimp-model name)))
                 (textures (player.model:model-embedded-textures model))
                 (entries (player:model-texture-images model)))
            (is (= 1 (length textures)) "~A: ~D embedded textures" name (length textures))
            (is (equal "*0" (car (first entries))))
            (let ((image (cdr (first entries))))
              (is (typep image 'player:image) "~A: ~A" name image)
              (when (typep image 'player:image)
                (is (= 211 (player:image-width image) (player:image-height image)))
                (is (equalp (player:image-pixels logo) (player:image-pixels image))
                    "~A: the embedded PNG decodes to other pixels than the file" name)))
            (is (eq (aref textures 0)
                    (player.model:model-mesh-embedded-texture (first (player:model-meshes model)))))))))))

(test truncated-embedded-texture-is-one-error
  "A .glb whose embedded PNG is cut short imports, and its texture is one
IMAGE-ERROR naming the model's embedded texture *0 with stb's reason, which
`bin/player model` prints as undecodable."
  (with-stb
    (with-assimp-models
      (with-truncated-box (path)
        (let* ((model (player:import-model path))
               (result (cdr (first (player:model-texture-images model)))))
          (is (typep result 'player:image-error))
          (is (search "embedded texture *0" (princ-to-string result)) "~A" result)
          (signals player:image-error (player:mesh-texture-image (first (player:model-meshes model)))))
        (multiple-value-bind (out err code) (player-command "model" (namestring path))
          (is (= 0 code) "exit ~D: ~A" code err)
          (is (search "textures: *0 (undecodable: stb_image cannot decode it" out) "~A" out))))))

(test embedded-texture-model-prints-size
  "`bin/player model` prints an embedded texture's size."
  (with-stb
    (with-assimp-models
      (multiple-value-bind (out err code)
          (player-command "model" (assimp-model (first *embedded-box-files*)))
        (is (= 0 code) "exit ~D: ~A" code err)
        (is (search "textures: *0 211x211" out) "~A" out)))))

(test embedded-texture-written-back-to-gltf
  "Writing a model with an embedded texture embeds its PNG again: the file
read back holds a texture of the same pixels."
  (with-stb
    (with-assimp-models
      (uiop:with-temporary-file (:pathname path :type "glb" :keep nil)
        (player:write-gltf (player:import-model (assimp-model (first *embedded-box-files*))) path)
        (let ((image (cdr (first (player:model-texture-images (player:import-model path))))))
          (is (typep image 'player:image) "~A" image)
          (when (typep image 'player:image)
            (is (equalp (player:image-pixels (cesium-logo-image)) (player:image-pixels image)))))))))

(defun fake-ai-texture-result (width height data file-size)
  "The IMAGE (or IMAGE-ERROR) COPY-EMBEDDED-TEXTURE makes of an aiTexture
built here in C memory: WIDTH, HEIGHT and DATA (a pointer) as given, from a
model file of FILE-SIZE bytes."
  (cffi:with-foreign-object (texture '(:struct player.model::%ai-texture))
    (setf (cffi:foreign-slot-value texture '(:struct player.model::%ai-texture) 'player.model::width) width
          (cffi:foreign-slot-value texture '(:struct player.model::%ai-texture) 'player.model::height) height
          (cffi:foreign-slot-value texture '(:struct player.model::%ai-texture) 'player.model::data) data)
    (player.model:embedded-texture-image
     (player.model::copy-embedded-texture texture 0 file-size "/tmp/fake.glb"))))

(test embedded-texture-sizes-are-checked-before-reading
  "What Assimp says of an embedded texture is checked before its data is
read: a NULL pointer, a compressed length past the model file's size, raw
texels past *image-pixel-limit* are each an IMAGE-ERROR (the 4 bytes at the
pointer are never read past); 2x1 raw B G R A texels become RGBA."
  (with-stb
    (cffi:with-foreign-object (bytes :uint8 8)
      (loop for i below 8 for b in '(10 20 30 255 40 50 60 128) do (setf (cffi:mem-aref bytes :uint8 i) b))
      (flet ((reason (result) (and (typep result 'player:image-error) (player:image-error-reason result))))
        (is (search "Assimp gave no data" (reason (fake-ai-texture-result 100 0 (cffi:null-pointer) 1000))))
        (is (search "more than the whole model file's" (reason (fake-ai-texture-result 2000000000 0 bytes 1000))))
        (is (search "more than" (reason (fake-ai-texture-result 100000 100000 bytes 1000))))
        (is (search "stb_image cannot decode it" (reason (fake-ai-texture-result 8 0 bytes 1000))))
        (let ((image (fake-ai-texture-result 2 1 bytes 1000)))
          (is (typep image 'player:image))
          (when (typep image 'player:image)
            (is (equalp #(30 20 10 255 60 50 40 128) (player:image-pixels image)))))))))
