;;;; test-pose-drivers.lisp -- pose libraries and the pose drivers: direct,
;;;; keyframe and pose, lips, beat, idle.  Drivers are mostly checked on their
;;;; own (begin with a pose, drive into a copy) against closed forms, and
;;;; then inside a body, where limits must hold on every frame.

(in-package #:player-tests)

(def-suite* pose-drivers :in player-tests)

;;; ---------------------------------------------------------------------------
;;; Helpers

(defun near (a b &optional (tolerance 1d-6))
  "Are the reals A and B within TOLERANCE?  (Frames written here hold single floats.)"
  (< (abs (- a b)) tolerance))

(defun seconds (time)
  "TIME as a double-float, a single-float literal taken as the decimal it was written as."
  (float (rationalize time) 1d0))

(defun same-form-p (a b)
  "Are the forms A and B equal, symbols compared by name (files are read in PLAYER-USER)?"
  (cond ((and (symbolp a) (symbolp b)) (string= a b))
        ((and (consp a) (consp b)) (and (same-form-p (car a) (car b)) (same-form-p (cdr a) (cdr b))))
        (t (equal a b))))

(defun fresh-body (skeleton)
  "A new body with the shipped SKELETON, in no scene."
  (player::make-body 'test-body skeleton))

(defun dof (body joint dof-name)
  "The pose index of JOINT's DOF-NAME in BODY."
  (player::dof-index (player::body-skeleton body) joint dof-name))

(defun pose-with (body &rest joint-dof-angles)
  "BODY's rest pose with (JOINT DOF ANGLE) triples set."
  (let ((pose (player::make-pose (player::body-skeleton body))))
    (loop for (joint dof-name angle) in joint-dof-angles
          do (setf (aref pose (dof body joint dof-name)) (float angle 1d0)))
    pose))

(defun begun (frame body &key (start 0) (pose (player::make-pose (player::body-skeleton body))))
  "A driver for FRAME on BODY from START, begun with POSE."
  (let ((driver (player::make-driver (player::parse-motor-frame frame) body (seconds start))))
    (player::driver-begin driver pose (seconds start))
    driver))

(defun driven (driver time &optional base)
  "What DRIVER writes at TIME over a copy of BASE (default the rest pose)."
  (let ((pose (player.body::copy-pose (or base (player::make-pose (player.body::driver-skeleton driver))))))
    (player::driver-drive driver (seconds time) pose)
    pose))

(defmacro signals-pose-error ((text &optional (form nil form-p)) &body body)
  "Check that BODY signals a POSE-ERROR whose report contains TEXT (and whose form is FORM)."
  `(let ((condition (handler-case (progn ,@body nil)
                      (player.body::pose-error (c) c))))
     (is (typep condition 'spec-error) "no pose-error from ~S" ',body)
     (when condition
       (is (search ,text (princ-to-string condition))
           "~S does not mention ~S" (princ-to-string condition) ,text)
       ,@(when form-p
           `((is (same-form-p ,form (spec-error-form condition))
                 "the error names ~S, not ~S" (spec-error-form condition) ,form))))))

(defun library-file-error (text)
  "The report of the POSE-ERROR from loading a pose library file holding TEXT, or NIL."
  (uiop:with-temporary-file (:pathname path :stream out :type "lisp")
    (write-string text out)
    :close-stream
    (handler-case (progn (player.body::load-pose-library path) nil)
      (player.body::pose-error (c) (list (princ-to-string c) (spec-error-form c)
                                    (file-namestring path))))))

;;; ---------------------------------------------------------------------------
;;; Pose libraries

