;;;; body-presenter.lisp -- a presenter that moves a body: an op plays the
;;;; script its :script names (or runs its director), autoscripts loop their
;;;; scripts while their value holds, and the op's duration is its script's,
;;;; so the controller's clock follows the animation.  It prints the same trace
;;;; lines as the trace presenter.

(in-package #:player.performance)

(defparameter *default-body* 'humanoid
  "The skeleton a spec's character gets when neither its (:body NAME) option nor the caller names one.
\(:body none) gives a scene of props alone: see CHARACTER-SKELETON.")

(defclass body-presenter (trace-presenter)
  ((performance :initarg :performance :reader presenter-performance)
   (autoscript-runs :initform (make-hash-table :test #'equal) :reader autoscript-runs
                    :documentation "(PROC VARIABLE VALUE) -> the looping run playing it.")
   (op-runs :initform (make-hash-table :test #'equal) :reader op-runs
            :documentation "(OP . START) -> the script runs playing that op, so a cut can stop them.")
   (placeholder :initarg :placeholder :initform nil :reader presenter-placeholder-p
                :documentation "True when the library is made up (placeholders.lisp): each
op then shows its name as a caption while it plays.")
   (starting-poses :initarg :starting-poses :initform '() :reader presenter-starting-poses
                   :documentation "The library's (:pose-when ...) entries, checked (STARTING-POSEs).")
   (captions :initform (make-hash-table :test #'equal) :reader op-captions
             :documentation "(OP . START) -> the caption showing that op's name, so a cut can end it."))
  (:documentation "Plays a controller's ops as scripts of a library on a body.
PRESENTER-PERFORMANCE gives the frames."))

(defun spec-option-path (spec key)
  "SPEC's option KEY as a pathname, relative to the spec's file, or NIL."
  (let ((value (getf (spec-options spec) key)))
    (when value
      (unless (stringp value)
        (error 'spec-error :form (list key value) :spec (spec-name spec)
                           :message (format nil "(~A ~A) needs a file name in a string"
                                            (lisp-text key) (lisp-text value))))
      (merge-pathnames value (or (spec-source-file spec) *default-pathname-defaults*)))))

(defun spec-body-name (spec)
  "The skeleton SPEC's (:body NAME) option names, or NIL."
  (getf (spec-options spec) :body))

(defun library-character-body (library spec body)
  "What SPEC's character's body is: BODY when given, else the skeleton of
LIBRARY's (model \"FILE\" ...) form (LIBRARY may be NIL), else SPEC's (:body
NAME), else *DEFAULT-BODY*: a skeleton or a name for CHARACTER-SKELETON."
  (or body
      (and library (script-library-skeleton library))
      (spec-body-name spec)
      *default-body*))

(defun spec-script-names (spec)
  "Every script or director SPEC's ops and autoscripts need, each once, in spec order."
  (remove-duplicates
   (append (loop for op in (spec-ops spec)
                 append (case (op-kind op)
                          (:script (list (or (op-script op) (op-name op))))
                          (:director (list (op-director op)))))
           (loop for auto in (spec-autoscripts spec)
                 append (copy-list (autoscript-procs auto))))
   :test #'string-equal :from-end t))

(defun spec-names-scripts-p (spec)
  "Does SPEC give (:scripts FILE)?"
  (and (getf (spec-options spec) :scripts) t))

(defun spec-script-library (spec &key scripts)
  "The script library for SPEC: SCRIPTS (a SCRIPT-LIBRARY or a file), else SPEC's
(:scripts FILE) option.  Signals a SPEC-ERROR when there is neither (a body
presenter then plays placeholders, see MAKE-PLACEHOLDER-LIBRARY)."
  (when (script-library-p scripts)
    (return-from spec-script-library scripts))
  (let ((path (or (and scripts (pathname scripts)) (spec-option-path spec :scripts))))
    (unless path
      (error 'spec-error :form (spec-name spec) :spec (spec-name spec)
                         :message (format nil "spec ~A names no script library: give (:scripts \"FILE\") in its defspec, or --scripts FILE"
                                          (lisp-text (spec-name spec)))))
    (load-script-library path)))

(defun check-spec-scripts (spec library)
  "Signal a SCRIPT-ERROR listing every script or director SPEC needs that LIBRARY lacks."
  (let ((missing (missing-scripts library (spec-script-names spec))))
    (when missing
      (error 'script-error :spec (spec-name spec)
                           :message (format nil "its ops need scripts that ~A does not define: ~{~A~^, ~}"
                                            (if (script-library-source library)
                                                (file-namestring (script-library-source library))
                                                "its script library")
                                            (mapcar #'lisp-text missing))))))

(defun check-body-presenter-arguments (function spec scripts body seed stream blend-time)
  "Check MAKE-BODY-PRESENTER's arguments (also SIMULATE's and VIEW-SPEC's): an
ARGUMENT-ERROR of FUNCTION for the first that is of the wrong kind."
  (check-argument function 'spec spec #'spec-designator-p *spec-designator*)
  (check-argument function :scripts scripts
                  (lambda (x) (or (null x) (script-library-p x) (pathname-designator-p x)))
                  (format nil "NIL, a script library or ~A" *path-phrase*))
  (check-argument function :body body
                  (lambda (x) (or (null x) (skeleton-p x) (symbolp x) (pathname-designator-p x)))
                  "NIL, a skeleton, or a skeleton's name or path")
  (check-real function :seed seed :integer t)
  (check-argument function :stream stream #'output-stream-designator-p
                  "an output stream, T (standard output) or NIL")
  (check-real function :blend-time blend-time :minimum 0 :maximum *max-seconds*))

(defun make-body-presenter (spec &key scripts body (seed 0) stream
                                      (blend-time *default-blend-time*)
                                      name origin (check t) silent)
  "A body presenter for SPEC: its character, named NAME (default: after SPEC), has the skeleton
BODY (else the library's (model \"FILE\" ...), else SPEC's (:body NAME), else
*DEFAULT-BODY*) and plays the library
SCRIPTS (else SPEC's (:scripts FILE), else placeholders: a gesture per op with
its name as a caption, see MAKE-PLACEHOLDER-LIBRARY).  Trace lines go to STREAM when given.
With ORIGIN (a vec3) the whole scene, props and camera included, stands
there (see MAKE-PERFORMANCE): how a cast places its members.
With SILENT, speech and sounds play nothing (see MAKE-PERFORMANCE).
Before anything plays, signals a SCRIPT-ERROR listing every missing script,
naming a (:pose-when ...) entry whose expression or pose is unknown,
or naming the first item of a needed script that cannot play on this body
(what CHECK reports as an error, at the item's file and line; skipped when
CHECK is NIL, for a caller that checked the same spec already); an
ARGUMENT-ERROR for an argument of the wrong kind."
  (check-body-presenter-arguments 'make-body-presenter spec scripts body seed stream blend-time)
  (check-argument 'make-body-presenter :name name (lambda (x) (or (null x) (string-designator-p x)))
                  "NIL or a character's name (a symbol or string)")
  (let* ((spec (if (spec-p spec) spec (find-spec spec)))
         (placeholder (not (or scripts (spec-names-scripts-p spec))))
         (loaded (unless placeholder (spec-script-library spec :scripts scripts)))
         (body (library-character-body loaded spec body))
         ;; (:body none): a stand-in skeleton, not drawn (CHARACTER-SKELETON).
         (skeleton (values (character-skeleton body)))
         ;; Scripts the library lacks play placeholder gestures (CHECK warns).
         (library (if loaded
                      (library-with-placeholders loaded spec skeleton)
                      (make-placeholder-library spec skeleton)))
         (performance (progn
                        (check-spec-scripts spec library)
                        (make-performance library (list (list (or name (spec-name spec))
                                                              (if (no-body-p body) body skeleton)))
                                          :seed seed :blend-time blend-time :origin origin :silent silent))))
    (when check (check-scripts-play spec performance))
    (make-instance 'body-presenter :stream stream :performance performance
                                   :placeholder placeholder
                                   :starting-poses (check-starting-poses library spec skeleton
                                                                         (performance-poses performance)))))

(defmethod present-initial-state ((presenter body-presenter) controller)
  ;; The character starts in the first (:pose-when ...) pose whose expression holds.
  (let ((start (choose-starting-pose (presenter-starting-poses presenter) (controller-bits controller)))
        (performance (presenter-performance presenter)))
    (unless (eq start (performance-starting-pose performance))
      (setf (performance-starting-pose performance) start)
      (rebuild-scene performance))))

(defun state-settled-pose (presenter bits)
  "The settled pose of the state BITS (one-hot) for PRESENTER's character, as
\(values ANGLES POSITION ROTATION): the first (:pose-when ...) entry whose
expression holds, on the skeleton's rest pose, else the rest pose; at the
entry's :position, else NIL (its resting place: where root motion left it,
else where it was placed, settle.lisp); turned as it was placed."
  (let* ((performance (presenter-performance presenter))
         (character (first (performance-characters performance)))
         (start (choose-starting-pose (presenter-starting-poses presenter) bits))
         (angles (make-pose (character-spec-skeleton character))))
    (when start
      (apply-pose-angles (starting-pose-angles start) angles)
      (%clamp-pose (character-spec-skeleton character) angles))
    (values angles
            (and start (pose-when-position (starting-pose-entry start)))
            (character-spec-rotation character))))

(defmethod present-state-change ((presenter body-presenter) controller time)
  ;; Channels at rest turn toward the new state's pose (settle.lisp).
  (multiple-value-bind (angles position rotation)
      (state-settled-pose presenter (controller-bits controller))
    (performance-settle-to (presenter-performance presenter) angles position rotation time)))

(defun check-scripts-play (spec performance)
  "Signal a SCRIPT-ERROR for the first item of a script SPEC needs that cannot
play on PERFORMANCE's character (CHECK-LIBRARY-SCRIPTS), so a render never
stops halfway on it."
  (let ((failure (first (check-library-scripts
                         (performance-library performance)
                         (character-spec-skeleton (first (performance-characters performance)))
                         (append (spec-script-names spec)
                                 (reactive-director-names (performance-library performance)))
                         :characters (list (performance-character performance))
                         :poses (performance-poses performance)))))
    (when failure
      (error 'script-error :spec (spec-name spec) :message (diagnostic-message failure)))))

(defun presenter-library (presenter)
  "The script library PRESENTER plays."
  (performance-library (presenter-performance presenter)))

(defmethod play-script ((presenter body-presenter) script op start)
  (declare (ignore op))
  (let ((library (presenter-library presenter)))
    (if (find-director library script nil)
        (run-director presenter script nil start)
        (script-duration (script-run-script
                          (perform-script (presenter-performance presenter) script start :settle t))))))

(defmethod run-director ((presenter body-presenter) director op start)
  (declare (ignore op))
  ;; A placeholder library plays every director as a script of its name.
  (when (presenter-placeholder-p presenter)
    (return-from run-director
      (script-duration (script-run-script (perform-script (presenter-performance presenter) director start
                                                          :settle t)))))
  (or (perform-director (presenter-performance presenter) director start :settle t)
      (error 'script-error :form director
                           :message (format nil "director ~A never ends (a script it starts loops unstopped), so it cannot play an op"
                                            (lisp-text director)))))

(defmethod start-autoscript :after ((presenter body-presenter) proc variable value time)
  (setf (gethash (list proc variable value) (autoscript-runs presenter))
        (perform-script (presenter-performance presenter) proc time :loop t :settle t)))

(defmethod stop-autoscript :after ((presenter body-presenter) proc variable value time)
  (let ((key (list proc variable value)))
    (let ((run (gethash key (autoscript-runs presenter))))
      (when run
        (stop-script-run (presenter-performance presenter) run time)
        (remhash key (autoscript-runs presenter))))))

;;;# What a timed controller asks

(defun op-script-name (op)
  "The script or director OP plays, or NIL for a :code or macro op."
  (case (op-kind op)
    (:script (or (op-script op) (op-name op)))
    (:director (op-director op))))

(defmethod planned-op-duration ((presenter body-presenter) op start)
  (let ((library (presenter-library presenter))
        (name (op-script-name op)))
    (cond ((null name) (op-duration op))
          ((find-director library name nil)
           (or (nth-value 1 (director-schedule (find-director library name t) library start))
               (error 'script-error :form name
                                    :message (format nil "director ~A never ends (a script it starts loops unstopped), so it cannot play an op"
                                                     (lisp-text name)))))
          (t (script-duration (find-script library name t))))))

(defmethod critical-time ((presenter body-presenter) op name)
  (let ((script (and (eq (op-kind op) :script)
                     (find-script (presenter-library presenter) (op-script-name op) nil))))
    (unless script
      (error 'spec-error :form (op-form op) :spec nil
                         :message (format nil "op ~A: :interrupt (:at ~A) needs the op to play a script with that critical time"
                                          (lisp-text (op-name op)) (lisp-text name))))
    (handler-case (script-critical-time script name)
      (script-error ()
        (error 'spec-error :form (op-form op) :spec nil
                           :message (format nil "op ~A: :interrupt (:at ~A): script ~A has no critical time ~A (it has: ~:[none~;~:*~{~A~^ ~}~])"
                                            (lisp-text (op-name op)) (lisp-text name) (lisp-text (op-script-name op))
                                            (lisp-text name) (mapcar (lambda (entry) (lisp-text (car entry)))
                                                                     (script-critical script))))))))

(defmethod present-op :around ((presenter body-presenter) op start)
  (let* ((performance (presenter-performance presenter))
         (before (performance-runs performance)))
    (let ((duration (call-next-method)))
      (let ((runs (ldiff (performance-runs performance) before)))
        (when runs
          (setf (gethash (cons op start) (op-runs presenter)) runs)))
      (when (presenter-placeholder-p presenter)
        (setf (gethash (cons op start) (op-captions presenter))
              (add-caption performance (string-downcase (string (op-name op)))
                           start (+ start duration))))
      duration)))

(defmethod present-cut :after ((presenter body-presenter) op start time by)
  (declare (ignore by))
  (when op
    (let ((key (cons op start)))
      (dolist (run (gethash key (op-runs presenter)))
        (stop-script-run (presenter-performance presenter) run time))
      (remhash key (op-runs presenter))
      (let ((caption (gethash key (op-captions presenter))))
        (when caption (cut-caption caption time))))))

;;;# Checking declared durations

(defun op-declares-duration-p (op)
  "Did OP's form give :duration?"
  (let ((form (op-form op)))
    (and (consp form) (member :duration (cddr form)))))

(defun script-duration-diagnostics (spec library)
  "Warnings for ops whose declared :duration differs from their script's duration."
  (loop for op in (spec-ops spec)
        for name = (and (eq (op-kind op) :script) (or (op-script op) (op-name op)))
        for script = (and name (find-script library name nil))
        when (and script (op-declares-duration-p op)
                  (> (abs (- (op-duration op) (script-duration script))) 1d-6))
          collect (make-diagnostic :duration-mismatch
                                   (format nil "op ~A declares :duration ~A but its script ~A lasts ~A s"
                                           (lisp-text (op-name op)) (format-number (op-duration op))
                                           (lisp-text name) (format-number (script-duration script)))
                                   (list (op-name op) (op-duration op) (script-duration script)))))

(defun script-diagnostics (spec &optional scripts)
  "CHECK's findings about SPEC's script library (SCRIPTS, a library or a file,
else its (:scripts FILE)): errors for everything playing SPEC would fail on
\(see DIAGNOSTIC-SEVERITY) -- a library or pose library that cannot be read,
or a (:pose-when ...) entry naming what the spec or pose library lacks, as one
:SCRIPT-LIBRARY diagnostic; and, set up on a scratch body of SPEC's
skeleton as playing would, each item of a needed script that cannot play
\(:MOTOR-CALL, :SCENE-NAME; see CHECK-LIBRARY-SCRIPTS), a missing director
-- then warnings for missing scripts (which play placeholders) and durations
that disagree.  NIL when SPEC names no library."
  (when (or scripts (getf (spec-options spec) :scripts))
    (let ((library (handler-case (spec-script-library spec :scripts scripts)
                     (spec-error (condition)
                       (return-from script-diagnostics (list (library-failure-diagnostic condition)))))))
      (let* ((needed (append (spec-script-names spec) (reactive-director-names library)))
             (placeholders (missing-placeholder-names library spec))
             (missing (set-difference (missing-scripts library needed) placeholders :test #'string-equal))
             (skeleton (values (character-skeleton (library-character-body library spec nil))))
             (poses (and (script-library-poses library)
                         (handler-case (load-pose-library (script-library-poses library) :skeleton skeleton
                                                            :fallback (shipped-pose-library skeleton))
                           (spec-error (condition)
                             (return-from script-diagnostics (list (library-failure-diagnostic condition))))))))
        (append (handler-case (progn (check-starting-poses library spec skeleton poses)
                                     (check-reactive-directors library spec)
                                     '())
                  (spec-error (condition) (list (library-failure-diagnostic condition))))
                (check-library-scripts library skeleton needed
                                       :characters (list (spec-name spec)) :poses poses)
                (script-collision-diagnostics library (library-character-body library spec nil) needed (spec-name spec))
                (and missing
                     (list (make-diagnostic :missing-scripts
                                            (format nil "the script library lacks the director~P ~{~A~^, ~}"
                                                    (length missing) (mapcar #'lisp-text missing))
                                            missing)))
                (and placeholders
                     (list (make-diagnostic :placeholder-scripts
                                            (format nil "the script library lacks ~{~A~^, ~}: ~:[it plays~;they play~] placeholder gestures"
                                                    (mapcar #'lisp-text placeholders) (rest placeholders))
                                            placeholders)))
                (script-duration-diagnostics spec library))))))
