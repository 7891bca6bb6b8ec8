;;;; test-root-motion.lisp -- a :clip item's :root :move (src/rig/root-motion.lisp):
;;;; the character travels as the clip's root does, checked against the
;;;; file's own root keys (CMU's 01_01.bvh, whose hips walk across the room;
;;;; Testwuson's walk keeps its root still, so Wuson stays where it stood),
;;;; scaled when the clip is retargeted, and :in-place stays.

(in-package #:player-tests)

(def-suite* root-motion :in player-tests)

(defun write-walker-files (directory library)
  "Write LIBRARY as lib.lisp and a spec whose op walk plays script walk (3 s)
as spec.lisp in DIRECTORY; return the spec."
  (write-library directory library)
  (let ((path (merge-pathnames "spec.lisp" directory)))
    (with-open-file (out path :direction :output :if-exists :supersede)
      (write-string "(in-package :player-user)
(defspec walker \"Walks.\" (:scripts \"lib.lisp\")
  (state-variable went boolean false)
  (op walk :add went :duration 3)
  (event ev-walk :op walk))
" out))
    (first (player:load-spec path))))

(defun simulated-position (simulation time)
  "Where the body of SIMULATION stands at TIME seconds (a vec3)."
  (let ((scene (player.performance::simulation-scene-at simulation (float time 1d0))))
    (player:property-value (find-if (lambda (o) (typep o 'player:body)) (player:scene-objects scene))
                           'player.body::position)))

(defun body-position-at (spec time &rest simulate-arguments)
  "Where the body of SPEC, sent ev-walk, stands at TIME seconds (a vec3)."
  (simulated-position (apply #'player:simulate spec :events '(ev-walk) :silent t simulate-arguments) time))

(defun bvh-hips-travel (seconds)
  "How far the hips of 01_01.bvh travel, horizontally (x z, file units), in its first SECONDS."
  (let* ((model (player:import-model (assimp-model "BVH/01_01.bvh")))
         (channel (find "Hips" (player:model-animation-channels (first (player:model-animations model)))
                        :key (lambda (c) (player:joint-name (aref (player:model-joints model) (player.model:channel-joint c))))
                        :test #'string=))
         (times (player.model:channel-position-times channel))
         (keys (player.model:channel-positions channel))
         (k (position-if (lambda (time) (>= time (- seconds 1d-9))) times)))
    (list (- (aref keys (* 3 k)) (aref keys 0)) (- (aref keys (+ 2 (* 3 k))) (aref keys 2)))))

(defun horizontal-distance (position xz)
  "How far the vec3 POSITION lies from (X 0 Z), XZ being (X Z), ignoring height."
  (sqrt (+ (expt (- (player.body::vec3-x position) (first xz)) 2)
           (expt (- (player.body::vec3-z position) (second xz)) 2))))

(defun library-clip (directory name)
  "The clip NAME of the model of the library lib.lisp in DIRECTORY."
  (let ((library (player:load-script-library (merge-pathnames "lib.lisp" directory))))
    (player.rig:find-clip (player.body:skeleton-rig (player.performance::script-library-skeleton library)) name)))

(test root-move-follows-the-clips-root-keys
  "A BVH file as the character, its clip played with :root :move for 2 s,
carries the body by the clip's root travel, which is the file's hips keys'
\(scale 1: the file's units; within 3%, the clip sampling its keys where the
raw keys are taken at the next one), and holds it there after; :in-place
keeps it at the origin."
  (with-assimp-models
    (with-rig-directory (dir)
      (let* ((moving (write-walker-files dir (format nil "(model ~S)
(defscript walk (:duration 3) (:at 0 :clip motion :root :move :fade 0 :for 2))" (assimp-model "BVH/01_01.bvh"))))
             (clip (library-clip dir "motion")))
        (flet ((travel (seconds)
                 (let ((v (player.rig:clip-travel clip (float seconds 1d0) nil)))
                   (list (player.body::vec3-x v) (player.body::vec3-z v)))))
          (let ((keys (bvh-hips-travel 2d0)))
            (is (> (sqrt (+ (expt (first keys) 2) (expt (second keys) 2))) 5)
                "the hips travel only ~A in 2 s: no test" keys)
            (is (< (horizontal-distance (body-position-at moving 2) keys) (* 0.03 (abs (second keys))))
                "at 2 s the body is at ~A, the hips keys travelled ~A" (body-position-at moving 2) keys))
          (dolist (time '(0.5 1 2 2.9))
            (let ((at (body-position-at moving time)))
              (is (< (horizontal-distance at (travel (min time 2))) 1d-6)
                  "at ~A s the body is at ~A, the clip's root travelled ~A" time at (travel (min time 2)))
              (is (= 0 (player.body::vec3-y at)) "the body rose to ~A" at))))
        (let ((in-place (write-walker-files dir (format nil "(model ~S)
(defscript walk (:duration 3) (:at 0 :clip motion :fade 0 :for 2))" (assimp-model "BVH/01_01.bvh")))))
          (is (< (horizontal-distance (body-position-at in-place 2) '(0 0)) 1d-9)))))))

(test root-move-of-a-retargeted-clip-is-scaled
  "CMU's walk retargeted onto the humanoid carries it by the retargeted
clip's travel, the file's scaled by the skeletons' leg lengths (so less than
the file's centimetre-sized units)."
  (with-assimp-models
    (with-rig-directory (dir)
      (let* ((spec (write-walker-files dir (format nil "(defscript walk (:duration 3) (:at 0 :clip motion :from ~S :root :move :fade 0 :for 2))"
                                                   (assimp-model "BVH/01_01.bvh"))))
             (clip (player.rig:retarget-clip (player:import-model (assimp-model "BVH/01_01.bvh")) "motion"
                                             (player:load-skeleton 'player.body::humanoid)))
             (travel (player.rig:clip-travel clip 2d0 nil))
             (at (body-position-at spec 2 :body 'player.body::humanoid)))
        (is (< 0.05 (player.body::vdistance travel (player.body::vec3)) 5) "the retargeted travel is ~A" travel)
        (is (< (horizontal-distance at (list (player.body::vec3-x travel) (player.body::vec3-z travel))) 1d-6)
            "the humanoid is at ~A, the retargeted clip travels ~A" at travel)))))

(test wuson-walk-moves-as-far-as-its-root-keys
  "Testwuson's walk keeps its root still (no position keys move), so with
:root :move Wuson stands where it started, as the clip's root keys say."
  (with-assimp-models
    (with-rig-directory (dir)
      (let* ((spec (write-walker-files dir (format nil "(model ~S :height 0.8)
(defscript walk (:duration 3) (:at 0 :clip wuson-walk :root :move :fade 0))" (assimp-model "X/Testwuson.X"))))
             (clip (library-clip dir "wuson-walk"))
             (travel (player.rig:clip-travel clip 2.5d0 nil)))
        (is (< (horizontal-distance (body-position-at spec 2.5)
                                    (list (player.body::vec3-x travel) (player.body::vec3-z travel)))
               1d-9))))))

(test root-move-turns-with-the-body
  "A body turned 90 degrees about its vertical before the clip starts travels
as far, but at right angles to the clip's own travel."
  (with-assimp-models
    (with-rig-directory (dir)
      (let* ((spec (write-walker-files dir (format nil "(model ~S)
(defscript walk (:duration 3)
  (:at 0 :set (:self rotation) (:degrees 0 90 0))
  (:at 0 :clip motion :root :move :fade 0 :for 2))" (assimp-model "BVH/01_01.bvh"))))
             (travel (player.rig:clip-travel (library-clip dir "motion") 2d0 nil))
             (at (body-position-at spec 2)))
        (is (< (abs (- (player.body::vdistance at (player.body::vec3))
                       (player.body::vdistance travel (player.body::vec3))))
               1d-6)
            "the turned body is at ~A, the clip travels ~A" at travel)
        (is (< (abs (player.body::vdot at travel)) 1d-6)
            "the turned body went ~A, not at right angles to the clip's ~A" at travel)))))

;;; Loop seams: a looping clip carries the body steadily

(defun walk-loop-spec (directory library)
  "Write LIBRARY as lib.lisp and a spec in DIRECTORY whose ev-walk, after a
0.2 s op, goes to a walking gait playing LIBRARY's script WALK-LOOP; return
the spec."
  (write-library directory library)
  (let ((path (merge-pathnames "spec.lisp" directory)))
    (with-open-file (out path :direction :output :if-exists :supersede)
      (write-string "(in-package :player-user)
(defspec looper \"Walks on.\" (:scripts \"lib.lisp\")
  (state-variable gait string rest (rest walk))
  (op start-walking :precond gait.rest :add gait.walk :duration 0.2)
  (autoscript gait walk (walk-loop))
  (event ev-walk :state gait.walk))
" out))
    (first (player:load-spec path))))

(defun check-steady-across-seams (simulation direction start seams)
  "Check the body of SIMULATION, walking from START seconds, moves monotonely
along the unit vec3 DIRECTION (sampled every 10 ms to the last of SEAMS plus
0.2 s), and that its speed at each of SEAMS (times) is its speed mid-way
between the walk's start and the first seam, within 5%."
  (flet ((along (time) (player.body::vdot (simulated-position simulation time) direction)))
    (flet ((speed (time) (/ (- (along (+ time 0.02)) (along (- time 0.02))) 0.04)))
      (is (< (abs (along (- start 0.05))) 1d-9) "the body moved before the walk began at ~A s" start)
      (let ((middle (speed (/ (+ start (first seams)) 2))))
        (is (> middle 0.5) "the walk's speed is only ~A: no test" middle)
        (loop for time from start to (+ (car (last seams)) 0.2) by 0.01
              for before = (along time) then now
              for now = (along (+ time 0.01))
              count (< now (- before 1d-9)) into backwards
              finally (is (zerop backwards) "the body went back in ~D of its 10 ms steps" backwards))
        (dolist (seam seams)
          (let ((at-seam (speed seam)))
            (is (< (abs (- at-seam middle)) (* 0.05 middle))
                "at the seam at ~,3F s the speed is ~,3F, mid-clip ~,3F" seam at-seam middle)))))))

(test looping-root-move-advances-steadily-across-seams
  "CMU's 01_01 looped with :root :move (played 24 times as fast, so three
of its cycles take 2.9 s) keeps advancing at each seam where the clip starts
again, as fast as mid-cycle: its travel is each cycle's, spread evenly (the
file's hips go back before each jump, so its keys would take the body back at
every seam).  A script looping every 0.5 s, restarting the looped clip,
likewise."
  (with-assimp-models
    (with-rig-directory (dir)
      (let* ((bvh (assimp-model "BVH/01_01.bvh"))
             (fast (walk-loop-spec dir (format nil "(model ~S)
(defscript walk-loop (:loop t :duration 10) (:at 0 :clip motion :root :move :loop t :speed 24 :fade 0))" bvh)))
             (clip (library-clip dir "motion"))
             (cycle (/ (player.rig::clip-duration clip) 24))
             (travel (player.rig:clip-travel clip (player.rig::clip-duration clip) t))
             (direction (player.body::v* travel (/ (player.body::vdistance travel (player.body::vec3))))))
        (is (> (player.body::vdistance travel (player.body::vec3)) 10) "a cycle travels only ~A: no test" travel)
        (check-steady-across-seams (player:simulate fast :events '(ev-walk) :silent t :until 3.5)
                                   direction 0.2 (loop for k from 1 to 3 collect (+ 0.2 (* k cycle))))
        (let ((restarted (walk-loop-spec dir (format nil "(model ~S)
(defscript walk-loop (:loop t :duration 0.5) (:at 0 :clip motion :root :move :loop t :fade 0))" bvh))))
          (check-steady-across-seams (player:simulate restarted :events '(ev-walk) :silent t :until 2.5)
                                     direction 0.2 '(0.7 1.2 1.7)))))))
