;;;; test-skinned-render.lisp -- imported models drawn from their skins
;;;; (src/render/skinned-mesh.lisp): the GPU's skinning against the CPU's, the
;;;; CPU's against a reference computed here from the model's own matrices,
;;;; textures covering the model's projected bounds, a clip moving the
;;;; picture, and the errors.  Needs Debian's assimp-testmodels and libOSMesa;
;;;; without them the tests skip with a note.

(in-package #:player-tests)

(def-suite* skinned-render :in player-tests)

(defparameter *wuson-file* "/usr/share/assimp/models/X/Testwuson.X" "The skinned test model.")
(defparameter *test-texture* "/usr/share/assimp/models/LWO/LWO2/uvtest.png"
  "A texture with strong colours, laid on Testwuson's UVs for the texture tests.")

(defmacro with-skinned-render-prerequisites (&body body)
  "Run BODY when Testwuson and libOSMesa are there; else skip with a note."
  `(if (and (probe-file *wuson-file*) (ignore-errors (player.render::load-osmesa-library)))
       (progn ,@body)
       (skip "Testwuson (Debian assimp-testmodels) or libOSMesa is missing: skinned rendering not tested")))

(defun wuson-body (&key clip (time 0d0) texture)
  "A scene with Testwuson, 1 m tall, evaluated at TIME playing CLIP (a name)
from 0, looping; with TEXTURE every mesh is drawn with that image.  Returns
the scene and the body."
  (let* ((model (player.model::import-model *wuson-file*))
         (skeleton (player.rig::model-skeleton model :height 1.0))
         (scene (make-instance 'player::scene))
         (body (player.body::make-body 'wuson skeleton :scene scene)))
    (when texture
      (dolist (mesh (player.model::model-meshes model))
        (setf (player.model::model-mesh-texture mesh) texture)))
    (when clip
      (player.body::body-add-driver
       body (player.body::make-driver (player.body::parse-motor-frame `(:clip :name ,clip :loop t)) body 0d0)))
    (player.body::body-evaluate body (float time 1d0))
    (values scene body)))

(defun render-pixels (scene width height &key (gpu t) (floor t))
  "SCENE drawn offscreen at WIDTH x HEIGHT without antialiasing, skinned on
the GPU when GPU: its pixels, the view, and the renderer's skinning mode."
  (let ((player.render::*gpu-skinning* gpu))
    (player::with-offscreen-context ((context) width height)
      (let ((renderer (player.render::make-renderer width height :antialias nil :floor floor)))
        (unwind-protect
             (let ((view (player.render::render-scene renderer scene)))
               (values (player.render::renderer-pixels renderer) view
                       (player.render::renderer-skinning renderer)))
          (player.render::delete-renderer renderer))))))

(defun differing-pixels (a b &key (threshold 8))
  "How many pixels of the RGBA images A and B differ by more than THRESHOLD in a channel."
  (loop for i below (floor (length a) 4)
        count (> (pixel-difference a b i) threshold)))

;;;# The GPU against the CPU

