;;;; performance.lisp -- scripts played on a scene: which scripts started when
;;;; (and stopped when).  The frame that follows for any time is replay.lisp's.
;;;; Evaluation is a pure function of the time and the runs: a performance
;;;; replays from the start whenever asked for an earlier time, so a user can
;;;; scrub and two evaluations of the same time give the same frame.

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
