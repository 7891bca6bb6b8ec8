;;;; test-retarget.lisp -- clips played on another skeleton (src/rig/retarget.lisp,
;;;; dof-layouts.lisp, clip-files.lisp) and the :clip item's :from file: the
;;;; identity on a clip's own skeleton, CMU motion capture on the humanoid, a
;;;; BVH Player wrote read back, and bad files failing at the item's line.

(in-package #:player-tests)

(def-suite* retarget :in player-tests)

(defparameter *cmu-bvh* "/usr/share/assimp/models/BVH/01_01.bvh"
  "CMU motion capture subject 1, trial 1 (Debian's assimp-testmodels): 2,751 frames at 120 fps.")

(defmacro with-cmu ((&optional (skeleton (gensym "SKELETON"))) &body body)
  "Run BODY with SKELETON the model skeleton of *CMU-BVH*; skip when it is missing."
  `(if (probe-file *cmu-bvh*)
       (let ((,skeleton (player.rig:clip-file-source *cmu-bvh*)))
         (declare (ignorable ,skeleton))
         ,@body)
       (skip "no ~A (Debian assimp-testmodels)" *cmu-bvh*)))

(defun clip-pose (clip skeleton time)
  "SKELETON's pose (rest where CLIP does not reach) with CLIP's angles at TIME,
each track decomposed into its joint's own DOFs, as the clip driver writes them."
  (let* ((pose (player.body::make-pose skeleton))
         (layouts (or (player.rig::clip-layouts clip skeleton)
                      (make-array (length (player.rig:clip-tracks clip)) :initial-element nil)))
         (angles (player.rig:clip-dof-angles clip time layouts
                                             (make-array (* 3 (length (player.rig:clip-tracks clip)))
                                                         :element-type 'double-float))))
    (loop for track across (player.rig:clip-tracks clip)
          for offset from 0 by 3
          do (loop for index in (player.rig::track-pose-indices skeleton track)
                   for n from 0
                   unless (minusp index)
                     do (setf (aref pose index) (aref angles (+ offset n)))))
    pose))

(defun bone-direction (skeleton pose from to)
  "The world direction, a unit vec3, from SKELETON's joint FROM to joint TO in POSE."
  (let ((transforms (pose-world-transforms skeleton pose)))
    (player.body::vnormalize
     (player.body::v- (player.body::joint-world-position transforms (find-joint skeleton to))
                      (player.body::joint-world-position transforms (find-joint skeleton from))))))

(defun degrees-between (a b)
  "The angle between the unit vec3s A and B, in degrees."
  (* (/ 180 pi) (acos (max -1d0 (min 1d0 (player.body::vdot a b))))))

;;;# (a) A clip retargeted onto its own skeleton is itself

(test retarget-onto-own-skeleton-is-identity
  (with-cmu (source)
    (let* ((own (player.rig:find-clip (player.rig::skeleton-rig source) "motion"))
           (again (retarget-clip source "motion" source))
           (worst 0d0))
      (dolist (time '(0d0 0.004d0 1d0 5.5d0 11.2581d0 17d0 22.9d0))
        (let ((a (clip-angles own time)) (b (clip-angles again time)))
          (loop for track across (player.rig:clip-tracks own)
                for i from 0
                for k = (position (player.rig:track-joint track) (player.rig:clip-tracks again)
                                  :key #'player.rig:track-joint)
                do (is (integerp k) "joint ~D has no track" (player.rig:track-joint track))
                   (when k
                     (dotimes (n 3)
                       (setf worst (max worst (abs (- (aref a (+ (* 3 i) n)) (aref b (+ (* 3 k) n)))))))))))
      (is (< worst 1d-6) "angles differ by ~A degrees" worst))))

;;;# (b) CMU motion capture on the humanoid

(test cmu-plays-on-the-humanoid
  (with-cmu (source)
    (let* ((humanoid (load-skeleton 'humanoid))
           (clip (retarget-clip source "motion" humanoid))
           (own (player.rig:find-clip (player.rig::skeleton-rig source) "motion"))
           (elbow (player.body::dof-index humanoid 'l_elbow 'x))
           (knee (player.body::dof-index humanoid 'l_knee 'x))
           (elbows '()) (knees '()))
      (loop for time from 0d0 below (clip-duration clip) by 0.25d0
            for pose = (clip-pose clip humanoid time)
            do (push (aref pose elbow) elbows)
               (push (aref pose knee) knees)
               (is (player.body::pose-within-limits-p humanoid pose) "a pose past a limit at ~A s" time))
      (is (> (- (reduce #'max elbows) (reduce #'min elbows)) 20) "the left elbow hardly moves: ~A" elbows)
      (is (> (- (reduce #'max knees) (reduce #'min knees)) 10) "the left knee hardly moves: ~A" knees)
      ;; The upper arms point where the subject's do.  Exactly, but for what
      ;; the humanoid cannot do: its trunk (vl5) and shoulders clamp to their
      ;; ranges of motion, which a T-posed subject's arm swings approach; 10
      ;; degrees covers those clamps, a wrong axis or side is off by 45 or more.
      (dolist (time '(0.5d0 3d0 6d0 9d0 12d0 15d0))
        (loop for (mine-from mine-to theirs-from theirs-to) in '((l_shoulder l_elbow "LeftArm" "LeftForeArm")
                                                                  (r_shoulder r_elbow "RightArm" "RightForeArm"))
              for off = (degrees-between (bone-direction humanoid (clip-pose clip humanoid time) mine-from mine-to)
                                         (bone-direction source (clip-pose own source time) theirs-from theirs-to))
              do (is (< off 10) "at ~A s the humanoid's ~A points ~,1F degrees off the subject's" time mine-from off))))))

;;;# (c) A BVH Player wrote reads back as a clip

(test written-bvh-round-trips-as-a-clip
  (uiop:with-temporary-file (:pathname path :type "bvh")
    (let* ((spec (first (load-spec (checkout-file "examples/tutorial/robbie.lisp"))))
           (simulation (simulate spec :events '(ev-hello ev-thanks) :fps 30))
           (humanoid (load-skeleton 'humanoid))
           (poses '()))
      (player.performance::map-simulation-frames
       (lambda (index time scene)
         (declare (ignore index time scene))
         (push (player.body::copy-pose (player.body::body-pose (player.performance::simulation-body simulation))) poses))
       simulation)
      (setf poses (coerce (nreverse poses) 'vector))
      (write-bvh-file path humanoid poses :frame-time (/ 1d0 30))
      (let* ((clip (retarget-clip (import-model path) "motion" humanoid))
             (worst 0d0))
        (loop for i from 0 below (length poses) by 3
              for pose = (clip-pose clip humanoid (/ i 30d0))
              do (loop for joint across (skeleton-joints humanoid)
                       for written = (player.body::joint-local-rotation joint (aref poses i))
                       for read = (player.body::joint-local-rotation joint pose)
                       do (setf worst (max worst (player.body::quat-angle written read)))))
        (is (< worst 1d-4) "a joint turns ~A rad off what was written" worst)))))

;;;# (d) Bad :from files fail at the item's line

(defun error-line (condition)
  "The line CONDITION's position names, or NIL."
  (let ((position (spec-error-position condition)))
    (and position (cdr position) (player.base::position-line (car position) (cdr position)))))

(defun clip-item-error (from &optional (name "motion"))
  "Two values: the SCRIPT-ERROR reading a library whose script's second line
plays NAME :from FROM, and the line it names."
  (uiop:with-temporary-file (:pathname path :stream out :type "lisp" :direction :output :keep t)
    (format out "(defscript dance ()~%  (:at 0 :clip ~A :from ~S))~%" name from)
    (finish-output out)
    :close-stream
    (unwind-protect
         (handler-case (progn (load-script-library path) nil)
           (script-error (condition) (values condition (error-line condition))))
      (delete-file path))))

(test bad-from-files-fail-at-the-items-line
  (multiple-value-bind (missing line) (clip-item-error "/nonexistent/walk.bvh")
    (is (typep missing 'script-error))
    (is (eql 2 line))
    (is (search "no clip file" (princ-to-string missing)) "~A" missing))
  (uiop:with-temporary-file (:pathname garbage :stream out :type "bvh")
    (write-line "HIERARCHY { this is not a skeleton" out)
    (finish-output out)
    (multiple-value-bind (unreadable line) (clip-item-error (namestring garbage))
      (is (typep unreadable 'script-error))
      (is (eql 2 line))
      (is (search (file-namestring garbage) (princ-to-string unreadable)) "~A" unreadable)))
  (with-cmu ()
    (multiple-value-bind (unknown line) (clip-item-error *cmu-bvh* "jump")
      (is (typep unknown 'script-error))
      (is (eql 2 line))
      (is (search "motion" (princ-to-string unknown)) "the clips are not listed: ~A" unknown))))

(test from-clip-counts-in-the-scripts-duration
  (with-cmu ()
    (uiop:with-temporary-file (:pathname path :stream out :type "lisp" :direction :output :keep t)
      (format out "(defscript dance ()~%  (:at 1 :clip motion :from ~S :speed 2))~%" *cmu-bvh*)
      :close-stream
      (unwind-protect
           (let* ((library (load-script-library path))
                  (script (find-script library 'dance)))
             (is (< (abs (- (script-duration script) (+ 1 (/ 22.9249d0 2)))) 1d-3)
                 "the script lasts ~A s" (script-duration script)))
        (delete-file path)))))
