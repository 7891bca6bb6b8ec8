;;;; test-peedy-body.lisp -- specs/peedy-scripts.lisp: Peedy's script library on
;;;; the parrot body.  Every op and autoscript has a motion, durations agree,
;;;; every motor call fits the parrot, and the papers' scenario (asleep;
;;;; ev-search twice; ev-bad-speech; ev-thanks) moves him as it should: the
;;;; note in his right wing, the wing at his ear, the camera pulling back after
;;;; the bow, no joint past its limits, no reach falling short.

(in-package #:player-tests)

(def-suite* peedy-body :in player-tests)

;;; Loading and playing

(defun peedy-body-spec ()
  "specs/peedy.lisp loaded afresh: its one spec."
  (first (load-spec (checkout-file "specs/peedy.lisp"))))

(defun peedy-script-library (&optional (spec (peedy-body-spec)))
  "The script library SPEC's (:scripts ...) option names."
  (player.performance::spec-script-library spec))

(defun peedy-simulation (events &rest initial)
  "Peedy simulated from INITIAL (an alist) through EVENTS (names), no output."
  (player::simulate (peedy-body-spec) :initial initial :events events :stream nil))

(defun peedy-papers-simulation ()
  "The papers' scenario: asleep and sitting; ev-search twice, ev-bad-speech, ev-thanks."
  (peedy-simulation '(ev-search ev-search ev-bad-speech ev-thanks)
                    '(alert . snore) '(posture . sit)))

(defun peedy-op-lines (simulation name)
  "The (:op NAME ...) trace lines of SIMULATION's op called NAME, oldest first."
  (remove-if-not (lambda (line) (and (eq (first line) :op) (string-equal (second line) name)))
                 (trace-lines (player.performance::simulation-presenter simulation))))

(defun peedy-op-start (line)
  "When the op of the trace LINE started."
  (getf (cddr line) :start))

(defun peedy-op-end (line)
  "When the op of the trace LINE ended."
  (getf (cddr line) :end))

(defun peedy-frame-at (simulation time)
  "SIMULATION's scene at TIME."
  (performance-frame (player.performance::simulation-performance simulation) time))

(defun peedy-body-of (simulation)
  "Peedy's body in SIMULATION's current scene."
  (player.performance::simulation-body simulation))

(defun peedy-object (scene name)
  "SCENE's object called NAME (compared by name)."
  (find-object scene name))

(defun peedy-joint-distance (body a b)
  "Metres between BODY's joints (or roles) A and B at its last evaluation."
  (player.body::vdistance (body-joint-position body a) (body-joint-position body b)))

(defun peedy-frame-times (simulation from to)
  "The times of SIMULATION's frames within [FROM, TO]."
  (loop for index from 0 below (player::simulation-frame-count simulation)
        for time = (player.performance::simulation-frame-time simulation index)
        when (<= from time to) collect time))

(defun peedy-lid-closure (body)
  "How far (degrees) BODY's left upper lid is closed."
  (aref (body-pose body) (dof-index (body-skeleton body) 'l_lid 'close)))

;;; The library

(test peedy-library-has-a-motion-for-every-op-and-autoscript
  (let* ((spec (peedy-body-spec))
         (library (peedy-script-library spec))
         (names (player.performance::spec-script-names spec)))
    (is (null (player.performance::missing-scripts library names)))
    ;; 41 script ops (the macro-ops need none) and 5 autoscript procedures.
    (is (= 46 (length names)))
    (is (find "stream" names :test #'string-equal) "search plays the script (or director) stream")
    (is (player::find-director library 'stream) "stream is a director")
    (is (string-equal "parrot" (player.performance::spec-body-name spec)))))

(test peedy-op-durations-are-their-scripts-durations
  (let* ((spec (peedy-body-spec))
         (library (peedy-script-library spec)))
    (is (null (player.performance::script-duration-diagnostics spec library)))
    (is (null (player.performance::script-diagnostics spec)))
    ;; The director of search lasts the op's 3 seconds too.
    (is (= 3 (nth-value 1 (player::director-schedule (player::find-director library 'stream) library 0))))
    (dolist (name '(snore-loop doze-breathe flap-wings tap-foot bob-head))
      (is (player.performance::script-loop (player::find-script library name)) "autoscript ~A loops" name))))

(test peedy-motor-calls-fit-the-parrot
  ;; Poses are resolved when a driver is made; make one for every motor call of
  ;; every script, on a parrot with the library's poses, so a bad joint, pose or
  ;; angle fails here and not in the middle of a run.
  (let* ((library (peedy-script-library))
         (skeleton (player::load-skeleton 'parrot))
         (body (make-body 'peedy skeleton))
         (count 0))
    (setf (player.body::body-pose-library body)
          (player.body::load-pose-library (player.performance::script-library-poses library) :skeleton skeleton))
    (loop for script being the hash-values of (player.performance::script-library-scripts library)
          do (dolist (item (player.performance::script-items script))
               (when (player.performance::motor-item-p item)
                 (incf count)
                 (is (typep (handler-case (make-driver (player.performance::motor-item-call item) body 0)
                              (error (e) e))
                            'player::driver)
                     "script ~A: ~S does not fit the parrot"
                     (player.performance::script-name script) (player.performance::motor-item-frame item)))))
    (is (> count 100))))

;;; The papers' scenario

(test peedy-sleeps-then-wakes-into-the-camera
  (let* ((simulation (peedy-papers-simulation))
         (focus (first (peedy-op-lines simulation 'focus))))
    (peedy-frame-at simulation 0)
    (is (>= (peedy-lid-closure (peedy-body-of simulation)) 60) "asleep from the first frame: lids shut")
    (is (< (abs (- -0.026 (player.body::vec3-y (property-value (peedy-body-of simulation) 'position)))) 1d-9)
        "sitting on the table")
    (peedy-frame-at simulation (peedy-op-end focus))
    (is (<= (peedy-lid-closure (peedy-body-of simulation)) 10) "eyes open after focus")))

(test peedy-search-puts-the-note-in-the-right-wing
  (let* ((simulation (peedy-papers-simulation))
         (skeleton (player::load-skeleton 'parrot))
         (wing (mapcar #'player.body::body-joint-name
                       (cons (skeleton-role skeleton :right-hand) (skeleton-role skeleton :right-arm))))
         (searches (peedy-op-lines simulation 'search))
         (drop (first (peedy-op-lines simulation 'drop-note))))
    (is (= 2 (length searches)))
    (dolist (search searches)
      (let* ((scene (peedy-frame-at simulation (peedy-op-end search)))
             (parent (object-parent (peedy-object scene 'note))))
        (is (consp parent) "after a search the note hangs from a joint")
        (when (consp parent)
          (is (eq (peedy-body-of simulation) (car parent)))
          (is (member (cdr parent) wing :test #'string-equal)
              "the note hangs from ~A, not from the right wing" (cdr parent)))))
    ;; drop-note lets go: the note lies on the table again.
    (let* ((scene (peedy-frame-at simulation (peedy-op-end drop)))
           (note (peedy-object scene 'note)))
      (is (null (object-parent note)))
      (is (< (abs (player.body::vec3-y (object-world-position note))) 0.01)))))

(test peedy-bad-speech-holds-the-wing-to-the-ear
  (let* ((simulation (peedy-papers-simulation))
         (raise (first (peedy-op-lines simulation 'raise-wing)))
         (huh (first (peedy-op-lines simulation 'huh))))
    (peedy-frame-at simulation (peedy-op-end raise))
    (is (< (peedy-joint-distance (peedy-body-of simulation) :right-hand 'head) 0.1)
        "the right wing tip is at the head when raise-wing ends")
    (dolist (time (peedy-frame-times simulation (peedy-op-start huh) (peedy-op-end huh)))
      (peedy-frame-at simulation time)
      (let ((distance (peedy-joint-distance (peedy-body-of simulation) :right-hand 'head)))
        (unless (< distance 0.1)
          (fail "during huh, at ~,2F s, the wing tip is ~,3F m from the head" time distance))))))

(test peedy-thanks-pulls-the-camera-back-three-seconds-after-the-bow
  ;; Label a is the time right after the bow; camgoodbye comes 3 s later.
  (let* ((simulation (peedy-papers-simulation))
         (bow (first (peedy-op-lines simulation 'bow)))
         (goodbye (first (peedy-op-lines simulation 'camgoodbye)))
         (cue (+ (peedy-op-end bow) 3))
         (home (player::vec3 0d0 0.25d0 1.1d0)))
    (is (= cue (peedy-op-start goodbye)))
    (flet ((camera-position (time)
             (object-world-position (peedy-object (peedy-frame-at simulation time) 'camera))))
      (dolist (time (peedy-frame-times simulation 0 cue))
        (unless (< (player.body::vdistance home (camera-position time)) 1d-9)
          (fail "the camera moved at ~,2F s, before ~,2F s" time cue)))
      (is (> (player.body::vdistance home (camera-position (+ cue 0.1))) 1d-4) "moving just after")
      (let ((moves (loop for (a b) on (peedy-frame-times simulation (+ cue 0.05) (peedy-op-end goodbye))
                         while b
                         count (> (player.body::vdistance (camera-position a) (camera-position b)) 1d-6))))
        (is (> moves 30) "still moving through camgoodbye"))
      (is (> (player.body::vdistance home (camera-position (peedy-op-end goodbye))) 0.5) "pulled well back"))))

(test peedy-bows-at-the-stroke
  (let* ((simulation (peedy-papers-simulation))
         (bow (first (peedy-op-lines simulation 'bow)))
         (library (peedy-script-library))
         (stroke (player::script-critical-time (player::find-script library 'bow) 'stroke)))
    (flet ((root-pitch (time)
             (peedy-frame-at simulation time)
             (let ((body (peedy-body-of simulation)))
               (aref (body-pose body) (dof-index (body-skeleton body) 'parrot-root :x)))))
      (let ((lowest (root-pitch (+ (peedy-op-start bow) stroke))))
        (is (> lowest 20) "pitched well forward at the stroke")
        (is (< (abs (root-pitch (peedy-op-end bow))) 1) "upright again after")
        (dolist (time (peedy-frame-times simulation (peedy-op-start bow) (peedy-op-end bow)))
          (is (<= (root-pitch time) (+ lowest 1d-6))))))))

(defun frames-past-limits (simulation)
  "The times of SIMULATION's frames in which Peedy's pose exceeds a joint limit."
  (let ((bad '()))
    (player::map-simulation-frames
     (lambda (index time scene)
       (declare (ignore index scene))
       (let ((body (peedy-body-of simulation)))
         (unless (pose-within-limits-p (body-skeleton body) (body-pose body))
           (push time bad))))
     simulation)
    (nreverse bad)))

(test peedy-papers-scenario-stays-within-limits-and-in-reach
  (let ((simulation (peedy-papers-simulation)))
    (let ((bad (frames-past-limits simulation)))
      (is (null bad) "frames past the joint limits at ~A" bad))
    (is (null (player.performance::simulation-reports simulation)) "drivers reported ~S" (player.performance::simulation-reports simulation))
    (peedy-frame-at simulation (player.performance::simulation-end simulation))
    (is (< (abs (- -0.026 (player.body::vec3-y (property-value (peedy-body-of simulation) 'position)))) 1d-9)
        "he sits down at the end")))

;;; Every op

(defparameter *peedy-tour*
  '(ev-hello ev-search ev-give ev-search ev-found ev-dance ev-next-track ev-stop ev-listen ev-wake
    ev-help ev-no ev-confirm ev-whistle ev-look ev-not-found ev-celebrate ev-fly ev-circle ev-land
    ev-sit ev-preen ev-sleep ev-nap ev-goodbye ev-wake ev-wide ev-cd-done ev-hop ev-idle)
  "Events that, from Peedy's default state, play nearly every op he has.")

(test peedy-tour-plays-every-op-cleanly
  (let* ((simulation (peedy-simulation *peedy-tour*))
         (played (remove-duplicates
                  (loop for line in (trace-lines (player.performance::simulation-presenter simulation))
                        when (eq (first line) :op) collect (string-downcase (second line)))
                  :test #'string=)))
    ;; All but the ops of the papers' scenario (drop-note, raise-wing, huh,
    ;; lower-wing, camgoodbye).
    (dolist (op '("greet" "give-note" "play-cd" "dance" "next-track" "stop-cd" "put-on-phones"
                  "take-off-phones" "scratch-head" "point" "shake-head" "nod" "whistle" "look-around"
                  "shrug" "hop" "bow" "take-off" "fly-loop" "land" "sit" "preen" "doze" "nod-off"
                  "snort" "exhale" "focus" "blink" "stretch" "wave-goodbye" "camwide" "camhello"
                  "standup" "search" "yawn"))
      (is (member op played :test #'string=) "the tour does not play ~A" op))
    (let ((bad (frames-past-limits simulation)))
      (is (null bad) "frames past the joint limits at ~A" bad))
    (is (null (player.performance::simulation-reports simulation)) "drivers reported ~S" (player.performance::simulation-reports simulation))))
