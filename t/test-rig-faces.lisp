;;;; test-rig-faces.lisp -- morph targets and drivers on imported bodies
;;;; (issue 26, item 6): morph weights imported and played as the file keys
;;;; them, blended into the skin before skinning, set by :morph; :lips and
;;;; :blink through a face's morph targets, and the jaw of an imported model;
;;;; head, reach, facing and beat on a skeleton nobody here made (CMU's).

(in-package #:player-tests)

(def-suite* rig-faces :in player-tests)

(defparameter *morph-cube* "glTF2/glTF-Sample-Models/AnimatedMorphCube-glTF/AnimatedMorphCube.gltf"
  "Khronos' AnimatedMorphCube: one mesh, two morph targets, one animation of their weights.")

(defun floats (&rest values)
  "VALUES as a single-float vector."
  (map '(simple-array single-float (*)) (lambda (x) (float x 1f0)) values))

(defun face-model (morph-names)
  "A model made here: one joint, one triangle whose vertex 0 each morph target
of MORPH-NAMES moves up by 1 cm times its position in the list (+1)."
  (let ((mesh (player:make-model-mesh
               :name "face" :positions (floats 0 1 0 0.1 1 0 0 1.1 0)
               :triangles (make-array 3 :element-type '(unsigned-byte 32) :initial-contents '(0 1 2))
               :bones (make-array 0 :element-type '(unsigned-byte 32))
               :holder 0
               :morph-targets (copy-list morph-names)
               :morphs (loop for name in morph-names for k from 1
                             collect (player:make-morph-target name (floats 0 (* 0.01 k) 0 0 0 0 0 0 0))))))
    (player:make-model "/tmp/face.made-here" (list mesh)
                       (vector (player:make-joint "Head" nil (player.rig::doubles '(0 0 0)) (player.rig::doubles '(1 0 0 0))
                                                  (player.rig::doubles '(1 1 1)) nil))
                       '())))

(defun face-body (morph-names)
  "A body whose skeleton is FACE-MODEL's."
  (player.body:make-body 'face (player.rig:model-skeleton (face-model morph-names))))

(defun evaluate-call (body frame start time)
  "BODY's pose at TIME after the motor FRAME starts at START."
  (player.body:body-add-driver body (player.body:make-driver (player.body:parse-motor-frame frame) body start))
  (player.body:body-evaluate body time))

(test morph-cube-weights-play-as-the-file-keys-them
  (with-assimp-models
    (let* ((model (player:import-model (assimp-model *morph-cube*)))
           (skeleton (player.rig:model-skeleton model))
           (rig (player.body:skeleton-rig skeleton))
           (animation (first (player:model-animations model)))
           (channel (first (player:model-animation-morph-channels animation)))
           (clip (player.rig:find-clip rig (player.rig:clip-name-from-animation (player:model-animation-name animation)))))
      (is (= 2 (length (player.body:skeleton-morphs skeleton))) "the cube's two morph targets are channels")
      (is (= 1 (length (player.body:skeleton-joints skeleton))) "a model of morphs and no joints gets one root joint")
      (is (= 2 (length (player.rig:clip-morph-tracks clip))))
      ;; At each key time the clip's weights are the file's.
      (let ((times (player:morph-channel-times channel))
            (weights (player:morph-channel-weights channel))
            (worst 0d0))
        (dotimes (i (length times))
          (loop for track in (player.rig:clip-morph-tracks clip)
                for k from 0
                do (setf worst (max worst (abs (- (player.rig:clip-morph-weight track (aref times i))
                                                  (aref weights (+ (* 2 i) k))))))))
        (is (< worst 1d-9) "morph weights differ from the keys by ~A" worst)))))

(test morphs-are-added-before-skinning
  (with-assimp-models
    (let* ((model (player:import-model (assimp-model *morph-cube*)))
           (skeleton (player.rig:model-skeleton model))
           (rig (player.body:skeleton-rig skeleton))
           (skin (first (player.rig:rig-skins rig)))
           (mesh (player.rig:skin-mesh skin))
           (pose (player.body::make-pose skeleton))
           (base (player.body:skeleton-dof-count skeleton)))
      (setf (aref pose base) 0.3d0 (aref pose (1+ base)) 0.7d0)
      (let* ((transforms (player.body:pose-world-transforms skeleton pose))
             (out (make-array (length (player:model-mesh-positions mesh)) :element-type 'single-float))
             (skinned (player.rig:skin-vertices skin (player.rig:skin-palette-matrices skin transforms) out nil pose))
             (node (player.rig::row-major-matrix (player:model-mesh-transform mesh)))
             (frame (player.rig::affine* (player.rig:rig-placement rig) node))
             (deltas (mapcar #'player:morph-target-deltas (player:model-mesh-morphs mesh)))
             (worst 0d0))
        ;; The reference: the placed node transform times (base + 0.3 d0 + 0.7 d1).
        (dotimes (v (player:model-mesh-vertex-count mesh))
          (flet ((at (k) (+ (aref (player:model-mesh-positions mesh) (+ (* 3 v) k))
                            (* 0.3 (aref (first deltas) (+ (* 3 v) k)))
                            (* 0.7 (aref (second deltas) (+ (* 3 v) k))))))
            (let ((p (player.rig::affine-point frame (at 0) (at 1) (at 2))))
              (setf worst (max worst (abs (- (aref skinned (* 3 v)) (player.body:vec3-x p)))
                               (abs (- (aref skinned (+ (* 3 v) 1)) (player.body:vec3-y p)))
                               (abs (- (aref skinned (+ (* 3 v) 2)) (player.body:vec3-z p))))))))
        (is (< worst 1d-5) "morphed, skinned vertices differ from the reference by ~A m" worst)
        (is (> (reduce #'max (second deltas) :key #'abs) 0.001) "the targets move something")))))

(test the-morph-function-eases-to-a-weight-and-holds
  (let* ((body (face-body '("smile" "frown")))
         (skeleton (player.body:body-skeleton body))
         (smile (player.body:morph-index skeleton "smile")))
    (evaluate-call body '(:morph :name "smile" :weight 0.8 :duration 0.4) 0 0)
    (is (< (abs (- (aref (player.body:body-evaluate body 0.2d0) smile) 0.4d0)) 1d-6) "half way, half the weight")
    (is (< (abs (- (aref (player.body:body-evaluate body 1d0) smile) 0.8d0)) 1d-6) "held at its weight")
    ;; A weight above 1 or a morph the model lacks is refused, naming it.
    (flet ((refusal (frame)
             (handler-case (progn (player.body:make-driver (player.body:parse-motor-frame frame) body 0) nil)
               (player:player-error (e) (princ-to-string e)))))
      (is (search "0 to 1" (or (refusal '(:morph :name "smile" :weight 1.5)) "")))
      (is (search "frown" (or (refusal '(:morph :name "grin")) "")) "the error lists the morph targets"))))

(test lips-move-viseme-morphs
  (let* ((names '("viseme_sil" "viseme_PP" "viseme_aa" "viseme_E" "viseme_I" "viseme_O" "viseme_U"))
         (body (face-body names))
         (skeleton (player.body:body-skeleton body)))
    (evaluate-call body '(:lips :visemes ((0.2 :aa) (0.5 :ee) (0.8 :rest)) :ramp 0.05) 0 0)
    (flet ((weight (name time) (aref (player.body:body-evaluate body time) (player.body:morph-index skeleton name))))
      (is (< (abs (- (weight "viseme_aa" 0.2d0) 1)) 1d-9) ":aa is viseme_aa")
      (is (< (abs (weight "viseme_E" 0.2d0)) 1d-9))
      (is (< (abs (- (weight "viseme_E" 0.5d0) 1)) 1d-9) ":ee is viseme_E")
      (is (< (abs (weight "viseme_aa" 0.5d0)) 1d-9))
      (is (< (abs (- (weight "viseme_sil" 0.8d0) 1)) 1d-9) ":rest is viseme_sil"))))

(test lips-open-an-arkit-mouth-by-the-viseme-s-opening
  (let* ((body (face-body '("jawOpen" "mouthSmile")))
         (skeleton (player.body:body-skeleton body)))
    (evaluate-call body '(:lips :visemes ((0.2 :ih) (0.6 :aa))) 0 0)
    (flet ((weight (time) (aref (player.body:body-evaluate body time) (player.body:morph-index skeleton "jawOpen"))))
      (is (< (abs (- (weight 0.2d0) 0.5)) 1d-9) ":ih opens jawOpen half")
      (is (< (abs (- (weight 0.6d0) 1)) 1d-9) ":aa opens it wide"))))

(test blink-closes-blink-morphs
  (let* ((body (face-body '("eyeBlink_L" "eyeBlink_R")))
         (skeleton (player.body:body-skeleton body)))
    (evaluate-call body '(:blink :mean-interval 0.5 :duration 0.2 :seed 3) 0 0)
    (let ((closed (loop for i from 1 to 400
                        for pose = (player.body:body-evaluate body (* i 0.01d0))
                        maximize (min (aref pose (player.body:morph-index skeleton "eyeBlink_L"))
                                      (aref pose (player.body:morph-index skeleton "eyeBlink_R"))))))
      (is (> closed 0.9d0) "in 4 s of blinking both eyes shut (most ~A)" closed))))

(test an-imported-jaw-opens-about-x
  (with-assimp-models
    (let* ((body (player.body:make-body 'wuson (player.rig:model-skeleton (player:import-model (assimp-model "X/Testwuson.X"))
                                                                          :height 0.8 :roles '((:jaw "Mouth")))))
           (jaw (player.body:skeleton-role (player.body:body-skeleton body) :jaw))
           (index (player.body:body-joint-dof-start jaw)))
      (evaluate-call body '(:lips :visemes ((0.3 :aa))) 0 0)
      (is (< (abs (- (aref (player.body:body-evaluate body 0.3d0) index) player.body::*imported-jaw-opening*)) 1d-9)
          ":aa opens Wuson's Mouth joint ~A degrees about x" player.body::*imported-jaw-opening*))))

(defvar *rig-faces-cmu-skeleton* nil "CMU's 01_01.bvh as a skeleton, made once.")

(defun cmu-body ()
  "A body on CMU's motion-capture skeleton (01_01.bvh), 1.7 m tall, in a scene."
  (let ((scene (make-instance 'player.body:scene)))
    (player.body:make-body 'subject (or *rig-faces-cmu-skeleton*
                                        (setf *rig-faces-cmu-skeleton* (player.rig:model-skeleton
                                                              (player:import-model (assimp-model "BVH/01_01.bvh"))
                                                              :height 1.7)))
                           :scene scene)))

(test drivers-move-a-skeleton-nobody-here-made
  (with-assimp-models
    ;; Head: a nod pitches the :head joint.
    (let* ((body (cmu-body))
           (head (player.body:skeleton-role (player.body:body-skeleton body) :head))
           (moved (progn (evaluate-call body '(:head :action :nod :amplitude 15 :duration 0.6) 0 0)
                         (loop for i from 1 to 6
                               maximize (reduce #'max (player.body::joint-dof-indices head)
                                                :key (lambda (k) (abs (aref (player.body:body-evaluate body (* i 0.1d0)) k))))))))
      (is (> moved 5) "a nod turns CMU's head (~A degrees)" moved))
    ;; Reach: the left hand comes to a point in front of the chest.
    (let* ((body (cmu-body))
           (target (list :point 0.25d0 1.2d0 0.35d0)))
      (evaluate-call body `(:reach :arm :left :target ,target :duration 0.5) 0 0)
      (player.body:body-evaluate body 1d0)
      (let ((hand (player.body:body-joint-position body :left-hand)))
        (is (< (player.body:vdistance hand (player.body:vec3 0.25d0 1.2d0 0.35d0)) 0.05d0)
            "the left hand reaches within 5 cm (it is at ~A)" hand)))
    ;; Beat: the right forearm dips at the beat.
    (let* ((body (cmu-body))
           (arm (player.body:skeleton-role (player.body:body-skeleton body) :right-arm))
           (rest (player.body:copy-vec3 (progn (player.body:body-evaluate body 0) (player.body:body-joint-position body :right-hand)))))
      (declare (ignore arm))
      (evaluate-call body '(:beat :arm :right :times (0.4)) 0.1d0 0.1d0)
      (let ((dip (player.body:vdistance rest (progn (player.body:body-evaluate body 0.5d0)
                                                    (player.body:body-joint-position body :right-hand)))))
        (is (> dip 0.01d0) "a beat moves CMU's right hand (~A m)" dip)))
    ;; Gaze without eye joints: the head turns to the target.
    (let* ((body (cmu-body))
           (skeleton (player.body:body-skeleton body))
           (head (player.body:skeleton-role skeleton :head))
           (target (player.body:vec3 1.5d0 1.6d0 1d0)))
      (evaluate-call body '(:gaze :target (:point 1.5 1.6 1)) 0 0)
      (player.body:body-evaluate body 2d0)
      (let* ((frame (svref (player.body:body-transforms body) (player.body:body-joint-index head)))
             (front (player.body:transform-vector frame (player.body:vec3 0d0 0d0 1d0)))
             (to (player.body:v- target (player.body:transform-translation frame)))
             (degrees (* (/ 180 pi) (acos (/ (player.body:vdot front to) (player.body:vnorm to))))))
        (is (< degrees 10) "the head looks ~,1F degrees off the target" degrees)))
    ;; Lips need a jaw or mouth morphs, which CMU's skeleton has not: refused, naming the file.
    (let ((body (cmu-body)))
      (is (search "01_01.bvh"
                  (handler-case (progn (player.body:make-driver (player.body:parse-motor-frame '(:lips :visemes ((0.1 :aa)))) body 0) "")
                    (player:player-error (e) (princ-to-string e))))))))

(test keyframe-poses-name-imported-joints-directly
  (with-assimp-models
    (let* ((body (player.body:make-body 'wuson (wuson-skeleton)))
           (skeleton (player.body:body-skeleton body))
           (neck (player.body:find-joint skeleton "Neck")))
      ;; A joint named in a string, as a model's names often must be, and an :x DOF.
      (evaluate-call body '(:keyframe :keys ((0.5 (("Neck" :x 20 :y -10))))) 0 0)
      (let ((pose (player.body:body-evaluate body 0.5d0)))
        (is (< (abs (- (aref pose (player.body:body-joint-dof-start neck)) 20)) 1d-6))
        (is (< (abs (- (aref pose (1+ (player.body:body-joint-dof-start neck))) -10)) 1d-6))))))

(test a-clip-masked-to-the-head-moves-only-the-head
  (with-assimp-models
    (let* ((skeleton (player.rig:model-skeleton (player:import-model (assimp-model "X/Testwuson.X"))
                                                :height 0.8 :roles '((:head "Neck"))))
           (body (player.body:make-body 'wuson skeleton))
           (neck (player.body:find-joint skeleton "Neck"))
           (neck-channels (player.body::joint-dof-indices neck)))
      (evaluate-call body '(:clip :name "wuson-walk" :loop t :fade 0 :joints (:head)) 0 0)
      (let ((pose (player.body:body-evaluate body 1.3d0)))
        (is (some (lambda (i) (> (abs (aref pose i)) 0.01)) neck-channels) "the head moves")
        (is (every (lambda (i) (or (member i neck-channels) (zerop (aref pose i))))
                   (alexandria:iota (length pose)))
            "nothing but the head moves")))))

(test motion-capture-plays-on-the-humanoid-through-a-library
  ;; (:clip NAME :from FILE) in a library, resolved by the clip driver at play.
  (with-assimp-models
    (with-rig-directory (dir)
      (flet ((write-file (name text)
               (with-open-file (out (merge-pathnames name dir) :direction :output :if-exists :supersede)
                 (write-string text out))))
        (write-file "mocap.lisp" "(in-package :player-user)
(defspec mocap \"CMU 01_01 on the humanoid.\" (:scripts \"mocap-scripts.lisp\") (:body humanoid)
  (state-variable moving boolean false)
  (op move :add moving :duration 2)
  (event ev-move :state moving))")
        (write-file "mocap-scripts.lisp" (format nil "(defscript move (:duration 2)~%  (:at 0 :clip motion :from ~S :fade 0))"
                                            (assimp-model "BVH/01_01.bvh"))))
      (let* ((spec (first (player::load-spec (merge-pathnames "mocap.lisp" dir))))
             (simulation (player.performance::simulate spec :events '("ev-move") :fps 10 :silent t))
             (body (player.performance::performance-body (player.performance::presenter-performance (player.performance::simulation-presenter simulation))))
             (skeleton (player.body:body-skeleton body))
             (elbow (player.body:dof-index skeleton 'l_elbow (player.body:body-dof-name (first (player.body::body-joint-dofs (player.body:find-joint skeleton 'l_elbow))))))
             (angles (let ((seen '()))
                       (player.performance::map-simulation-frames (lambda (index time scene) (declare (ignore index time scene))
                                                        (push (aref (player.body:body-pose body) elbow) seen))
                                                      simulation)
                       seen)))
        (is (> (- (reduce #'max angles) (reduce #'min angles)) 1) "the humanoid's left elbow follows the capture")
        (is (player.body:pose-within-limits-p skeleton (player.body:body-pose body)))))))

(test facing-and-lids-on-imported-joints
  (with-assimp-models
    ;; Facing turns the root about the vertical: CMU's subject turns to a point on its left.
    (let* ((body (cmu-body))
           (skeleton (player.body:body-skeleton body))
           (root (svref (player.body:skeleton-joints skeleton) 0))
           (yaw (1+ (player.body:body-joint-dof-start root))))
      (evaluate-call body '(:facing :target (:point 5 0 0) :duration 0.5) 0 0)
      ;; From where the root stands, the point lies this many degrees round from +z.
      (let* ((centre (player.body:body-joint-center root))
             (heading (* (/ 180 pi) (atan (- 5 (svref centre 0)) (- 0 (svref centre 2))))))
        (is (< (abs (- (aref (player.body:body-evaluate body 1d0) yaw) heading)) 1d-6)
            "the root turns ~,1F degrees about y to face the point" heading)
        (is (> heading 80))))
    ;; An imported upper lid (no close DOF) shuts about x on a blink.
    (let* ((skeleton (player.rig:model-skeleton (player:import-model (assimp-model "X/Testwuson.X"))
                                                :height 0.8 :roles '((:left-upper-lid "Ear_L") (:right-upper-lid "Ear_R"))))
           (body (player.body:make-body 'wuson skeleton))
           (lid (player.body:body-joint-dof-start (player.body:find-joint skeleton "Ear_L"))))
      (evaluate-call body '(:blink :mean-interval 0.5 :duration 0.2 :seed 3) 0 0)
      (is (< (abs (- (loop for i from 1 to 400 maximize (aref (player.body:body-evaluate body (* i 0.01d0)) lid))
                     player.body::*imported-lid-closing*))
             1)
          "the lid shuts to ~A degrees about x" player.body::*imported-lid-closing*))))
