;;;; performance.lisp -- scripts played on a scene: which scripts started when
;;;; (and stopped when), and the frame that follows for any time.  Evaluation
;;;; is a pure function of the time and the runs: a performance replays from
;;;; the start whenever asked for an earlier time, so a user can scrub and two
;;;; evaluations of the same time give the same frame.

(in-package #:player.performance)

(defstruct (script-run (:constructor make-script-run (script start stop body loop &optional settles)))
  "SCRIPT started at START on BODY (a body's name), until STOP (or NIL), repeated when LOOP;
when SETTLES, the channels it drove settle once it is over (settle.lisp).
The rest is what the current replay has made of it."
  (script nil :read-only t)
  (start 0d0 :type double-float :read-only t)
  (stop nil)
  (body nil :read-only t)
  (loop nil :read-only t)
  (settles nil :read-only t)
  (settled nil)
  (iterations 0 :type fixnum)
  (next-begin nil)
  (drivers '())
  (bindings '())
  (children '())
  (clips '()))

(defstruct (binding (:constructor make-binding (object property control start end)))
  "CONTROL (or a constant value) drives OBJECT's PROPERTY from START until END (or NIL)."
  object property control start end)

(defstruct (cue (:constructor make-cue (time item run iteration-end)))
  "A script item due at TIME in RUN, whose iteration ends at ITERATION-END."
  (time 0d0 :type double-float) item run iteration-end)

(defstruct (character-spec (:constructor make-character-spec (name skeleton position rotation
                                                             &optional (visible t))))
  "A body the performance puts in its scene; not drawn unless VISIBLE."
  name skeleton position rotation visible)

;;; A scene of props alone (Newton's cradle) still has a character: scripts
;;; play on one (:self) and the presenters expect a body.  The skeleton NONE
;;; gives it a stand-in body that is never drawn.

(defparameter *stand-in-skeleton* 'humanoid
  "The skeleton of the hidden character a performance gets for the skeleton NONE.")

(defun no-body-p (designator)
  "Does DESIGNATOR (a skeleton's name) ask for no visible character: NONE?"
  (and (or (symbolp designator) (stringp designator)) (string-equal designator "NONE")))

(defun character-skeleton (designator)
  "The SKELETON DESIGNATOR names (a skeleton, a name or a path for LOAD-SKELETON;
NONE: *STAND-IN-SKELETON*), and whether its body is drawn."
  (cond ((skeleton-p designator) (values designator t))
        ((no-body-p designator) (values (load-skeleton *stand-in-skeleton*) nil))
        (t (values (load-skeleton designator) t))))

(defclass performance ()
  ((library :initarg :library :reader performance-library)
   (characters :initarg :characters :reader performance-characters
               :documentation "CHARACTER-SPECs, the first one playing scripts by default.")
   (seed :initarg :seed :initform 0 :reader performance-seed)
   (silent :initarg :silent :initform nil :reader performance-silent
           :documentation "True when :say and :sound items play nothing (no sound, no beak).")
   (poses :initform nil :accessor performance-poses
          :documentation "The pose library the library's (poses FILE) names, loaded, or NIL.")
   (blend-time :initarg :blend-time :initform *default-blend-time* :reader performance-blend-time)
   (origin :initarg :origin :initform nil :reader performance-origin
           :documentation "NIL, or a vec3: where the whole scene stands in the world.  A
scene cast with others (src/cast/) is moved there by hanging everything that
would hang from the world from a group object, its stage, at ORIGIN.")
   (runs :initform '() :accessor performance-runs :documentation "Top-level runs, newest first.")
   (starting-pose :initform nil :accessor performance-starting-pose
                  :documentation "The STARTING-POSE the first character starts in (starting-pose.lisp), or NIL.")
   (captions :initform '() :accessor performance-captions
             :documentation "CAPTIONs shown over the frames, newest first (see captions.lisp).")
   (settle-targets :initform '() :accessor performance-settle-targets
                   :documentation "SETTLE-TARGETs, oldest first: when the first character's settled pose changes (settle.lisp).")
   (tempi :initform '() :accessor performance-tempi
          :documentation "((TIME . BPM) ...), newest first: the music's tempo from TIME on (BPM NIL: none).")
   (reaction-state :initform nil :accessor performance-reaction-state
                   :documentation "What its reactive directors need (reactions.lisp), made on first use.")
   (settle-state :initform nil :accessor replay-settle-state
                 :documentation "The SETTLE-TARGET in force in the replay, and those still to come.")
   ;; The replay: rebuilt from the runs whenever time goes back.
   (scene :initform nil :accessor performance-scene)
   (all-runs :initform '() :accessor replay-runs)
   (cues :initform '() :accessor replay-cues)
   (bindings :initform '() :accessor replay-bindings)
   (clips :initform '() :accessor replay-clips :documentation "The audio clips started so far, newest first.")
   (time :initform nil :accessor performance-time)
   (stale :initform t :accessor replay-stale))
  (:documentation "A script library, the characters it is played on, and the
scripts started so far.  PERFORMANCE-FRAME gives the scene at any time."))

(defun characters-p (x)
  "Is X a nonempty proper list of (NAME SKELETON [POSITION [ROTATION]]) entries?"
  (and (consp x) (proper-form-list-p x)
       (every (lambda (entry)
                (and (alexandria:proper-list-p entry) (<= 2 (length entry) 4)
                     (string-designator-p (first entry))
                     (let ((skeleton (second entry)))
                       (or (skeleton-p skeleton) (symbolp skeleton) (pathname-designator-p skeleton)))
                     (or (null (cddr entry)) (finite-vec3-p (third entry)))
                     (or (null (cdddr entry))
                         (and (finite-quat-p (fourth entry)) (plusp (qnorm (fourth entry)))))))
              x)))

(defun performance-p (x)
  "Is X a performance?"
  (typep x 'performance))

(defun make-performance (library characters &key (seed 0) (blend-time *default-blend-time*) origin silent)
  "A performance of LIBRARY on CHARACTERS, each (NAME SKELETON [POSITION [ROTATION]])
with SKELETON a SKELETON or the name of one; SEED seeds the random drivers.
With ORIGIN (a vec3) the characters, props and cameras hang from the group
object STAGE standing there, so the whole scene plays moved by ORIGIN.
With SILENT, speech and sounds play nothing (so no speech library is needed)."
  (check-argument 'make-performance 'library library #'script-library-p "a script library (from load-script-library)")
  (check-argument 'make-performance 'characters characters #'characters-p
                  "a nonempty proper list of (name skeleton [position [rotation]]), names symbols or strings, skeletons a skeleton or its name, positions vec3s, rotations nonzero quats")
  (check-real 'make-performance :seed seed :integer t)
  (check-real 'make-performance :blend-time blend-time :minimum 0 :maximum *max-seconds*)
  (check-argument 'make-performance :origin origin (lambda (x) (or (null x) (finite-vec3-p x)))
                  "NIL or a vec3 of finite numbers")
  (let ((performance
          (make-instance 'performance
                         :library library :seed seed :blend-time blend-time :origin origin :silent (and silent t)
                         :characters (mapcar (lambda (entry)
                                               (destructuring-bind (name skeleton &optional (position (vec3))
                                                                                    (rotation (quat)))
                                                   entry
                                                 (multiple-value-bind (skeleton visible)
                                                     (character-skeleton skeleton)
                                                   (make-character-spec name skeleton position rotation visible))))
                                             characters))))
    (when (script-library-poses library)
      (setf (performance-poses performance)
            (let ((skeleton (character-spec-skeleton (first (performance-characters performance)))))
              ;; The shipped poses stay under the library's own.
              (load-pose-library (script-library-poses library) :skeleton skeleton
                                                                :fallback (shipped-pose-library skeleton)))))
    (rebuild-scene performance)
    performance))

(defun performance-character (performance)
  "The name of the body scripts play on unless told otherwise."
  (character-spec-name (first (performance-characters performance))))

(defun performance-body (performance &optional (name nil name-given))
  "The body called NAME (default: the first character's) in PERFORMANCE's current scene."
  (check-argument 'performance-body 'performance performance #'performance-p "a performance (from make-performance)")
  (if name-given
      (check-argument 'performance-body 'name name #'string-designator-p "a body's name (a symbol or string)")
      (setf name (performance-character performance)))
  (find-object (performance-scene performance) name))

;;;# Starting and stopping

(defun perform-script (performance name start &key stop body loop settle)
  "Start the script NAME of PERFORMANCE's library at START on BODY (default: the
first character); LOOP repeats it even when the script does not loop; with
SETTLE, the channels and the place it drove settle to the settled pose once it
is over (PERFORMANCE-SETTLE-TO), instead of holding where it left them.
Returns the SCRIPT-RUN; its duration is the script's."
  (check-argument 'perform-script 'performance performance #'performance-p "a performance (from make-performance)")
  (check-argument 'perform-script 'name name #'string-designator-p "a script's name (a symbol or string)")
  (check-seconds 'perform-script 'start start)
  (when stop (check-seconds 'perform-script :stop stop))
  (when body (check-body-name 'perform-script performance body))
  (let ((script (find-script (performance-library performance) name t)))
    (add-script-run performance
                    (make-script-run script (float start 1d0) (and stop (float stop 1d0))
                                     (or body (performance-character performance))
                                     (or loop (script-loop script)) (and settle t)))))

(defun add-script-run (performance run)
  "Add RUN to PERFORMANCE's runs (the replay goes stale if it starts before
the time last shown); returns RUN."
  (push run (performance-runs performance))
  (unless (replay-stale performance)
    (if (and (performance-time performance) (< (script-run-start run) (performance-time performance)))
        (setf (replay-stale performance) t)
        ;; Oldest first, as a replay has them: equal-time cues keep the order runs started in.
        (setf (replay-runs performance) (append (replay-runs performance) (list run)))))
  run)

(defun check-body-name (function performance body)
  "BODY when it names one of PERFORMANCE's characters; else an ARGUMENT-ERROR of FUNCTION."
  (check-argument function :body body
                  (lambda (x) (and (string-designator-p x)
                                   (find x (performance-characters performance)
                                         :key #'character-spec-name :test #'string-equal)))
                  (format nil "the name of one of the performance's characters (~{~A~^, ~})"
                          (mapcar (lambda (c) (lisp-text (character-spec-name c)))
                                  (performance-characters performance)))))

(defun perform-director (performance name start &key body settle)
  "Start the director NAME at START: its scripts at the times its schedule gives
\(each settling when over, with SETTLE: see PERFORM-SCRIPT), its :set and
:send steps at theirs, and, once it ends, the directors written (:after NAME)
\(reactions.lisp).  Returns its duration (NIL when it loops for ever)."
  (check-argument 'perform-director 'performance performance #'performance-p "a performance (from make-performance)")
  (check-argument 'perform-director 'name name #'string-designator-p "a director's name (a symbol or string)")
  (check-seconds 'perform-director 'start start)
  (when body (check-body-name 'perform-director performance body))
  (let ((director (find-director (performance-library performance) name t)))
    (multiple-value-bind (schedule duration actions)
        (director-schedule director (performance-library performance) start)
      (loop for (script script-start script-stop) in schedule
            do (perform-script performance script script-start :stop script-stop :body body :settle settle))
      (director-started performance director (float start 1d0) duration actions)
      duration)))

(defun stop-script-run (performance run time)
  "Stop RUN (and what it started) at TIME."
  (check-argument 'stop-script-run 'performance performance #'performance-p "a performance (from make-performance)")
  (check-argument 'stop-script-run 'run run #'script-run-p "a script run (from perform-script)")
  (check-seconds 'stop-script-run 'time time)
  (let ((time (float time 1d0)))
    (setf (script-run-stop run) (if (script-run-stop run) (min time (script-run-stop run)) time))
    (if (and (performance-time performance) (< time (performance-time performance)))
        (setf (replay-stale performance) t)
        (stop-run-effects performance run time))))

(defun stop-run-effects (performance run time)
  "Cut what the replay made of RUN at TIME: its drivers, bindings and children."
  (dolist (driver (script-run-drivers run))
    (body-stop-driver (driver-body driver) driver time))
  (dolist (binding (script-run-bindings run))
    (when (or (null (binding-end binding)) (> (binding-end binding) time))
      (setf (binding-end binding) time)))
  (dolist (clip (script-run-clips run))
    (setf (clip-cut clip) (if (clip-cut clip) (min time (clip-cut clip)) time)))
  (dolist (child (script-run-children run))
    (setf (script-run-stop child) (if (script-run-stop child) (min time (script-run-stop child)) time))
    (stop-run-effects performance child time)))

;;;# The replay

(defparameter *stage-name* '%stage
  "The name of the group object a performance with an origin hangs its scene from.")

(defun performance-stage (performance)
  "The group object PERFORMANCE's scene hangs from (see PERFORMANCE-ORIGIN), or NIL."
  (and (performance-origin performance)
       (find-object (performance-scene performance) *stage-name* nil)))

(defun rebuild-scene (performance)
  "Start the replay over: a fresh scene at its initial state, every run unplayed."
  (let* ((scene (make-instance 'scene))
         (library (performance-library performance))
         (stage (and (performance-origin performance)
                     (add-object scene (make-instance 'scene-object :name *stage-name* :kind :group
                                                                    :position (performance-origin performance))))))
    (dolist (spec (performance-characters performance))
      (let ((body (make-body (character-spec-name spec) (character-spec-skeleton spec)
                             :scene scene :position (character-spec-position spec)
                             :rotation (character-spec-rotation spec)
                             :blend-time (performance-blend-time performance))))
        (setf (object-parent body) stage)
        (setf (body-seed body) (performance-seed performance))
        (unless (character-spec-visible spec)
          (setf (property-value body 'visible) nil))
        (when (performance-poses performance)
          (setf (body-pose-library body) (performance-poses performance)))))
    (setf (performance-scene performance) scene)
    (start-performance-pose performance)
    (start-performance-idle-life performance)
    (dolist (spec (script-library-objects library))
      (let ((object (apply #'make-instance
                           (if (scene-object-spec-prop-model spec) 'model-prop 'scene-object)
                           :name (scene-object-spec-name spec)
                           :kind (scene-object-spec-kind spec)
                           :position (scene-object-spec-position spec)
                           :rotation (scene-object-spec-rotation spec)
                           (and (scene-object-spec-prop-model spec)
                                (list :prop-model (scene-object-spec-prop-model spec))))))
        (loop for (name type value) in (scene-object-spec-properties spec)
              do (define-property object name type value))
        (setf (object-parent object) stage)
        (add-object scene object)))
    (setf (performance-scene performance) scene)
    (dolist (spec (script-library-objects library))
      (when (scene-object-spec-parent spec)
        (setf (object-parent (find-object scene (scene-object-spec-name spec)))
              (resolve-parent performance (scene-object-spec-parent spec) nil))))
    (dolist (run (performance-runs performance))
      (reset-run run))
    (setf (replay-settle-state performance) (cons (initial-settle-target performance)
                                                  (performance-settle-targets performance)))
    (setf (replay-runs performance) (reverse (performance-runs performance))
          (replay-cues performance) '()
          (replay-bindings performance) '()
          (replay-clips performance) '()
          (performance-time performance) nil
          (replay-stale performance) nil)))

(defun reset-run (run)
  "Forget what an earlier replay made of RUN."
  (setf (script-run-iterations run) 0
        (script-run-next-begin run) nil
        (script-run-settled run) nil
        (script-run-drivers run) '()
        (script-run-bindings run) '()
        (script-run-children run) '()
        (script-run-clips run) '()))

(defun resolve-parent (performance parent body-name)
  "The scene parent PARENT (NIL, an object's name or (OBJECT JOINT-OR-ROLE)) names,
:SELF being the body BODY-NAME."
  (let ((scene (performance-scene performance)))
    (flet ((object (name)
             (find-object scene (if (eq name :self) (or body-name (performance-character performance)) name))))
      (cond ((null parent) (performance-stage performance))
            ((symbolp parent) (object parent))
            (t (let ((object (object (first parent))))
                 (cons object (joint-name-for object (second parent) parent))))))))

(defun joint-name-for (object joint-or-role form)
  "The name of OBJECT's joint JOINT-OR-ROLE (a role keyword gives its joint, or a
chain's last joint)."
  (unless (typep object 'body)
    (anim-fail 'anim-error form "~A is not a body, so nothing can hang from its joints"
               (lisp-text (object-name object))))
  (let ((joint (if (keywordp joint-or-role)
                   (skeleton-role (body-skeleton object) joint-or-role)
                   (find-joint (body-skeleton object) joint-or-role))))
    (when (consp joint) (setf joint (car (last joint))))
    (unless joint
      (anim-fail 'anim-error form "body ~A has no joint or role ~A" (lisp-text (object-name object))
                 (lisp-text joint-or-role)))
    (body-joint-name joint)))

(defun expand-runs (performance time)
  "Turn into cues every iteration of every run that starts by TIME."
  (dolist (run (replay-runs performance))
    (expand-run performance run time)))

(defun expand-run (performance run time)
  "Add RUN's cues for its iterations starting at or before TIME (and before
its stop).  A looping script of :beats takes each iteration at the tempo of
its start (RUN-ITERATION-SCRIPT, tempo.lisp)."
  (loop for k = (script-run-iterations run)
        for begin = (or (script-run-next-begin run) (script-run-start run))
        for iteration = (run-iteration-script performance run begin)
        for duration = (script-duration iteration)
        while (and (<= begin time)
                   (or (zerop k) (and (script-run-loop run) (plusp duration)))
                   (or (null (script-run-stop run)) (< begin (script-run-stop run))))
        do (incf (script-run-iterations run))
           (setf (script-run-next-begin run) (+ begin duration))
           ;; Items due at the same time play in the order they are written.
           (setf (replay-cues performance)
                 (merge 'list (replay-cues performance)
                        (stable-sort (loop for item in (script-items iteration)
                                           collect (make-cue (+ begin (script-item-at item)) item
                                                             run (+ begin duration)))
                                     #'< :key #'cue-time)
                        #'< :key #'cue-time))))

(defun item-end (cue)
  "When CUE's item ends: its :for, its iteration's end, its run's stop, whichever
is first.  Speech and sounds are not cut by the iteration's end: NIL when
nothing else cuts them."
  (let* ((item (cue-item cue))
         (run (cue-run cue))
         (ends (remove nil (list (and (script-item-until item)
                                      (+ (cue-time cue) (script-item-until item)))
                                 (and (not (typep item '(or say-item sound-item)))
                                      (cue-iteration-end cue))
                                 (script-run-stop run)))))
    (and ends (reduce #'min ends))))

(defun bring-to (performance time)
  "Set every bound property and evaluate every body for TIME."
  (let ((scene (performance-scene performance)))
    (setf (replay-bindings performance)
          (loop for binding in (replay-bindings performance)
                for end = (binding-end binding)
                for at = (if (and end (< end time)) end time)
                do (setf (property-value (binding-object binding) (binding-property binding))
                         (let ((control (binding-control binding)))
                           (if (control-p control)
                               (control-value control (- at (binding-start binding)))
                               control)))
                unless (and end (<= end time)) collect binding))
    (dolist (object (scene-objects scene))
      (when (typep object 'body)
        (body-evaluate object time)))
    ;; Dynamic props fall and collide (src/physics/), after what placed the rest.
    (advance-scene-physics scene time)
    (setf (performance-time performance) time)))

(defun play-cue (performance cue)
  "Carry out CUE's item at its time."
  (let* ((item (cue-item cue))
         (run (cue-run cue))
         (time (cue-time cue))
         (end (item-end cue))
         (body-name (script-run-body run)))
    (flet ((object (name)
             (find-object (performance-scene performance) (if (eq name :self) body-name name))))
      (etypecase item
        (motor-item
         (let* ((body (performance-body performance body-name))
                (driver (make-driver (motor-item-call item) body time :stop end)))
           (push driver (script-run-drivers run))
           (body-add-driver body driver)
           ;; A clip played with :root :move carries the body: its position is
           ;; bound, for the item's span, to the clip's travel from here.
           (when (moves-root-p driver)
             (add-binding performance run body 'position
                          (make-root-motion-control driver (property-value body 'position)
                                                    (property-value body 'rotation))
                          time end))))
        (animate-item
         (add-binding performance run (object (animate-item-object item)) (animate-item-property item)
                      (animate-item-control item) time end))
        (set-item
         (add-binding performance run (object (set-item-object item)) (set-item-property item)
                      (set-item-value item) time time))
        (play-item
         (let* ((script (find-script (performance-library performance) (play-item-script item) t))
                (child (make-script-run script time end body-name (script-loop script))))
           (push child (script-run-children run))
           (setf (replay-runs performance) (append (replay-runs performance) (list child)))
           (expand-run performance child time)))
        ((or say-item sound-item)
         (play-audio-item performance item run time end body-name))
        (attach-item
         (reparent-object (object (attach-item-object item))
                          (resolve-parent performance (attach-item-parent item) body-name)
                          :keep-world (attach-item-keep-world item)))))))

(defun add-binding (performance run object property control start end)
  "Bind CONTROL (or a constant) to OBJECT's PROPERTY from START to END; the
newest binding of a property replaces the older ones."
  (let ((binding (make-binding object property control start end)))
    (setf (replay-bindings performance)
          (append (remove-if (lambda (b) (and (eq (binding-object b) object)
                                              (string-equal (binding-property b) property)))
                             (replay-bindings performance))
                  (list binding)))
    (push binding (script-run-bindings run))
    (bring-to performance start)))

(defun performance-frame (performance time)
  "PERFORMANCE's scene at TIME (seconds): every run's cues due by then played in
order, every body evaluated.  An earlier TIME than the last replays from the
start.  Returns the scene (PERFORMANCE-SCENE; its objects change with the next call)."
  (check-argument 'performance-frame 'performance performance #'performance-p "a performance (from make-performance)")
  (check-seconds 'performance-frame 'time time)
  (let ((time (float time 1d0)))
    (when (or (replay-stale performance)
              (and (performance-time performance) (< time (performance-time performance))))
      (rebuild-scene performance))
    (loop
      (expand-runs performance time)
      (let ((cue (first (replay-cues performance)))
            (settle-time (next-settle-time performance)))
        (cond ((and settle-time (<= settle-time time)
                    (or (null cue) (< settle-time (cue-time cue))))
               ;; A script over, or a new settled pose, before the next cue (cues at
               ;; the same instant first: a channel a new script takes then never settles).
               (bring-to performance settle-time)
               (settle-due performance settle-time))
              ((not (and cue (<= (cue-time cue) time)))
               (return))
              (t
               (pop (replay-cues performance))
               (when (or (null (script-run-stop (cue-run cue)))
                         (< (cue-time cue) (script-run-stop (cue-run cue))))
                 (bring-to performance (cue-time cue))
                 (play-cue performance cue))))))
    (bring-to performance time)
    (check-property-reactions performance time)
    (setf (scene-caption (performance-scene performance)) (caption-at performance time))
    (performance-scene performance)))