(test pose-library-parsing
  (let* ((library (player.body::make-pose-library
                   '((defpose wave "Hand up." (l_shoulder z 90) (l_elbow x -90))
                     (defpose curl (:left-fingers curl 40) (l_index1 curl 10)))))
         (humanoid (player::load-skeleton 'humanoid))
         (wave (player.body::resolve-pose (player.body::find-pose library 'wave) humanoid))
         (curl (player.body::resolve-pose (player.body::find-pose library "CURL") humanoid)))
    (is (equal '("WAVE" "CURL") (mapcar #'string (player.body::pose-library-names library))))
    (is (equal "Hand up." (player.body::pose-definition-documentation (player.body::find-pose library 'wave))))
    (is (equal (list (cons (player::dof-index humanoid 'l_shoulder :z) 90d0)
                     (cons (player::dof-index humanoid 'l_elbow :x) -90d0))
               wave))
    ;; A role sets each of its joints; a later clause overrides an earlier one.
    (is (= 5 (length curl)))
    (is (= 10d0 (cdr (assoc (player::dof-index humanoid 'l_index1 'curl) curl))))
    (is (= 40d0 (cdr (assoc (player::dof-index humanoid 'l_pinky1 'curl) curl))))
    (is (null (player.body::find-pose library 'nothing nil)))
    (signals-pose-error ("no pose nothing") (player.body::find-pose library 'nothing))))

(test pose-library-errors-name-the-clause
  (let ((humanoid (player::load-skeleton 'humanoid)))
    (flet ((resolve (&rest clauses)
             (player.body::resolve-pose
              (player.body::find-pose (player.body::make-pose-library `((defpose p ,@clauses))) 'p)
              humanoid)))
      (signals-pose-error ("no joint l_elbw" '(l_elbw x -10)) (resolve '(l_elbw x -10)))
      (signals-pose-error ("fills no role :crest" '(:crest raise 10)) (resolve '(:crest raise 10)))
      (signals-pose-error ("no role :nose" '(:nose x 1)) (resolve '(:nose x 1)))
      (signals-pose-error ("has no DOF z" '(l_elbow z 10)) (resolve '(l_elbow z 10)))
      (signals-pose-error ("outside its limits -150 to 0" '(l_elbow x 20)) (resolve '(l_elbow x 20)))
      ;; The thumb curls only to 50, so a role clause must fit every joint.
      (signals-pose-error ("limits 0 to 50" '(:left-fingers curl 80)) (resolve '(:left-fingers curl 80)))
      (signals-pose-error ("no pose q" '(:include q)) (resolve '(:include q))))
    (signals-pose-error ("DOF ANGLE pairs" '(l_elbow x)) (player.body::make-pose-library '((defpose p (l_elbow x)))))
    (signals-pose-error ("DOF ANGLE pairs") (player.body::make-pose-library '((defpose p (l_elbow x "ten")))))
    (signals-pose-error ("pose clause" 'l_elbow) (player.body::make-pose-library '((defpose p l_elbow))))
    (signals-pose-error ("only (defpose") (player.body::make-pose-library '((pose p (l_elbow x 0)))))
    (signals-pose-error ("needs a name") (player.body::make-pose-library '((defpose))))
    (signals-pose-error ("sets nothing") (player.body::make-pose-library '((defpose p "doc"))))
    (signals-pose-error ("defined twice")
      (player.body::make-pose-library '((defpose p (l_elbow x 0)) (defpose p (l_elbow x -1)))))
    (signals-pose-error ("includes itself")
      (player.body::resolve-pose
       (player.body::find-pose (player.body::make-pose-library '((defpose a (:include b)) (defpose b (:mirror a))))
                          'a)
       humanoid))))

(test pose-library-file-errors-name-file-and-line
  (destructuring-bind (report form file)
      (library-file-error (format nil ";; poses~%(defpose ok (l_elbow x 0))~%~%(defpose bad (l_elbow x))"))
    (is (search (format nil "~A:4:" file) report) "~S" report)
    (is (same-form-p '(l_elbow x) form)))
  (is (search "could not read" (first (library-file-error "(defpose p (l_elbow x 0)"))))
  (is (search "could not read" (first (library-file-error "(defpose p #.(l_elbow x 0))"))))
  (is (search "only (defpose" (first (library-file-error "(in-package :player)"))))
  (signals-pose-error ("no pose library file")
    (player.body::load-pose-library "/nonexistent/poses.lisp"))
  ;; With a skeleton, loading resolves every pose, and errors name the line.
  (uiop:with-temporary-file (:pathname path :stream out :type "lisp")
    (format out "(defpose a (l_elbow x 0))~%(defpose b (r_elbow x 45))")
    :close-stream
    (is (player.body::load-pose-library path))
    (signals-pose-error (":2: DOF x of joint r_elbow: 45 degrees is outside its limits -150 to 0")
      (player.body::load-pose-library path :skeleton (player::load-skeleton 'humanoid)))))

(test shipped-poses-resolve-within-limits
  (dolist (name '(humanoid parrot))
    (let* ((skeleton (player::load-skeleton name))
           (library (player.body::shipped-pose-library skeleton)))
      (is (<= 10 (length (player.body::pose-library-names library))) "~A ships few poses" name)
      (dolist (pose-name (player.body::pose-library-names library))
        (let* ((entries (player.body::resolve-pose (player.body::find-pose library pose-name) skeleton))
               (pose (player.body::apply-pose-angles entries (player::make-pose skeleton))))
          (is (consp entries))
          (is (player::pose-within-limits-p skeleton pose 0) "~A ~A exceeds a limit" name pose-name)))))
  (let ((parrot (player.body::shipped-pose-library (player::load-skeleton 'parrot))))
    (dolist (pose '(perch-sit stand wings-spread wing-to-ear-right bow beak-open crest-up
                    sleep-tuck fly-up fly-down))
      (is (player.body::find-pose parrot pose nil) "the parrot lacks ~A" pose))))

(test mirrored-poses-mirror-the-figure
  (let* ((skeleton (player::load-skeleton 'parrot))
         (library (player.body::shipped-pose-library skeleton)))
    (flet ((primaries (pose-name joint)
             (let ((pose (player.body::apply-pose-angles
                          (player.body::resolve-pose (player.body::find-pose library pose-name) skeleton)
                          (player::make-pose skeleton))))
               (player::joint-world-position (player::pose-world-transforms skeleton pose)
                                             (player::find-joint skeleton joint)))))
      (let ((right (primaries 'wing-to-ear-right 'r_primaries))
            (left (primaries 'wing-to-ear-left 'l_primaries)))
        (is (near (player.body::vec3-x left) (- (player.body::vec3-x right)) 1d-9))
        (is (near (player.body::vec3-y left) (player.body::vec3-y right) 1d-9))
        (is (near (player.body::vec3-z left) (player.body::vec3-z right) 1d-9))))))

(test body-pose-library-defaults-and-overrides
  (let ((body (fresh-body 'humanoid))
        (other (fresh-body 'humanoid))
        (library (player.body::make-pose-library '((defpose salute (r_shoulder z -90) (r_elbow x -120))))))
    (is (eq (player.body::shipped-pose-library (player::body-skeleton body))
            (player.body::body-pose-library body)))
    (setf (player.body::body-pose-library body) library)
    (is (eq library (player.body::body-pose-library body)))
    (is (player::make-driver (player::parse-motor-frame '(:pose :name salute)) body 0))
    (signals player::motor-error (player::make-driver (player::parse-motor-frame '(:pose :name salute)) other 0))
    (let ((player.body::*pose-library* library))
      (is (player::make-driver (player::parse-motor-frame '(:pose :name salute)) other 0)))
    (setf (player.body::body-pose-library body) nil)
    (is (player.body::find-pose (player.body::body-pose-library body) 'fist))))

;;; ---------------------------------------------------------------------------
;;; Direct, keyframe and pose

(test direct-eases-to-its-targets-and-holds
  (let* ((body (fresh-body 'humanoid))
         (start (pose-with body '(l_elbow x -20)))
         (driver (begun '(:direct :set ((l_elbow x -100) (:left-fingers curl 30)) :duration 0.4)
                        body :start 1 :pose start))
         (elbow (dof body 'l_elbow :x)))
    (is (= 6 (length (player.body::driver-channels driver))))
    (is (near -20 (aref (driven driver 1 start) elbow)))
    ;; smoothstep: 1/4 of the way in time is 5/32 of the way in angle.
    (is (near (+ -20 (* 5/32 -80)) (aref (driven driver 1.1 start) elbow)))
    (is (near -60 (aref (driven driver 1.2 start) elbow)))
    (is (near -100 (aref (driven driver 1.4 start) elbow)))
    (is (near -100 (aref (driven driver 9 start) elbow)))
    (is (near 30 (aref (driven driver 9 start) (dof body 'l_thumb1 'curl))))
    (is (null (player::driver-end-time driver)))))

(defparameter *elbow-keys*
  '((0 ((l_elbow x -20))) (1 ((l_elbow x -60))) (2 ((l_elbow x -100) (l_wrist z -30))))
  "Three keys on the left elbow, the wrist named only by the last.")

(test keyframe-hits-keys-and-closed-forms
  (let* ((body (fresh-body 'humanoid))
         (elbow (dof body 'l_elbow :x))
         (wrist (dof body 'l_wrist :z))
         (start (pose-with body '(l_wrist z 10))))
    (flet ((elbow-at (interpolation time)
             (aref (driven (begun `(:keyframe :keys ,*elbow-keys* :interpolation ,interpolation)
                                  body :start 5 :pose start)
                           (+ 5 time) start)
                   elbow)))
      (dolist (mode '(:step :linear :ease :catmull-rom))
        (loop for time in '(0 1 2) for value in '(-20 -60 -100)
              do (is (near value (elbow-at mode time)) "~A at key ~A" mode time)))
      (is (near -40 (elbow-at :linear 0.5)))
      (is (near -30 (elbow-at :linear 0.25)))
      (is (near (+ -20 (* 5/32 -40)) (elbow-at :ease 0.25)))
      (is (near -40 (elbow-at :ease 0.5)))
      (is (near -20 (elbow-at :step 0.9)))
      ;; Evenly spaced, evenly stepped keys: every Catmull-Rom slope is the same, so it is linear.
      (is (near -80 (elbow-at :catmull-rom 1.5)))
      (is (near -100 (elbow-at :linear 7))))
    (let ((driver (begun `(:keyframe :keys ,*elbow-keys* :interpolation :linear) body :pose start)))
      ;; The wrist keeps its start angle until the one key that names it.
      (is (near 10 (aref (driven driver 1 start) wrist)))
      (is (near -10 (aref (driven driver 1.5 start) wrist)))
      (is (near -30 (aref (driven driver 2 start) wrist)))
      (is (near 2 (player::driver-end-time driver))))))

(test keyframe-start-keys-implicit-start-and-loop
  (let* ((body (fresh-body 'humanoid))
         (elbow (dof body 'l_elbow :x))
         (start (pose-with body '(l_elbow x -30))))
    ;; No key at 0: the first key is eased into from the start pose.
    (let ((driver (begun '(:keyframe :keys ((1 ((l_elbow x -90))) (2 :start)) :interpolation :linear)
                         body :pose start)))
      (is (near -30 (aref (driven driver 0 start) elbow)))
      (is (near -60 (aref (driven driver 0.5 start) elbow)))
      (is (near -90 (aref (driven driver 1 start) elbow)))
      (is (near -30 (aref (driven driver 2 start) elbow))))
    (let ((driver (begun '(:keyframe :keys ((0 ((l_elbow x -10))) (1 ((l_elbow x -50))) (2 ((l_elbow x -10))))
                           :interpolation :linear :loop t)
                         body :start 3 :pose start)))
      (is (null (player::driver-end-time driver)))
      (dolist (time '(0.25 0.5 1.3 1.9))
        (is (near (aref (driven driver (+ 3 time) start) elbow)
                  (aref (driven driver (+ 3 time 2) start) elbow)))
        (is (near (aref (driven driver (+ 3 time) start) elbow)
                  (aref (driven driver (+ 3 time 20) start) elbow) 1d-6)))
      (is (near -30 (aref (driven driver 3.5 start) elbow))))))

(test pose-shorthand-eases-into-a-named-pose
  (let* ((body (fresh-body 'humanoid))
         (driver (begun '(:pose :name fist :duration 0.5) body :start 2))
         (fist (player.body::resolve-pose (player.body::find-pose (player.body::body-pose-library body) 'fist)
                                     (player::body-skeleton body))))
    (is (equal (mapcar #'car fist) (player.body::driver-channels driver)))
    (is (null (player::driver-end-time driver)))
    (loop for (index . angle) in fist
          do (is (near 0 (aref (driven driver 2) index)))
             (is (near (/ angle 2) (aref (driven driver 2.25) index)))
             (is (near angle (aref (driven driver 2.5) index)))
             (is (near angle (aref (driven driver 30) index))))))

(test keyframe-through-a-body
  (let* ((body (fresh-body 'humanoid))
         (elbow (dof body 'l_elbow :x)))
    (player::body-add-driver
     body (player::make-driver (player::parse-motor-frame
                                `(:keyframe :keys ,*elbow-keys* :interpolation :linear :blend 0))
                               body 1))
    (is (near 0 (aref (player::body-evaluate body 0.5) elbow)))
    (is (near -40 (aref (player::body-evaluate body 1.5) elbow)))
    (is (near -100 (aref (player::body-evaluate body 3) elbow)))
    ;; Ended: the body holds the last angle.
    (is (near -100 (aref (player::body-evaluate body 5) elbow)))
    (is (null (player.body::body-active body)))))

;;; ---------------------------------------------------------------------------
;;; Lips, beat, idle

(defparameter *speech* '((0.1 :aa) (0.3 :mm) (0.5 :oh) (0.7 :rest))
  "A short viseme list: open wide, shut, round, rest.")

(test lips-open-and-close-the-jaw
  (loop for (skeleton joint widest) in '((humanoid temporomandibular 28) (parrot beak 35))
        do (let* ((body (fresh-body skeleton))
                  (jaw (dof body joint 'open))
                  (driver (begun `(:lips :visemes ,*speech*) body :start 1)))
             (is (equal (list jaw) (player.body::driver-channels driver)))
             (is (near 0 (aref (driven driver 1) jaw)))
             (is (near widest (aref (driven driver 1.1) jaw)) "~A jaw at :aa" skeleton)
             (is (near 0 (aref (driven driver 1.3) jaw)) "~A jaw at :mm" skeleton)
             (is (near (* 0.7 widest) (aref (driven driver 1.5) jaw)))
             (is (< 0 (aref (driven driver 1.07) jaw) widest) "the ramp into :aa")
             (is (near 1.7 (player::driver-end-time driver)))
             (is (loop for time from 1 to 1.7 by 0.005
                       always (<= 0 (aref (driven driver time) jaw) widest))))))

(test beat-flicks-the-forearm-at-each-beat-and-returns
  (let* ((body (fresh-body 'humanoid))
         (start (pose-with body '(r_elbow x -90)))
         (driver (begun '(:beat :arm :right :times (0.5 1.0) :stroke 0.1 :retract 0.25)
                        body :start 2 :pose start))
         (elbow (dof body 'r_elbow :x))
         (skeleton (player::body-skeleton body)))
    (flet ((hand-height (pose)
             (player.body::vec3-y (player.body::hand-point skeleton pose (player::find-joint skeleton 'r_wrist)
                                                 (player.body::identity-transform)))))
      (dolist (beat '(2.5 3.0))
        (is (near -78 (aref (driven driver beat start) elbow)) "elbow at the beat ~A" beat)
        (is (< (hand-height (driven driver beat start)) (- (hand-height start) 0.03)))
        (is (near -90 (aref (driven driver (+ beat 0.25) start) elbow)))
        (is (near -90 (aref (driven driver (- beat 0.1) start) elbow))))
      (is (near -90 (aref (driven driver 2 start) elbow)))
      (is (< -90 (aref (driven driver 2.45 start) elbow) -78))
      (is (near 3.25 (player::driver-end-time driver)))))
  ;; The parrot's wing beats through its arm chain.
  (let* ((body (fresh-body 'parrot))
         (start (player.body::apply-pose-angles
                 (player.body::resolve-pose (player.body::find-pose (player.body::body-pose-library body) 'wings-spread)
                                       (player::body-skeleton body))
                 (player::make-pose (player::body-skeleton body))))
         (driver (begun '(:beat :arm :left :times (0.3)) body :pose start))
         (moved (remove-if (lambda (i) (near (aref start i) (aref (driven driver 0.3 start) i)))
                           (player.body::driver-channels driver))))
    (is (member (dof body 'l_elbow 'unfold) moved))
    (is (equalp start (driven driver 0.6 start)))))

(test idle-is-additive-bounded-continuous-and-seeded
  (let* ((body (fresh-body 'humanoid))
         (driver (begun '(:idle :amplitude 3 :frequency 0.5 :seed 7 :joints (:spine :head)) body))
         (same (begun '(:idle :amplitude 3 :frequency 0.5 :seed 7 :joints (:spine :head)) body))
         (other (begun '(:idle :amplitude 3 :frequency 0.5 :seed 8 :joints (:spine :head)) body))
         (channels (player.body::driver-channels driver))
         (base (pose-with body '(vl5 x 10))))
    (is-true (player::driver-additive-p driver))
    (is (equal (append (player.body::joint-dof-indices (player::find-joint (player::body-skeleton body) 'vl5))
                       (player.body::joint-dof-indices (player::find-joint (player::body-skeleton body) 'skullbase)))
               channels))
    (is (equalp base (driven driver 0 base)) "the drift fades in from nothing")
    (let ((previous (driven driver 0 base)) (largest 0) (step 0) (differs nil))
      (loop for time from 0.001 to 6 by 0.001
            for pose = (driven driver time base)
            do (dolist (i channels)
                 (setf largest (max largest (abs (- (aref pose i) (aref base i))))
                       step (max step (abs (- (aref pose i) (aref previous i))))))
               (unless (equalp pose (driven same time base)) (return (fail "same seed, other drift")))
               (unless (equalp pose (driven other time base)) (setf differs t))
               (setf previous pose))
      (is (<= largest 3) "drift ~A exceeds the amplitude" largest)
      (is (< 0.5 largest) "drift ~A is hardly there" largest)
      (is (< step 0.05) "a jump of ~A degrees in a millisecond" step)
      (is-true differs))
    ;; In a body it owns no channel: it adds to what the others compose.
    (let ((drifting (fresh-body 'humanoid)))
      (player::body-add-driver drifting (player::make-driver (player::parse-motor-frame '(:idle :seed 7))
                                                             drifting 0))
      (player::body-evaluate drifting 2)
      (is (every #'null (player.body::body-owners drifting)))
      (is (not (equalp (player::body-pose drifting) (player.body::body-base drifting)))))))

;;; ---------------------------------------------------------------------------
;;; Limits and bad frames

(test drivers-keep-within-limits-on-every-frame
  (let* ((body (fresh-body 'humanoid))
         (skeleton (player::body-skeleton body))
         ;; Catmull-Rom overshoots 0 (the elbow's limit) after the middle key.
         (keys (begun '(:keyframe :keys ((0 ((l_elbow x -100))) (1 ((l_elbow x 0))) (2 ((l_elbow x 0))))
                        :interpolation :catmull-rom)
                      body)))
    (is (loop for time from 0 to 2 by 0.01
              always (player::pose-within-limits-p skeleton (driven keys time) 0)))
    (is (near 0 (aref (driven keys 1.25) (dof body 'l_elbow :x))))
    (dolist (frame '((:pose :name arms-raised :duration 0.4)
                     (:beat :arm :left :times (0.2 0.5 0.6 0.7 1.5) :amplitude 3)
                     (:keyframe :keys ((0.3 fist) (0.6 open) (0.9 hands-on-hips) (1.2 bow-down))
                      :interpolation :catmull-rom :loop t :priority 12)
                     (:lips :visemes ((0 :aa) (0.05 :mm) (0.1 :aa) (1 :rest)) :scale 2)
                     (:idle :amplitude 40 :frequency 2 :joints (:spine :left-arm :right-arm :jaw))
                     (:direct :set ((l_shoulder x -180) (l_elbow x -150) (vl5 x 80)) :duration 0.2 :priority 5)))
      ;; What each driver aims at is within the limits, before the body clamps.
      (let ((driver (begun frame body)))
        (unless (player::driver-additive-p driver)
          (is (loop for time from 0 to 3 by 1/60
                    always (player::pose-within-limits-p skeleton (driven driver time) 0))
              "~S aims outside the limits" frame)))
      (player::body-add-driver body (player::make-driver (player::parse-motor-frame frame) body 0.1)))
    (is (loop for time from 0 to 3 by 1/60
              always (player::pose-within-limits-p skeleton (player::body-evaluate body time) 0)))))

(test bad-pose-driver-frames-are-motor-errors
  (dolist (frame '((:direct)
                   (:direct :set 5)
                   (:direct :set ())
                   (:direct :set (l_elbow x -10))
                   (:direct :set ((nojoint x 1)))
                   (:direct :set ((:crest raise 10)))
                   (:direct :set ((l_elbow z 10)))
                   (:direct :set ((l_elbow x 10)))
                   (:direct :set ((l_elbow x -10)) :duration -1)
                   (:keyframe :keys ((0 nopose)))
                   (:keyframe :keys ((1 fist) (0.5 open)))
                   (:keyframe :keys ((-1 fist)))
                   (:keyframe :keys ((0 fist) (1)))
                   (:keyframe :keys ((0 fist)) :interpolation :cubic)
                   (:keyframe :keys ((0 ((l_elbow x 1))) (1 fist)))
                   (:pose :name nopose)
                   (:pose)
                   (:lips :visemes ((0 :zz)))
                   (:lips :visemes ((0.5 :aa) (0.2 :mm)))
                   (:lips :visemes ())
                   (:lips :visemes (0.5 :aa))
                   (:beat :times ())
                   (:beat :times (0.5 0.2))
                   (:beat :arm :middle :times (1))
                   (:idle :seed 1.5)
                   (:idle :joints (:crest))
                   (:idle :joints (nojoint))
                   (:idle :joints ())))
    (let ((condition (handler-case (progn (player::make-driver (player::parse-motor-frame frame)
                                                               (fresh-body 'humanoid) 0)
                                          nil)
                       (player::motor-error (c) c))))
      (is (typep condition 'player::motor-error) "no motor-error from ~S" frame)
      (when condition
        (is (eq frame (spec-error-form condition)))))))