(test gpu-skinning-draws-what-cpu-skinning-draws
  (with-skinned-render-prerequisites
    (let ((scene (wuson-body :clip "wuson-walk" :time 0.9d0)))
      (multiple-value-bind (gpu view mode) (render-pixels scene 320 240 :gpu t)
        (declare (ignore view))
        (is (eq :gpu mode) "this GL should skin on the GPU")
        (multiple-value-bind (cpu view cpu-mode) (render-pixels scene 320 240 :gpu nil)
          (declare (ignore view))
          (is (eq :cpu cpu-mode))
          ;; Single-float rounding moves a silhouette's edge by a pixel here and there.
          (let ((different (differing-pixels gpu cpu :threshold 24))
                (figure (differing-pixels gpu (render-pixels (make-instance 'player::scene) 320 240))))
            (is (> figure 3000) "the model covers ~D pixels" figure)
            (is (< different (* 0.005 figure)) "~D of ~D pixels differ between GPU and CPU skinning"
                different figure)))))))

(test a-palette-too-big-for-the-shader-falls-back-to-the-cpu
  (with-skinned-render-prerequisites
    (let* ((skin (first (player.rig::rig-skins (player.body::skeleton-rig
                                               (player.body::body-skeleton
                                                (nth-value 1 (wuson-body)))))))
           (big (copy-structure skin)))
      (setf (player.rig::skin-palette big)
            (coerce (loop repeat (1+ player.render::+palette-size+) collect (aref (player.rig::skin-palette skin) 0))
                    'simple-vector))
      (player::with-offscreen-context ((context) 64 64)
        (let ((renderer (player.render::make-renderer 64 64 :antialias nil)))
          (unwind-protect
               (progn
                 (is (eq :gpu (player.render::gpu-skin-mode (player.render::make-gpu-skin renderer skin))))
                 (is (eq :cpu (player.render::gpu-skin-mode (player.render::make-gpu-skin renderer big)))))
            (player.render::delete-renderer renderer)))))))

;;;# The CPU against the model's own matrices

(defun key-value (times values width time)
  "The key of TIMES and VALUES (WIDTH each) at TIME, slerped (WIDTH 4) or
lerped between neighbours, held outside, as a list."
  (let* ((n (length times))
         (i (or (position-if (lambda (x) (> x time)) times) n)))
    (flet ((key (k) (loop for j below width collect (aref values (+ (* k width) j)))))
      (cond ((= i 0) (key 0))
            ((= i n) (key (1- n)))
            (t (let* ((a (key (1- i))) (b (key i))
                      (u (/ (- time (aref times (1- i))) (- (aref times i) (aref times (1- i))))))
                 (if (/= width 4)
                     (mapcar (lambda (x y) (+ x (* u (- y x)))) a b)
                     (let* ((dot (reduce #'+ (mapcar #'* a b)))
                            (b (if (minusp dot) (mapcar #'- b) b))
                            (dot (min 1d0 (abs dot)))
                            (angle (acos dot)))
                       (if (< angle 1d-9)
                           a
                           (mapcar (lambda (x y) (/ (+ (* x (sin (* (- 1 u) angle))) (* y (sin (* u angle))))
                                                    (sin angle)))
                                   a b))))))))))

(defun row-major (values)
  "A 4x4 double array of the 16 row-major VALUES."
  (let ((m (make-array '(4 4) :element-type 'double-float)))
    (dotimes (i 16 m) (setf (row-major-aref m i) (float (elt values i) 1d0)))))

(defun local-matrix (translation quat scale)
  "T R S as a 4x4 array: TRANSLATION (x y z), QUAT (w x y z), SCALE (x y z)."
  (destructuring-bind (w x y z) (let ((n (sqrt (reduce #'+ (mapcar #'* quat quat)))))
                                  (mapcar (lambda (c) (/ c n)) quat))
    (let ((r (list (- 1 (* 2 (+ (* y y) (* z z)))) (* 2 (- (* x y) (* w z))) (* 2 (+ (* x z) (* w y)))
                   (* 2 (+ (* x y) (* w z))) (- 1 (* 2 (+ (* x x) (* z z)))) (* 2 (- (* y z) (* w x)))
                   (* 2 (- (* x z) (* w y))) (* 2 (+ (* y z) (* w x))) (- 1 (* 2 (+ (* x x) (* y y))))))
          (m (row-major '(0 0 0 0 0 0 0 0 0 0 0 0 0 0 0 1))))
      (dotimes (row 3 m)
        (dotimes (column 3)
          (setf (aref m row column) (* (nth (+ (* 3 row) column) r) (elt scale column))))
        (setf (aref m row 3) (elt translation row))))))

(defun matrix* (a b)
  "The 4x4 product A B."
  (let ((m (make-array '(4 4) :element-type 'double-float :initial-element 0d0)))
    (dotimes (i 4 m)
      (dotimes (j 4)
        (setf (aref m i j) (loop for k below 4 sum (* (aref a i k) (aref b k j))))))))

(defun reference-worlds (model animation time)
  "Each of MODEL's joints' world matrix in the model's space at TIME of
ANIMATION: rest translations and scales, the animation's rotations (Player's
joints turn, they do not stretch or slide)."
  (let* ((joints (player.model::model-joints model))
         (worlds (make-array (length joints))))
    (loop for joint across joints
          for i from 0
          for channel = (find i (player.model::model-animation-channels animation) :key #'player.model::channel-joint)
          for quat = (if (and channel (plusp (length (player.model::channel-rotation-times channel))))
                         (key-value (player.model::channel-rotation-times channel)
                                    (player.model::channel-rotations channel) 4 time)
                         (coerce (player.model::joint-rotation joint) 'list))
          for local = (local-matrix (player.model::joint-translation joint) quat (player.model::joint-scale joint))
          do (setf (svref worlds i)
                   (if (player.model::joint-parent joint)
                       (matrix* (svref worlds (player.model::joint-parent joint)) local)
                       local)))
    worlds))

(test cpu-skinning-matches-the-models-own-matrices
  ;; Vertex = placement x sum_k w_k (bone world x inverse bind) x rest vertex,
  ;; computed here from the file's joints and keys, against SKIN-VERTICES.
  (with-skinned-render-prerequisites
    (let ((time 1.3d0))
      (multiple-value-bind (scene body) (wuson-body :clip "wuson-walk" :time time)
        (declare (ignore scene))
        (let* ((rig (player.body::skeleton-rig (player.body::body-skeleton body)))
               (model (player.rig::rig-model rig))
               (animation (find "Wuson_Walk" (player.model::model-animations model)
                                :key #'player.model::model-animation-name :test #'string=))
               (worlds (reference-worlds model animation time))
               (worst 0d0))
          (dolist (skin (player.rig::rig-skins rig))
            (let* ((mesh (player.rig::skin-mesh skin))
                   (positions (player.model::model-mesh-positions mesh))
                   (count (player.model::model-mesh-vertex-count mesh))
                   (posed (player.rig::skin-vertices
                           skin (player.rig::skin-palette-matrices skin (player.body::body-transforms body))
                           (make-array (* 3 count) :element-type 'single-float) nil))
                   (binds (map 'vector (lambda (joint)
                                         (and (player.model::joint-inverse-bind joint)
                                              (row-major (player.model::joint-inverse-bind joint))))
                               (player.model::model-joints model)))
                   (placement (player.rig::rig-placement rig)))
              (dotimes (v count)
                (let ((sum (list 0d0 0d0 0d0)))
                  (dotimes (k 4)
                    (let ((w (aref (player.model::model-mesh-weights mesh) (+ (* 4 v) k)))
                          (j (aref (player.model::model-mesh-joints mesh) (+ (* 4 v) k))))
                      (when (plusp w)
                        (let ((m (matrix* placement (matrix* (svref worlds j) (svref binds j)))))
                          (setf sum (loop for row below 3
                                          for s in sum
                                          collect (+ s (* w (+ (loop for c below 3
                                                                     sum (* (aref m row c) (aref positions (+ (* 3 v) c))))
                                                               (aref m row 3))))))))))
                  (loop for c below 3
                        do (setf worst (max worst (abs (- (nth c sum) (aref posed (+ (* 3 v) c)))))))))))
          (format t "~&  CPU skinning vs the model's matrices: ~,2E m~%" worst)
          (is (< worst 1d-5) "CPU skinning is ~,2E m from the model's own matrices at ~A s" worst time))))))

;;;# Pixels

(defun projected-bounds-box (view bounds width height)
  "The pixel box (LEFT TOP RIGHT BOTTOM) of the 8 corners of BOUNDS seen through VIEW."
  (let ((xs '()) (ys '()))
    (dotimes (corner 8)
      (multiple-value-bind (x y)
          (player.render::project-point
           view (player.body::vec3 (player.body::vec3-x (if (logbitp 0 corner) (cdr bounds) (car bounds)))
                                   (player.body::vec3-y (if (logbitp 1 corner) (cdr bounds) (car bounds)))
                                   (player.body::vec3-z (if (logbitp 2 corner) (cdr bounds) (car bounds))))
           width height)
        (push x xs) (push y ys)))
    (list (reduce #'min xs) (reduce #'min ys) (reduce #'max xs) (reduce #'max ys))))

(test a-textured-model-covers-its-projected-bounds
  ;; Seen from the framing camera, the bind pose's box projects onto a
  ;; rectangle, all in the frame.  Testwuson is a bison seen head on, twice
  ;; as long as it is tall: the box's near face projects far larger than its
  ;; body, so a third of the rectangle is the model, and outside it nothing is.
  (with-skinned-render-prerequisites
    (multiple-value-bind (scene body) (wuson-body :texture *test-texture*)
      (multiple-value-bind (pixels view) (render-pixels scene 200 150 :floor nil)
        (setf (player::property-value body 'visible) nil)
        (let* ((empty (render-pixels scene 200 150 :floor nil))
               (bounds (player.rig::rig-bounds (player.body::skeleton-rig (player.body::body-skeleton body))))
               (box (projected-bounds-box view bounds 200 150))
               (inside 0) (inside-drawn 0) (outside-drawn 0))
          (destructuring-bind (left top right bottom) box
            (is (and (<= 0 left) (< right 200) (<= 0 top) (< bottom 150)) "the framing camera shows all of ~A" box)
            (dotimes (i (* 200 150))
              (multiple-value-bind (row column) (floor i 200)
                (let ((drawn (> (pixel-difference pixels empty i) 8)))
                  (if (and (<= left column right) (<= top row bottom))
                      (progn (incf inside) (when drawn (incf inside-drawn)))
                      (when drawn (incf outside-drawn)))))))
          (is (> inside-drawn (* 0.3 inside)) "only ~D of the ~D pixels inside the projected bounds are the model"
              inside-drawn inside)
          (is (< outside-drawn 20) "~D pixels outside the projected bounds are drawn" outside-drawn)
          (setf (player::property-value body 'visible) t)
          (is (> (differing-pixels pixels (render-pixels (wuson-body) 200 150 :floor nil)) 1000)
              "the texture changes the picture"))))))

(test a-walk-clip-moves-the-picture
  (with-skinned-render-prerequisites
    (let ((early (render-pixels (wuson-body :clip "wuson-walk" :time 0.4d0) 160 120))
          (late (render-pixels (wuson-body :clip "wuson-walk" :time 1.6d0) 160 120)))
      (is (> (differing-pixels early late :threshold 24) 100) "two times of wuson-walk draw the same picture"))))

;;;# Errors

(test a-missing-texture-is-a-render-error
  (with-skinned-render-prerequisites
    (let ((scene (wuson-body :texture "/nonexistent/player-no-such-texture.png")))
      (handler-case (progn (render-pixels scene 32 32) (fail "no error"))
        (player:render-error (condition)
          (let ((message (princ-to-string condition)))
            (is (search "player-no-such-texture.png" message) "~A" message)
            (is (search "does not exist" message) "~A" message)))))))
