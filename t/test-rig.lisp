;;;; test-rig.lisp -- imported models as Player characters (src/rig/): the
;;;; skeleton and placement made of a model, clips sampled against the file's
;;;; own keys, linear-blend skinning against an independent reference built
;;;; from the model's matrices, live cross-fades, and the (model ...) library
;;;; form and :clip items with their errors.

(in-package #:player-tests)

(def-suite* rig :in player-tests)

(defvar *wuson-skeleton* nil "Testwuson.X made a skeleton 0.8 m tall, once.")

(defun wuson-skeleton ()
  "Testwuson.X as a Player skeleton 0.8 m tall (made once)."
  (or *wuson-skeleton*
      (setf *wuson-skeleton*
            (player.rig:model-skeleton (player:import-model (assimp-model "X/Testwuson.X")) :height 0.8))))

(defun random-unit-quat (state)
  "A random unit quaternion (uniform enough for a round trip) from the random STATE."
  (player.body::qnormalize
   (player.body::make-quat (- (random 2d0 state) 1) (- (random 2d0 state) 1)
                           (- (random 2d0 state) 1) (- (random 2d0 state) 1))))

(defun quat-distance (a b)
  "The angle in radians between the rotations of unit quats A and B."
  (player.body::quat-angle a b))

(defun xyz-rotation (a b c)
  "Rx(A) Ry(B) Rz(C), degrees, as a quat: how an imported joint composes its DOFs."
  (flet ((about (x y z degrees)
           (player.body::quat-from-axis-angle (player.body::vec3 x y z) (* degrees (/ pi 180)))))
    (player.body::q* (player.body::q* (about 1d0 0d0 0d0 a) (about 0d0 1d0 0d0 b))
                     (about 0d0 0d0 1d0 c))))

(test euler-decomposition-recomposes
  (let ((state (sb-ext:seed-random-state 26)))
    (dotimes (i 2000)
      (let ((q (random-unit-quat state)))
        (multiple-value-bind (a b c) (player.rig:quat-to-xyz-degrees q)
          (is (< (quat-distance q (xyz-rotation a b c)) 1d-9)
              "~A decomposed to ~A ~A ~A does not recompose" q a b c)
          (is (<= -90 b 90)))))
    ;; Gimbal lock: the middle angle at 90 degrees.
    (let ((q (xyz-rotation 30 90 0)))
      (multiple-value-bind (a b c) (player.rig:quat-to-xyz-degrees q)
        (is (< (quat-distance q (xyz-rotation a b c)) 1d-7))))))

(test model-skeleton-stands-on-the-floor-at-its-height
  (with-assimp-models
    (let* ((skeleton (wuson-skeleton))
           (rig (player.body:skeleton-rig skeleton))
           (model (player.rig:rig-model rig))
           (bounds (player.rig:rig-bounds rig)))
      (is (= (length (player:model-joints model)) (length (player.body:skeleton-joints skeleton))))
      (is (< (abs (player.body:vec3-y (car bounds))) 1d-6) "the bind pose stands on y = 0")
      (is (< (abs (- (player.body:vec3-y (cdr bounds)) 0.8d0)) 1d-6) "the bind pose is 0.8 m tall")
      (is (< (abs (+ (player.body:vec3-x (car bounds)) (player.body:vec3-x (cdr bounds)))) 1d-6)
          "centred on x = 0")
      (is (equal '("wuson-bind" "wuson-run" "wuson-walk") (player.rig:rig-clip-names rig)))
      ;; Every joint turns about x, y and z, +-180 degrees.
      (is (every (lambda (joint) (= 3 (length (player.body::body-joint-dofs joint))))
                 (player.body:skeleton-joints skeleton))))))

(defun channel-rotation-at (channel time)
  "CHANNEL's rotation keys slerped at TIME (held outside them), as a quat:
the test's own sampling of the file's keys."
  (let* ((times (player:channel-rotation-times channel))
         (values (player:channel-rotations channel))
         (n (length times)))
    (flet ((key (i) (player.body::make-quat (aref values (* 4 i)) (aref values (+ (* 4 i) 1))
                                            (aref values (+ (* 4 i) 2)) (aref values (+ (* 4 i) 3)))))
      (cond ((<= time (aref times 0)) (key 0))
            ((>= time (aref times (1- n))) (key (1- n)))
            (t (let ((i (loop for i from 0 while (<= (aref times (1+ i)) time) finally (return i))))
                 (player.body::qslerp (key i) (key (1+ i))
                                      (/ (- time (aref times i)) (- (aref times (1+ i)) (aref times i))))))))))

(defun rig-clip-pose (skeleton clip time)
  "A pose of SKELETON with every joint CLIP moves at its angles at TIME."
  (let ((pose (player.body::make-pose skeleton))
        (angles (player.rig:clip-angles clip time)))
    (loop for track across (player.rig:clip-tracks clip)
          for k from 0 by 3
          for joint = (svref (player.body:skeleton-joints skeleton) (player.rig:track-joint track))
          do (dotimes (d 3)
               (setf (aref pose (+ (player.body:body-joint-dof-start joint) d)) (aref angles (+ k d)))))
    pose))

(test clip-samples-at-key-times-equal-the-keys
  (with-assimp-models
    (let* ((skeleton (wuson-skeleton))
           (rig (player.body:skeleton-rig skeleton))
           (model (player.rig:rig-model rig))
           (animation (find "Wuson_Walk" (player:model-animations model)
                            :key #'player:model-animation-name :test #'string=))
           (clip (player.rig:find-clip rig "wuson-walk"))
           (worst 0d0))
      ;; Each joint's world orientation delta from rest, composed from the clip's
      ;; angles, equals the one the file's keys give: G_p Q G_j^-1 down the chain.
      (dolist (channel (player:model-animation-channels animation))
        (let ((times (player:channel-rotation-times channel)))
          (loop for i below (length times) by 7
                for time = (aref times i)
                do (let* ((pose (rig-clip-pose skeleton clip time))
                          (joint (svref (player.body:skeleton-joints skeleton)
                                        (svref (player.rig::rig-joint-map rig) (player:channel-joint channel))))
                          (local (player.body:joint-local-rotation joint pose))
                          (expected (player.body::q* (player.body::q* (svref (player.rig::rig-parent-rotations rig) (player:channel-joint channel))
                                                                      (player.body::qnormalize (channel-rotation-at channel time)))
                                                     (player.body::qconjugate (svref (player.rig::rig-rest-rotations rig) (player:channel-joint channel))))))
                     (setf worst (max worst (quat-distance local (player.body::qnormalize expected))))))))
      (is (< worst 1d-7) "the clip's rotations differ from the file's keys by ~A rad" worst))))

(defun reference-skinned-positions (rig mesh time animation)
  "MESH's vertices at TIME of ANIMATION in Player's space, computed from the
model's own matrices: each joint's world is its parent's times its rest
translation, the keys' rotation (the test's slerp) and rest scale; a vertex
is the placement times the weighted sum of bone world x inverse bind x vertex
(for a joint that is not its bone, its world x its rest world^-1 x the node
transform)."
  (let* ((model (player.rig:rig-model rig))
         (joints (player:model-joints model))
         (worlds (make-array (length joints)))
         (rest-worlds (player.rig::model-world-rest model)))
    (loop for joint across joints for j from 0
          for channel = (find j (player:model-animation-channels animation) :key #'player:channel-joint)
          for rotation = (if (and channel (plusp (length (player:channel-rotation-times channel))))
                             (let ((q (channel-rotation-at channel time)))
                               (vector (player.body:quat-w q) (player.body:quat-x q) (player.body:quat-y q) (player.body:quat-z q)))
                             (player:joint-rotation joint))
          for local = (player.rig::trs-matrix (player:joint-translation joint) rotation (player:joint-scale joint))
          do (setf (svref worlds j) (if (player:joint-parent joint)
                                        (player.rig::affine* (svref worlds (player:joint-parent joint)) local)
                                        local)))
    (let* ((positions (player:model-mesh-positions mesh))
           (node (player.rig::row-major-matrix (player:model-mesh-transform mesh)))
           (out (make-array (length positions) :element-type 'double-float)))
      (dotimes (v (player:model-mesh-vertex-count mesh) out)
        (let ((sum (list 0d0 0d0 0d0)))
          (dotimes (k 4)
            (let ((weight (aref (player:model-mesh-weights mesh) (+ (* 4 v) k)))
                  (j (aref (player:model-mesh-joints mesh) (+ (* 4 v) k))))
              (when (plusp weight)
                (let* ((bind (if (and (find j (player:model-mesh-bones mesh)) (player:joint-inverse-bind (svref joints j)))
                                 (player.rig::row-major-matrix (player:joint-inverse-bind (svref joints j)))
                                 (player.rig::affine* (player.rig::affine-inverse (svref rest-worlds j)) node)))
                       (p (player.rig::affine-point (player.rig::affine* (player.rig:rig-placement rig)
                                                                         (player.rig::affine* (svref worlds j) bind))
                                                    (aref positions (* 3 v)) (aref positions (+ (* 3 v) 1))
                                                    (aref positions (+ (* 3 v) 2)))))
                  (setf sum (mapcar (lambda (s c) (+ s (* weight c)))
                                    sum (list (player.body:vec3-x p) (player.body:vec3-y p) (player.body:vec3-z p))))))))
          (replace out sum :start1 (* 3 v)))))))

(test skinning-agrees-with-the-model-s-own-matrices
  (with-assimp-models
    (let* ((skeleton (wuson-skeleton))
           (rig (player.body:skeleton-rig skeleton))
           (skin (first (player.rig:rig-skins rig)))
           (animation (find "Wuson_Run" (player:model-animations (player.rig:rig-model rig))
                            :key #'player:model-animation-name :test #'string=))
           (clip (player.rig:find-clip rig "wuson-run")))
      (dolist (time '(0d0 0.3d0 0.55d0))
        (let* ((transforms (player.body:pose-world-transforms skeleton (rig-clip-pose skeleton clip time)))
               (skinned (player.rig:skin-vertices skin (player.rig:skin-palette-matrices skin transforms)
                                                  (make-array (length (player:model-mesh-positions (player.rig:skin-mesh skin)))
                                                              :element-type 'single-float)
                                                  nil))
               (reference (reference-skinned-positions rig (player.rig:skin-mesh skin) time animation))
               (worst (loop for a across skinned for b across reference maximize (abs (- a b)))))
          ;; Single-float vertices: 1e-5 m is their resolution at this size.
          (is (< worst 1d-5) "at ~A s skinned vertices differ from the reference by ~A m" time worst)))
      ;; And the clip moves them: the run at 0.3 s is not the bind pose.
      (let ((rest (player.rig:skin-rest-positions skin (player.body:pose-world-transforms skeleton (player.body::make-pose skeleton))))
            (run (player.rig:skin-rest-positions skin (player.body:pose-world-transforms skeleton (rig-clip-pose skeleton clip 0.3d0)))))
        (is (> (loop for a across rest for b across run maximize (abs (- a b))) 0.01d0))))))

(test clips-cross-fade-live-with-weights-summing-to-one
  (with-assimp-models
    (let* ((skeleton (wuson-skeleton))
           (rig (player.body:skeleton-rig skeleton))
           (body (player.body:make-body 'wuson skeleton))
           (walk (player.rig:find-clip rig "wuson-walk"))
           (run (player.rig:find-clip rig "wuson-run")))
      (flet ((call (frame start)
               (player.body:body-add-driver body (player.body:make-driver (player.body:parse-motor-frame frame) body start))))
        (call '(:clip :name "wuson-walk" :loop t :fade 0 :priority 5) 0)
        (call '(:clip :name "wuson-run" :loop t :fade 0.4 :priority 10) 1))
      (dolist (time '(1.1d0 1.2d0 1.3d0 1.5d0))
        (let* ((pose (player.body:body-evaluate body time))
               (w (player.body:ramp (- time 1) 0d0 0.4d0))
               (under (rig-clip-pose skeleton walk (mod time (player.rig:clip-duration walk))))
               (over (rig-clip-pose skeleton run (mod (- time 1) (player.rig:clip-duration run))))
               (worst (loop for index below (length pose)
                            maximize (abs (- (aref pose index)
                                             (+ (* (- 1 w) (aref under index)) (* w (aref over index))))))))
          (is (< worst 1d-9) "at ~A s (run weight ~A) the pose is not (1 - w) walk + w run: off by ~A degrees"
              time w worst))))))

(defun write-library (directory text)
  "Write TEXT as lib.lisp in DIRECTORY; return its path."
  (let ((path (merge-pathnames "lib.lisp" directory)))
    (with-open-file (out path :direction :output :if-exists :supersede)
      (write-string text out))
    path))

(defun library-error-text (directory text)
  "The report of the error loading a library holding TEXT, or NIL when it loads."
  (handler-case (progn (player:load-script-library (write-library directory text)) nil)
    (player:player-error (condition) (princ-to-string condition))))

(defmacro with-rig-directory ((var) &body body)
  "Run BODY with VAR bound to a fresh directory, deleted afterwards."
  `(let ((,var (uiop:ensure-directory-pathname
                (format nil "/tmp/player-rig-test-~D-~D/" (sb-posix:getpid) (random 1000000)))))
     (ensure-directories-exist ,var)
     (unwind-protect (progn ,@body)
       (uiop:delete-directory-tree ,var :validate t :if-does-not-exist :ignore))))

(test model-form-and-clip-items-load
  (with-assimp-models
    (with-rig-directory (dir)
      (let* ((library (player:load-script-library
                       (write-library dir (format nil "(model ~S :height 0.8 :clips ((stride :from 10 :to 40 :fps 30 :animation \"Wuson_Walk\")))
(defscript walk-once () (:at 0.5 :clip wuson-walk :fade 0.3))
(defscript stride-twice () (:at 0 :clip stride :speed 2) (:at 1 :clip stride))"
                                                  (assimp-model "X/Testwuson.X")))))
             (skeleton (player.performance::script-library-skeleton library))
             (rig (player.body:skeleton-rig skeleton))
             (stride (player.rig:find-clip rig "stride"))
             (walk (player.rig:find-clip rig "wuson-walk")))
        (is (= 40 (length (player.body:skeleton-joints skeleton))))
        ;; A clip's length gives its script's inferred duration.
        (is (< (abs (- (player.performance::script-duration (player:find-script library 'walk-once)) (+ 0.5d0 3.6d0))) 1d-9))
        (is (< (abs (- (player.performance::script-duration (player:find-script library 'stride-twice)) 2)) 1d-9))
        ;; A clip cut by frames starts where its frames do.
        (is (< (abs (- (player.rig:clip-duration stride) 1)) 1d-9))
        (let ((a (player.rig:clip-angles stride 0.25d0))
              (b (player.rig:clip-angles walk (+ 0.25d0 (/ 10 30d0)))))
          (is (< (loop for x across a for y across b maximize (abs (- x y))) 1d-6)))))))

(test model-form-errors-name-the-file-and-line
  (with-assimp-models
    (with-rig-directory (dir)
      (let ((wuson (assimp-model "X/Testwuson.X")))
        (with-open-file (out (merge-pathnames "not-a-model.x" dir) :direction :output)
          (write-string "this is not a model" out))
        (loop for (text expected) in
              `(("(model \"missing.x\")" "missing.x")
                ("(model \"not-a-model.x\")" "not-a-model.x")
                (,(format nil "(model ~S :texture \"missing.png\")" wuson) "missing.png")
                (,(format nil "(model ~S :roles ((:head \"Nope\")))" wuson) "\"Nope\"")
                (,(format nil "(model ~S :roles ((:left-arm (\"Neck\" \"Mouth\"))))" wuson) ":left-arm")
                (,(format nil "(model ~S :height -1)" wuson) ":height")
                (,(format nil "(model ~S :up :x)" wuson) ":up")
                (,(format nil "(model ~S :limits ((\"Nope\" (:x -10 10))))" wuson) "Nope")
                (,(format nil "(model ~S :clips ((w :from 0 :to 1000 :fps 30 :animation \"Wuson_Walk\")))" wuson) "past the end")
                (,(format nil "(model ~S :clips ((w :from 0 :to 10 :fps 30 :animation \"Wuson_Fly\")))" wuson) "Wuson_Fly")
                (,(format nil "~%(model ~S)~%(defscript s () (:at 0 :clip wuson-fly))" wuson) "wuson-fly")
                ("(defscript s () (:at 0 :clip wuson-walk))" "(model"))
              do (let ((report (library-error-text dir text)))
                   (is (and report (search expected report)) "~S: ~A does not name ~A" text report expected)
                   (is (and report (search "lib.lisp:" report)) "~S: ~A does not name the file and line" text report)))))))

(test an-imported-character-records-and-verifies
  ;; Its joints are named by uninterned symbols, which a recording file reads
  ;; back as fresh ones: the replay must still match it, and catch a change.
  (with-assimp-models
    (with-rig-directory (dir)
      (let* ((spec (first (player::load-spec (checkout-file "examples/wuson/wuson.lisp"))))
             (file (merge-pathnames "wuson.rec" dir)))
        (player:record-scenario spec :events '("ev-walk" "ev-run") :frames t :fps 5 :out file)
        (is (player:verification-ok-p (player:verify-recording file :spec spec)))
        ;; A frame changed by a degree is a difference, named by its joint.
        (let ((text (uiop:read-file-string file)))
          (with-open-file (out file :direction :output :if-exists :supersede)
            (write-string (let ((at (search ":dofs (:x " text :from-end t)))
                            (concatenate 'string (subseq text 0 (+ at 10)) "1" (subseq text (+ at 10))))
                          out)))
        (let ((verification (player:verify-recording file :spec spec)))
          (is (not (player:verification-ok-p verification)))
          (is (search "joint" (player:verification-message verification))))))))
