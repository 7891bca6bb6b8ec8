;;;; test-images.lisp -- texture images decoded by stb_image (src/model/images.lisp):
;;;; a PNG written by Player's own writer read back pixel for pixel, Debian's
;;;; test textures (PNG, JPEG, TGA, BMP) checked against the sizes their headers
;;;; state, bad files as one IMAGE-ERROR each, a model's textures, and
;;;; `bin/player model` printing texture sizes.

(in-package #:player-tests)

(def-suite* images :in player-tests)

(defmacro with-stb (&body body)
  "Run BODY when libstb0 is installed; else skip with a note."
  `(if (probe-file "/usr/lib/x86_64-linux-gnu/libstb.so.0")
       (progn ,@body)
       (skip "libstb0 is not installed: texture decoding not tested")))

(defmacro with-image-file ((path suffix) &body body)
  "Run BODY with PATH bound to the name of a fresh temporary file ending in
SUFFIX, deleted afterwards."
  `(uiop:with-temporary-file (:pathname ,path :type ,suffix :keep nil)
     ,@body))

(defun image-error-for (file &rest arguments)
  "The IMAGE-ERROR READ-IMAGE signals for FILE (ARGUMENTS passed on), or NIL
when it signals none."
  (handler-case (progn (apply #'player.model:read-image file arguments) nil)
    (player.model:image-error (condition) condition)))

(defun png-header-size (file)
  "The width and height a PNG FILE's IHDR chunk states, read here
independently of stb: two big-endian 32-bit numbers at byte 16."
  (with-open-file (in file :element-type '(unsigned-byte 8))
    (let ((bytes (make-array 24 :element-type '(unsigned-byte 8))))
      (read-sequence bytes in)
      (flet ((u32 (at) (reduce (lambda (a b) (+ (* a 256) b)) (subseq bytes at (+ at 4)))))
        (values (u32 16) (u32 20))))))

(defun file-command-size (file)
  "The size `file` reports for the image FILE, as a list (WIDTH HEIGHT): the
\"WxH\" before \", components\" for a JPEG (whose line states its density
first), else the first \"W x H\" (a BMP's line says \"3.x\" before it)."
  (let* ((line (uiop:run-program (list "file" "-b" (namestring file)) :output :string))
         (components (search ", components" line))
         (start (if components
                    (1+ (position #\Space line :end components :from-end t))
                    (1+ (position #\Space line :end (search " x " line) :from-end t)))))
    (multiple-value-bind (width end) (parse-integer line :start start :junk-allowed t)
      (list width (parse-integer line :start (1+ (position #\x line :start end)) :junk-allowed t)))))

(defmacro with-box-without-texture ((gltf) &body body)
  "Run BODY with GLTF bound to a copy of Debian's BoxTextured.gltf (and its
.bin) in a fresh folder that lacks the texture it names; the folder is
deleted afterwards."
  (let ((folder (gensym "FOLDER")))
    `(let ((,folder (uiop:ensure-directory-pathname
                     (merge-pathnames (format nil "player-box-~36R/" (random (expt 36 8)))
                                      (uiop:temporary-directory)))))
       (ensure-directories-exist ,folder)
       (unwind-protect
            (let ((,gltf (namestring (merge-pathnames "BoxTextured.gltf" ,folder))))
              (dolist (name '("BoxTextured.gltf" "BoxTextured.bin"))
                (uiop:copy-file (assimp-model (concatenate 'string "glTF/BoxTextured-glTF/" name))
                                (merge-pathnames name ,folder)))
              ,@body)
         (uiop:delete-directory-tree ,folder :validate t)))))

(test image-reads-back-players-own-png
  "Every pixel of a PNG written by Player's PNG writer comes back as written,
rows top to bottom, for RGBA and RGB."
  (with-stb
    (dolist (channels '(4 3))
      (let* ((width 7) (height 5)
             (pixels (make-array (* width height channels) :element-type '(unsigned-byte 8))))
        (dotimes (i (length pixels)) (setf (aref pixels i) (mod (* 37 (1+ i)) 256)))
        (with-image-file (path "png")
          (player.render:write-png path width height pixels :channels channels)
          (let ((image (player.model:read-image path :channels channels)))
            (is (= width (player.model:image-width image)))
            (is (= height (player.model:image-height image)))
            (is (= channels (player.model:image-channels image)))
            (is (typep (player.model:image-pixels image) '(simple-array (unsigned-byte 8) (*))))
            (is (equalp pixels (player.model:image-pixels image)))))))))

(test image-sizes-of-debian-test-textures
  "PNG, JPEG, TGA and BMP textures decode to the sizes their headers state."
  (with-stb
    (with-assimp-models
      (let ((png (assimp-model "glTF/BoxTextured-glTF/CesiumLogoFlat.png")))
        (let ((image (player.model:read-image png)))
          (is (equal (multiple-value-list (png-header-size png))
                     (list (player.model:image-width image) (player.model:image-height image))))
          (is (= (* 4 (player.model:image-width image) (player.model:image-height image))
                 (length (player.model:image-pixels image))))))
      (dolist (name '("LWO/LWO2/MappingModes/earthSpherical.jpg" "Collada/duckCM.tga" "LWO/LWO2/white.bmp"))
        (let ((file (assimp-model name)))
          (when (probe-file file)
            (let ((image (player.model:read-image file :channels 3)))
              (is (equal (file-command-size file)
                         (list (player.model:image-width image) (player.model:image-height image)))
                  "~A: file says ~A" name (file-command-size file))
              (is (= 3 (player.model:image-channels image))))))))))

(test image-bad-files-are-one-image-error
  "A missing file, a folder, an empty file, a text file renamed .png and a
truncated PNG each give one IMAGE-ERROR naming the file, never a crash."
  (with-stb
    (let ((condition (image-error-for "/nonexistent/texture.png")))
      (is (typep condition 'player.model:image-error))
      (is (search "/nonexistent/texture.png" (princ-to-string condition)))
      (is (search "does not exist" (princ-to-string condition))))
    (is (typep (image-error-for (uiop:temporary-directory)) 'player.model:image-error))
    (with-image-file (path "png")
      (is (search "empty" (princ-to-string (image-error-for path)))))
    (with-image-file (path "png")
      (with-open-file (out path :direction :output :if-exists :supersede)
        (write-line "This is not a picture, just some notes." out))
      (let ((condition (image-error-for path)))
        (is (typep condition 'player.model:image-error))
        (is (search (namestring path) (princ-to-string condition)))
        (is (search "stb_image cannot decode it: " (princ-to-string condition)))))
    (let ((octets (player.render:png-octets 16 16 (make-array (* 16 16 4) :element-type '(unsigned-byte 8)
                                                                           :initial-element 200))))
      (with-image-file (path "png")
        (with-open-file (out path :direction :output :if-exists :supersede :element-type '(unsigned-byte 8))
          (write-sequence octets out :end (floor (length octets) 2)))
        (let ((condition (image-error-for path)))
          (is (typep condition 'player.model:image-error))
          (is (search (namestring path) (princ-to-string condition))))))))

(test image-pixel-limit-is-refused
  "An image past *IMAGE-PIXEL-LIMIT* is refused with an IMAGE-ERROR, and a
CHANNELS outside 1 to 4 is an argument error before any file is read."
  (with-stb
    (with-image-file (path "png")
      (player.render:write-png path 8 8 (make-array (* 8 8 4) :element-type '(unsigned-byte 8)))
      (let ((player.model:*image-pixel-limit* 63))
        (is (search "more than 63 pixels" (princ-to-string (image-error-for path)))))
      (signals player.base:argument-error (player.model:read-image path :channels 5)))))

(test a-huge-image-is-refused-from-its-header
  "A grey PNG whose header states 20000 x 20000 pixels, over a 1 x 1 image's
data, is refused from its header alone, before stb_image decodes it: past
*IMAGE-PIXEL-LIMIT* (stb_image's own header check lets a grey image of up to
2^30 pixels through)."
  (with-stb
    (let ((octets (player.render:png-octets 1 1 (make-array 4 :element-type '(unsigned-byte 8)
                                                               :initial-element 0))))
      ;; Signature (8 bytes), IHDR's length and type (8), then width, height,
      ;; bit depth and colour type (0: grey).  stb_image reads no CRC.
      (flet ((put-u32 (at value)
               (loop for k from 0 below 4
                     do (setf (aref octets (+ at k)) (ldb (byte 8 (* 8 (- 3 k))) value)))))
        (put-u32 16 20000)
        (put-u32 20 20000)
        (setf (aref octets 24) 8 (aref octets 25) 0))
      (with-image-file (path "png")
        (with-open-file (out path :direction :output :if-exists :supersede :element-type '(unsigned-byte 8))
          (write-sequence octets out))
        (is (search "it is 20000x20000, more than" (princ-to-string (image-error-for path))))))))

(test model-texture-images-decodes-or-reports
  "A textured glTF's texture is decoded; a texture that is missing is
reported as an IMAGE-ERROR in its entry instead of signalled."
  (with-stb
    (with-assimp-models
      (let* ((gltf (assimp-model "glTF/BoxTextured-glTF/BoxTextured.gltf"))
             (entries (player.model:model-texture-images (player.model:import-model gltf))))
        (is (= 1 (length entries)))
        (is (search "CesiumLogoFlat.png" (car (first entries))))
        (is (typep (cdr (first entries)) 'player.model:image))
        (with-box-without-texture (copy)
          (let ((missing (player.model:model-texture-images (player.model:import-model copy))))
            (is (= 1 (length missing)))
            (is (typep (cdr (first missing)) 'player.model:image-error))
            (is (search "does not exist" (princ-to-string (cdr (first missing)))))))))))

(test model-command-prints-texture-sizes
  "`bin/player model` prints each texture's size, or marks it missing (an\nundecodable --texture is an error: test-tidy.lisp)."
  (with-stb
    (with-assimp-models
      (let* ((gltf (assimp-model "glTF/BoxTextured-glTF/BoxTextured.gltf"))
             (size (format nil "CesiumLogoFlat.png ~{~D~^x~}"
                           (multiple-value-list (png-header-size (assimp-model "glTF/BoxTextured-glTF/CesiumLogoFlat.png"))))))
        (multiple-value-bind (out err code) (player-command "model" gltf)
          (is (= 0 code) "exit ~D: ~A" code err)
          (is (search size out) "no ~S in~%~A" size out))
        (with-box-without-texture (copy)
          (let ((out (player-command "model" copy)))
            (is (search "CesiumLogoFlat.png (missing)" out) "~A" out)))))))
