;;;; test-gltf-write.lisp -- WRITE-GLTF (src/model/gltf-*.lisp): Assimp's test
;;;; models written as .glb and .gltf and imported back through IMPORT-MODEL,
;;;; which must give the same model; the written files checked by two readers
;;;; that are not Player's: `assimp info` (its counts) and
;;;; t/fixtures/check-gltf.py (the structure the specification asks for);
;;;; bad models and unwritable places refused with a MODEL-ERROR and the file
;;;; that was there left alone.  Debian's assimp-testmodels and assimp-utils
;;;; must be installed (else the tests skip with a note, see WITH-ASSIMP-MODELS).

(in-package #:player-tests)

(def-suite* gltf-write :in player-tests)

(defparameter *gltf-round-trip-models*
  '("X/Testwuson.X" "glTF2/simple_skin/simple_skin.gltf" "X/BCN_Epileptic.X")
  "Models written and read back: a skinned .x with 3 clips, a skinned glTF,
and a .x of 3 meshes skinned by different bones.")

(defparameter *round-trip-tolerance* 1d-6
  "How far a number read back may be from the one written: the file holds
32-bit floats, which are what Assimp gave the model in the first place.")

(defmacro with-gltf-directory ((directory) &body body)
  "Run BODY with DIRECTORY bound to a fresh, empty folder (a pathname), removed afterwards."
  `(let ((,directory (pathname (format nil "/tmp/player-test-gltf-~D-~36R/" (sb-posix:getpid) (random (expt 36 6))))))
     (ensure-directories-exist ,directory)
     (unwind-protect (progn ,@body)
       (uiop:delete-directory-tree ,directory :validate t :if-does-not-exist :ignore))))

(defun read-back-near (a b)
  "Are the numbers A and B within *ROUND-TRIP-TOLERANCE* of each other?"
  (<= (abs (- a b)) *round-trip-tolerance*))

(defun vectors-near (a b)
  "Are the vectors A and B of one length and near element by element?"
  (and (= (length a) (length b)) (every #'read-back-near a b)))

(defun quaternions-near (a b &key (start 0))
  "Are the quaternions at START of A and B near as rotations: each made unit
length first (the writer normalises them, as glTF asks, and Assimp's are off
by up to 2e-4 in simple_skin.gltf), q and -q being one rotation."
  (flet ((unit (q)
           (let ((norm (sqrt (loop for k from start below (+ start 4) sum (expt (aref q k) 2)))))
             (loop for k from start below (+ start 4) collect (/ (aref q k) norm)))))
    (let ((p (unit a)) (q (unit b)))
      (or (every #'read-back-near p q) (every #'read-back-near p (mapcar #'- q))))))

(defun key-rotations-near (a b)
  "Are the rotation keys A and B (w x y z each) of one length and near key by key?"
  (and (= (length a) (length b))
       (loop for start from 0 below (length a) by 4
             always (quaternions-near a b :start start))))

;;;# Reading the written file back

(defun reread-joints (model)
  "MODEL's joints as written, without the node Assimp adds: a glTF scene with
several root nodes (the skeleton's root and the mesh nodes beside it, which
WRITE-GLTF keeps at the root) is imported under a made-up \"ROOT\" node,
which, being above every joint, becomes joint 0.  So that joint is dropped and
the others' parents shifted; every other joint must then come back in order."
  (let ((joints (player:model-joints model)))
    (if (and (plusp (length joints)) (string= "ROOT" (player:joint-name (aref joints 0))))
        (map 'vector (lambda (joint)
                       (player:make-joint (player:joint-name joint)
                                          (let ((parent (player:joint-parent joint)))
                                            (and parent (plusp parent) (1- parent)))
                                          (player:joint-translation joint) (player:joint-rotation joint)
                                          (player:joint-scale joint) (player:joint-inverse-bind joint)))
             (subseq joints 1))
        joints)))

(defun vertex-weights (model mesh vertex)
  "The joint names and weights that move VERTEX of MESH, as an alist sorted by name."
  (sort (loop for slot from (* 4 vertex) below (* 4 (1+ vertex))
              for weight = (aref (player:model-mesh-weights mesh) slot)
              when (plusp weight)
                collect (cons (player:joint-name (aref (player:model-joints model) (aref (player:model-mesh-joints mesh) slot)))
                              weight))
        #'string< :key #'car))

(defun weights-near (a b)
  "Are the alists A and B of joint names and weights alike, the weights near?"
  (and (= (length a) (length b))
       (every (lambda (x y) (and (string= (car x) (car y)) (read-back-near (cdr x) (cdr y)))) a b)))

(defun check-meshes-read-back (name original reread)
  "Each mesh of REREAD (a model read back) against ORIGINAL's: counts, positions, UVs, skin weights."
  (is (= (length (player:model-meshes original)) (length (player:model-meshes reread))) "~A: meshes" name)
  (loop for mesh in (player:model-meshes original)
        for back in (player:model-meshes reread)
        for what = (format nil "~A, mesh ~S" name (player:model-mesh-name mesh))
        do (is (= (player:model-mesh-vertex-count mesh) (player:model-mesh-vertex-count back)) "~A: vertices" what)
           (is (= (player:model-mesh-triangle-count mesh) (player:model-mesh-triangle-count back)) "~A: triangles" what)
           (is (equalp (player:model-mesh-triangles mesh) (player:model-mesh-triangles back)) "~A: triangle indices" what)
           (is (vectors-near (player:model-mesh-positions mesh) (player:model-mesh-positions back)) "~A: positions" what)
           (is (or (null (player:model-mesh-uvs mesh)) (vectors-near (player:model-mesh-uvs mesh) (player:model-mesh-uvs back)))
               "~A: UVs (glTF's V runs down, Assimp's up)" what)
           (is (= (length (player:model-mesh-bones mesh)) (length (player:model-mesh-bones back))) "~A: bones" what)
           (when (player:model-mesh-weights mesh)
             (is (loop for vertex below (player:model-mesh-vertex-count mesh)
                       always (weights-near (vertex-weights original mesh vertex) (vertex-weights reread back vertex)))
                 "~A: a vertex moved by other joints or weights" what))))

(defun check-joints-read-back (name original reread)
  "REREAD's joints against ORIGINAL's: names and parents in order, rest transforms."
  (let ((joints (player:model-joints original))
        (back (reread-joints reread)))
    (is (equal (map 'list #'player:joint-name joints) (map 'list #'player:joint-name back)) "~A: joint names" name)
    (is (equal (map 'list #'player:joint-parent joints) (map 'list #'player:joint-parent back)) "~A: joint parents" name)
    (when (= (length joints) (length back))
      (loop for joint across joints
            for other across back
            do (is (and (vectors-near (player:joint-translation joint) (player:joint-translation other))
                        (quaternions-near (player:joint-rotation joint) (player:joint-rotation other))
                        (vectors-near (player:joint-scale joint) (player:joint-scale other)))
                   "~A: the rest transform of ~A" name (player:joint-name joint))
               ;; Row-major in the model, column-major in the file: a missed transpose shows here.
               (is (equalp (and (player:joint-inverse-bind joint) t) (and (player:joint-inverse-bind other) t))
                   "~A: ~A is a bone on one side only" name (player:joint-name joint))
               (when (and (player:joint-inverse-bind joint) (player:joint-inverse-bind other))
                 (is (vectors-near (player:joint-inverse-bind joint) (player:joint-inverse-bind other))
                     "~A: the inverse bind matrix of ~A" name (player:joint-name joint)))))))

(defun channel-of (model animation joint-name)
  "The channel of ANIMATION (of MODEL) that animates the joint called JOINT-NAME, or NIL."
  (find joint-name (player:model-animation-channels animation)
        :key (lambda (channel) (player:joint-name (aref (player:model-joints model) (player:channel-joint channel))))
        :test #'string=))

(defun check-animations-read-back (name original reread)
  "REREAD's clips against ORIGINAL's: names, durations, and each channel's
keys where the original has keys (Assimp adds a rest key for a path a glTF
channel does not animate)."
  (is (= (length (player:model-animations original)) (length (player:model-animations reread))) "~A: clips" name)
  (loop for clip in (player:model-animations original)
        for back in (player:model-animations reread)
        do (is (string= (player:model-animation-name clip) (player:model-animation-name back)) "~A: clip names" name)
           (is (read-back-near (player:model-animation-duration clip) (player:model-animation-duration back))
               "~A: ~S lasts ~A s, read back ~A s" name (player:model-animation-name clip)
               (player:model-animation-duration clip) (player:model-animation-duration back))
           (dolist (channel (player:model-animation-channels clip))
             (let* ((joint (player:joint-name (aref (player:model-joints original) (player:channel-joint channel))))
                    (other (channel-of reread back joint)))
               (is (not (null other)) "~A: ~A is not animated when read back" name joint)
               (when other
                 (loop for (times values near) in `((,#'player:channel-position-times ,#'player:channel-positions ,#'vectors-near)
                                                    (,#'player:channel-rotation-times ,#'player:channel-rotations ,#'key-rotations-near)
                                                    (,#'player:channel-scale-times ,#'player:channel-scales ,#'vectors-near))
                       when (plusp (length (funcall times channel)))
                         do (is (and (vectors-near (funcall times channel) (funcall times other))
                                     (funcall near (funcall values channel) (funcall values other)))
                                "~A: the keys of ~A in ~S" name joint (player:model-animation-name clip))))))))

(defun written-files (directory name)
  "The .glb and .gltf paths in DIRECTORY for the model NAME."
  (let ((base (pathname-name name)))
    (list (namestring (merge-pathnames (format nil "~A.glb" base) directory))
          (namestring (merge-pathnames (format nil "~A.gltf" base) directory)))))

(test written-models-read-back-the-same
  (with-assimp-models
    (with-gltf-directory (directory)
      (dolist (name (sweep-sample *gltf-round-trip-models* 2))
        (let ((original (player:import-model (assimp-model name))))
          (dolist (file (written-files directory name))
            (player:write-gltf original file)
            (let ((reread (player:import-model file))
                  (what (format nil "~A as ~A" name (pathname-type file))))
              (check-joints-read-back what original reread)
              (check-meshes-read-back what original reread)
              (check-animations-read-back what original reread))))))))

;;;# Readers that are not Player's

(test assimp-info-counts-the-written-files
  ;; `assimp info -r` reads the file without post-processing, so its vertices
  ;; are exactly the ones written; the counts must be the model's.
  (with-assimp-models
    (with-gltf-directory (directory)
      (dolist (name (sweep-sample *gltf-round-trip-models* 2))
        (let ((model (player:import-model (assimp-model name))))
          (dolist (file (written-files directory name))
            (player:write-gltf model file)
            (let ((info (assimp-info-counts file :raw t)))
              (is (eql (length (player:model-meshes model)) (getf info :meshes)) "~A: meshes" file)
              (is (eql (player:model-vertex-count model) (getf info :vertices)) "~A: vertices" file)
              (is (eql (player:model-triangle-count model) (getf info :faces)) "~A: faces" file)
              (is (eql (player:model-bone-count model) (getf info :bones)) "~A: bones" file)
              (is (eql (length (player:model-animations model)) (getf info :animations)) "~A: animations" file)
              (is (eql (channel-count model) (getf info :channels)) "~A: channels" file))))))))

(defun python-program ()
  "The python3 program, or NIL."
  (player.base:find-executable "python3"))

(defun check-gltf-output (&rest files)
  "What t/fixtures/check-gltf.py prints about FILES, and its exit code."
  (let ((out (make-string-output-stream)))
    (let ((process (sb-ext:run-program (python-program)
                                       (cons (namestring (checkout-file "t/fixtures/check-gltf.py")) files)
                                       :output out :error out :search nil)))
      (values (get-output-stream-string out) (sb-ext:process-exit-code process)))))

(defmacro with-python (&body body)
  "Run BODY when python3 is there; else skip with a note."
  `(if (python-program)
       (progn ,@body)
       (skip "no python3: the written glTF files are not checked by t/fixtures/check-gltf.py")))

(test written-files-pass-the-structural-check
  ;; To see this fail: store the inverse bind matrices row-major (drop
  ;; COLUMN-MAJOR in INVERSE-BIND-SINGLES), or leave out POSITION's :BOUNDS in
  ;; MESH-ATTRIBUTES; check-gltf.py names the skin or the accessor.
  (with-assimp-models
    (with-python
      (with-gltf-directory (directory)
        (dolist (name (sweep-sample *gltf-round-trip-models* 2))
          (let ((model (player:import-model (assimp-model name))))
            (dolist (file (written-files directory name))
              (player:write-gltf model file)
              (multiple-value-bind (output code) (check-gltf-output file)
                (is (eql 0 code) "check-gltf.py refuses ~A:~%~A" file output)))))))))

(defun replace-once (text old new)
  "TEXT with its first OLD replaced by NEW (OLD must be there)."
  (let ((start (search old text)))
    (assert start () "no ~S in the text" old)
    (concatenate 'string (subseq text 0 start) new (subseq text (+ start (length old))))))

(test the-structural-check-can-fail
  "check-gltf.py is no rubber stamp: a written file broken in ways a writer
could break it (an accessor past its view, a child out of range, a .glb's
length off by 4) is refused."
  (with-assimp-models
    (with-python
      (with-gltf-directory (directory)
        (let* ((model (player:import-model (assimp-model "glTF2/simple_skin/simple_skin.gltf")))
               (good (namestring (merge-pathnames "good.gltf" directory)))
               (glb (namestring (merge-pathnames "good.glb" directory))))
          (player:write-gltf model good)
          (player:write-gltf model glb)
          (let ((text (alexandria:read-file-into-string good)))
            (loop for (label old new) in '(("an accessor's count too large" "\"count\":" "\"count\":1000")
                                           ("a child that is no node" "\"children\":[" "\"children\":[99,"))
                  for broken = (namestring (merge-pathnames (format nil "broken-~D.gltf" (length label)) directory))
                  do (alexandria:write-string-into-file (replace-once text old new) broken)
                     (is (eql 1 (nth-value 1 (check-gltf-output broken))) "check-gltf.py passes ~A" label)))
          (let ((octets (alexandria:read-file-into-byte-vector glb))
                (broken (namestring (merge-pathnames "broken.glb" directory))))
            (setf (aref octets 8) (mod (+ 4 (aref octets 8)) 256)) ; the header's total length, low byte
            (alexandria:write-byte-vector-into-file octets broken)
            (is (eql 1 (nth-value 1 (check-gltf-output broken))) "check-gltf.py passes a wrong .glb length")))))))

;;;# Textures

(test a-png-texture-is-embedded
  (with-assimp-models
    (with-gltf-directory (directory)
      (let* ((texture (assimp-model "glTF2/BoxTextured-glTF/CesiumLogoFlat.png"))
             (model (player:import-model (assimp-model "glTF2/BoxTextured-glTF/BoxTextured.gltf")))
             (file (namestring (merge-pathnames "box.glb" directory))))
        (is (equal (list texture) (player:model-textures model)))
        (player:write-gltf model file)
        (is (equal '("*0") (player:model-textures (player:import-model file)))
            "the texture is not embedded in the .glb")
        (let ((octets (alexandria:read-file-into-byte-vector texture))
              (written (alexandria:read-file-into-byte-vector file)))
          (is (search octets written) "the .glb does not hold the PNG's bytes"))
        (when (python-program)
          (multiple-value-bind (output code) (check-gltf-output file)
            (is (eql 0 code) "~A" output)))
        (player:write-gltf model file :textures nil)
        (is (null (player:model-textures (player:import-model file))) ":textures nil still wrote the texture")))))

(test a-texture-glTF-cannot-hold-is-refused
  (with-assimp-models
    (with-gltf-directory (directory)
      (let* ((tga (assimp-model "X/bottom.tga"))
             (model (player:import-model (assimp-model "X/Testwuson.X") :texture tga))
             (e (handler-case (player:write-gltf model (merge-pathnames "wuson.glb" directory))
                  (player:model-error (e) e))))
        (is (typep e 'player:model-write-error))
        (is (and e (search "bottom.tga is neither PNG nor JPEG" (princ-to-string e))) "~A" e)))))

;;;# Bad models and places

(defun tiny-model (&key (time 0.5d0) (value 1d0))
  "A model of two joints and one clip whose second translation key is at TIME with x VALUE."
  (flet ((doubles (&rest xs) (coerce xs 'player.model::double-vector)))
    (player:make-model "tiny" '()
                       (vector (player:make-joint "hips" nil (doubles 0d0 1d0 0d0) (doubles 1d0 0d0 0d0 0d0) (doubles 1d0 1d0 1d0) nil)
                               (player:make-joint "head" 0 (doubles 0d0 0.5d0 0d0) (doubles 1d0 0d0 0d0 0d0) (doubles 1d0 1d0 1d0) nil))
                       (list (player:make-model-animation "nod" 1d0
                                                    (list (player:make-channel 1 (doubles 0d0 time) (doubles 0d0 0d0 0d0 value 0d0 0d0)
                                                                               (doubles) (doubles) (doubles) (doubles))))))))

(defun write-error (model file)
  "The MODEL-ERROR writing MODEL to FILE signals, or NIL."
  (handler-case (progn (player:write-gltf model file) nil)
    (player:model-error (e) e)))

(test a-model-that-is-not-finite-is-refused
  (with-gltf-directory (directory)
    (let ((file (namestring (merge-pathnames "tiny.glb" directory))))
      (is (null (write-error (tiny-model) file)) "the tiny model is writable")
      (let ((nan (sb-int:with-float-traps-masked (:invalid)
                   ;; NOTINLINE: folded at compile time, the NaN would trap there.
                   (locally (declare (notinline -))
                     (- sb-ext:double-float-positive-infinity sb-ext:double-float-positive-infinity)))))
        (dolist (bad (list (tiny-model :value nan) (tiny-model :value sb-ext:double-float-positive-infinity)
                           (tiny-model :time nan) (tiny-model :value 1d300)))
          (let ((e (write-error bad file)))
            (is (typep e 'player:model-write-error))
            (is (and e (search "tiny.glb" (princ-to-string e)))))))
      (let ((e (write-error (tiny-model :time 0d0) file)))
        (is (and e (search "not strictly increasing" (princ-to-string e))) "~A" e)))))

(test a-model-whose-parts-disagree-is-refused
  (with-gltf-directory (directory)
    (let ((file (merge-pathnames "bad.gltf" directory))
          (model (tiny-model)))
      (setf (player:joint-parent (aref (player:model-joints model) 0)) 1)
      (is (search "not a joint before it" (princ-to-string (write-error model file)))))
    (let ((e (write-error (tiny-model) (merge-pathnames "tiny.obj" directory))))
      (is (and e (search "ends in .glb (binary) or .gltf (text), not .obj" (princ-to-string e)))))))

(test an-unwritable-place-is-a-model-error-naming-it
  (with-gltf-directory (directory)
    (let* ((file-as-folder (merge-pathnames "plain-file" directory))
           (file (namestring (merge-pathnames "plain-file/tiny.glb" directory))))
      (alexandria:write-string-into-file "not a folder" file-as-folder)
      (let ((e (write-error (tiny-model) file)))
        (is (typep e 'player:model-write-error))
        (is (and e (search file (princ-to-string e))) "~A" e)))
    (let ((e (write-error (tiny-model) "/nonexistent-folder/tiny.gltf")))
      (is (and e (search "/nonexistent-folder/tiny.gltf" (princ-to-string e))) "~A" e))
    ;; A folder without write permission stops everyone but root.
    (let ((locked (merge-pathnames "locked/" directory)))
      (ensure-directories-exist locked)
      (sb-posix:chmod (namestring locked) #o555)
      (unwind-protect
           (unless (zerop (sb-posix:geteuid))
             (let ((e (write-error (tiny-model) (merge-pathnames "tiny.glb" locked))))
               (is (and e (search "Permission denied" (princ-to-string e))) "~A" e)))
        (sb-posix:chmod (namestring locked) #o755)))))

(test a-failed-write-leaves-the-old-file
  (with-gltf-directory (directory)
    (let ((file (namestring (merge-pathnames "precious.glb" directory)))
          (folder-named-like-a-file (merge-pathnames "folder.glb/" directory)))
      (alexandria:write-string-into-file "the old file" file)
      ;; Refused before a byte is written: a number that is not finite.
      (is (write-error (tiny-model :value sb-ext:double-float-positive-infinity) file))
      (is (string= "the old file" (alexandria:read-file-into-string file)))
      ;; Refused before anything is written: a folder stands where the file
      ;; should go.  It stays, and so does nothing else.
      (ensure-directories-exist folder-named-like-a-file)
      (let ((e (write-error (tiny-model) (merge-pathnames "folder.glb" directory))))
        (is (and e (search "it is a directory" (princ-to-string e))) "~A" e))
      (is (probe-file folder-named-like-a-file))
      (is (equal '("folder.glb" "precious.glb")
                 (uiop:run-program (list "ls" "-A" (namestring directory)) :output :lines))
          "a temporary file was left behind")
      ;; And a write that succeeds replaces the old file whole.
      (player:write-gltf (tiny-model) file)
      (is (equalp #(#x67 #x6C #x54 #x46) (subseq (alexandria:read-file-into-byte-vector file) 0 4))))))

;;;# The JSON writer

(test json-text-is-rfc-8259
  (flet ((json (value) (player.model::json-text value)))
    (is (string= "{\"a\":[1,2.5,\"x\"],\"c\":true}"
                 (json (player.model::json-object "a" (list 1 2.5d0 "x") "b" nil "c" :true))))
    (is (string= "\"q\\\"b\\\\n\\nt\\tc\\u0001é\"" (json (format nil "q\"b\\n~Ct~Cc~Cé" #\Newline #\Tab (code-char 1)))))
    (is (string= "[1.0e-7,1.0e21,-0.0,0.1]" (json (vector 1d-7 1d21 -0d0 0.1))))
    (is (typep (handler-case (json (list sb-ext:single-float-positive-infinity))
                 (player:model-error (e) e))
               'player:model-write-error))))
