;;;; script-check.lisp -- CHECK's look at a spec's script library: every error
;;;; playing it could meet later, found before anything plays.  Each script and
;;;; director the spec needs (and every script they play or start) is walked
;;;; once; each motor call is set up as a real driver on a scratch body of the
;;;; spec's skeleton, finding poses where playing would (see SCRATCH-BODY in
;;;; op-channels.lisp), so an unknown pose, a written angle past a joint limit,
;;;; a joint, role or DOF the body lacks, or malformed keys fail here as they
;;;; would when the script starts; the objects, joints and roles that targets,
;;;; :animate, :set and :attach items name are looked up in the scene playing
;;;; would build.  Each failure is one error diagnostic naming the script, the
;;;; item, and the file and line where the library reader recorded them.
;;;;
;;;; Joint limits: an angle an author writes (a pose, a :keyframe or :direct
;;;; clause) must lie within its DOF's limits -- the driver refuses it when it
;;;; is set up (RESOLVE-CLAUSES, CHECK-ANGLE), so it is an error here; angles
;;;; drivers compute (a Catmull-Rom overshoot, gaze, head and IK solutions,
;;;; idle noise added on top) are clamped silently, and the body clamps its
;;;; final pose (%CLAMP-POSE).

(in-package #:player.performance)

;;;# Severity

(defparameter *error-diagnostic-kinds*
  '(:script-library :missing-scripts :motor-call :scene-name :code)
  "The DIAGNOSTIC kinds that are errors: what playing the spec would fail on.
Every other kind (:unreachable-goal, :unused-op, :truncated,
:unreachable-states, :shared-channel, :duration-mismatch) is a warning.
  :SCRIPT-LIBRARY  the library or its pose library cannot be read (a
                   malformed form, an unknown motor function or parameter, a
                   value of the wrong type, a director starting an unknown
                   script ...);
  :MISSING-SCRIPTS directors the spec's ops need that the library lacks
                   (simulate refuses them; a missing script plays a
                   placeholder gesture, a :PLACEHOLDER-SCRIPTS warning);
  :MOTOR-CALL      a motor call the spec's body cannot perform (an unknown
                   pose, joint, role or DOF, a written angle past its limit);
  :SCENE-NAME      an item or target naming an object, joint or role the
                   scene playing the spec would not have;
  :CODE            a :code form the compiler warns of (an undefined
                   function), which fails when it runs (CODE-DIAGNOSTICS).")

(defun diagnostic-severity (diagnostic)
  "DIAGNOSTIC's severity: :ERROR when its kind is one of *ERROR-DIAGNOSTIC-KINDS*
\(playing the spec would fail), else :WARNING."
  (check-argument 'diagnostic-severity 'diagnostic diagnostic #'diagnostic-p
                  "a diagnostic (from check-spec or script-diagnostics)")
  (if (member (diagnostic-kind diagnostic) *error-diagnostic-kinds*) :error :warning))

(defun diagnostic-error-p (diagnostic)
  "Is DIAGNOSTIC an error (see DIAGNOSTIC-SEVERITY)?"
  (eq (diagnostic-severity diagnostic) :error))

;;;# Where a script's items are

(defun source-text (file cache)
  "FILE's text, read once per CACHE (an EQUAL hash table), or NIL when unreadable."
  (let ((key (namestring file)))
    (multiple-value-bind (text found) (gethash key cache)
      (if found
          text
          (setf (gethash key cache)
                (ignore-errors          ; a regular file only: a FIFO would block
                 (with-input-file (in file :external-format '(:utf-8 :replacement #\Replacement_Character))
                   (alexandria:read-stream-content-into-string in))))))))

(defun line-at (text position)
  "The 1-based line of character POSITION in TEXT."
  (1+ (count #\Newline text :end (min position (length text)))))

(defun form-line-place (library form cache)
  "The (FILE . LINE) of FORM, a list inside LIBRARY's file (a :keyframe key),
when the library reader recorded where it was read; else NIL."
  (let ((place (and (consp form) (script-library-places library)
                    (gethash form (script-library-places library)))))
    (when place
      (let ((text (source-text (car place) cache)))
        (and text (cons (car place) (line-at text (cdr place))))))))

(defun item-place (script index cache)
  "The (FILE . LINE) of the INDEX-th item of SCRIPT (0-based), else of SCRIPT's
form, when the library reader recorded where SCRIPT was read; else NIL."
  (let ((source (script-source script)))
    (when (and (consp source) (car source) (integerp (cdr source)))
      (let* ((file (car source))
             (text (source-text file cache))
             (start (cdr source)))
        (cons file
              (and text (< start (length text))
                   ;; (defscript NAME OPTIONS ITEM ...): the items are elements 3, 4, ...
                   (let ((element (nth (+ 3 index) (ignore-errors (list-element-positions text start)))))
                     (line-at text (or element start)))))))))

;;;# What the scene has

(defstruct (scene-names (:constructor make-scene-names (characters objects skeleton)))
  "What a scene playing the library holds: the CHARACTERS' names (bodies of
SKELETON) and the library's declared OBJECTS (SCENE-OBJECT-SPECs)."
  characters objects skeleton)

(defun scene-name-problem (names name)
  "NIL when NAME (:self, a character's or a declared object's name) is in the
scene NAMES describes; else what is wrong, as a string."
  (unless (or (eq name :self)
              (member name (scene-names-characters names) :test #'name=)
              (find name (scene-names-objects names) :key #'scene-object-spec-name :test #'name=))
    (format nil "the scene has no object ~A (objects: ~{~A~^ ~})" (lisp-text name)
            (append (mapcar #'lisp-text (scene-names-characters names))
                    (mapcar (lambda (o) (lisp-text (scene-object-spec-name o))) (scene-names-objects names))))))

(defun scene-joint-problem (names object joint-or-role)
  "NIL when OBJECT's joint or role JOINT-OR-ROLE exists in the scene NAMES
describes (OBJECT must be a body); else what is wrong, as a string."
  (or (scene-name-problem names object)
      (if (or (eq object :self) (member object (scene-names-characters names) :test #'name=))
          (let ((skeleton (scene-names-skeleton names)))
            (unless (if (keywordp joint-or-role)
                        (skeleton-role skeleton joint-or-role)
                        (and (string-designator-p joint-or-role) (find-joint skeleton joint-or-role)))
              (format nil "~:[body ~A~;the character~*~] (skeleton ~A) has no joint or role ~A"
                      (eq object :self) (lisp-text object)
                      (lisp-text (skeleton-name skeleton)) (lisp-text joint-or-role))))
          (format nil "~A is not a body, so it has no joint or role ~A"
                  (lisp-text object) (lisp-text joint-or-role)))))

(defun target-problem (names target)
  "What is wrong with the :target form TARGET in the scene NAMES describes, or NIL."
  (case (first target)
    (:object (scene-name-problem names (second target)))
    (:joint (scene-joint-problem names (second target) (third target)))))

(defun parent-problem (names parent)
  "What is wrong with an :attach PARENT (NIL, an object, (OBJECT JOINT-OR-ROLE)), or NIL."
  (cond ((null parent) nil)
        ((symbolp parent) (scene-name-problem names parent))
        (t (scene-joint-problem names (first parent) (second parent)))))

(defun failing-key (call body)
  "When CALL is a :keyframe call that BODY cannot perform, its first key (as
written) that fails set up alone; else NIL."
  (let ((keys (and (eq (motor-call-function call) :keyframe) (motor-arg call :keys))))
    (when (alexandria:proper-list-p keys)
      (loop for key in keys
            when (and (consp key) (realp (first key))
                      (handler-case
                          (progn (make-driver (make-motor-call :keyframe
                                                               (list* :keys (list key)
                                                                      (alexandria:remove-from-plist
                                                                       (motor-call-args call) :keys))
                                                               (motor-call-frame call))
                                              body 0)
                                 nil)
                        (error () t)))
              return key))))

(defun item-problems (item body names)
  "What playing ITEM on BODY in the scene NAMES describes would fail on: a list
of (KIND MESSAGE [FORM]), KIND :MOTOR-CALL or :SCENE-NAME, FORM the part of
the item at fault when it is narrower than the item (a :keyframe key)."
  (flet ((scene (problem) (and problem (list (list :scene-name problem)))))
    (typecase item
      (motor-item
       (let ((call (motor-item-call item)))
         (append
          ;; Set up exactly as PLAY-CUE would: a driver of the call on the body.
          (handler-case (progn (make-driver call body 0) nil)
            (spec-error (condition)
              (let ((key (failing-key call body)))
                (list (list :motor-call (format nil "~@[the key at ~A s: ~]~A"
                                                (and key (format-number (first key)))
                                                (spec-error-message condition))
                            key))))
            (error (condition) (list (list :motor-call (condition-line condition)))))
          ;; Targets are found when the driver runs: look their names up now.
          (loop for (nil value) on (motor-call-args call) by #'cddr
                for problem = (and (target-form-p value) (target-problem names value))
                when problem collect (list :scene-name problem)))))
      (say-item
       (handler-case (progn (make-driver (say-item-motor-call '((0 :rest))) body 0) nil)
         (spec-error (condition)
           (list (cons :motor-call (format nil ":say moves the jaw: ~A" (spec-error-message condition)))))))
      (animate-item (scene (scene-name-problem names (animate-item-object item))))
      (set-item (scene (scene-name-problem names (set-item-object item))))
      (attach-item (scene (or (scene-name-problem names (attach-item-object item))
                              (parent-problem names (attach-item-parent item))))))))

;;;# Walking what a spec needs

(defun needed-definitions (library names)
  "The scripts and directors of LIBRARY that playing NAMES reaches: each named
one, every script they :play and every script a director starts, each once,
in the order first reached.  Names LIBRARY lacks are left out."
  (let ((seen '()))
    (labels ((walk (name)
               (let ((definition (or (find-script library name) (find-director library name))))
                 (when (and definition (not (member definition seen)))
                   (push definition seen)
                   (if (script-p definition)
                       (dolist (item (script-items definition))
                         (when (play-item-p item) (walk (play-item-script item))))
                       (dolist (step (director-steps definition))
                         (when (start-step-p step) (walk (start-step-script step)))))))))
      (mapc #'walk names))
    (nreverse seen)))

(defun item-text (item)
  "ITEM as written, shortened for a message."
  (bounded-lisp-text (script-item-form item) 100))

(defun check-library-scripts (library skeleton names &key characters poses)
  "Error DIAGNOSTICs for every item of the scripts LIBRARY plays for NAMES (see
NEEDED-DEFINITIONS) that would fail when played on a body of SKELETON named
by one of CHARACTERS (strings or symbols), in a scene holding LIBRARY's
objects: each motor call set up as a driver on a scratch body finding poses
in POSES (default: LIBRARY's (poses FILE), else the shipped library), each
object, joint and role an item or target names looked up.  Each diagnostic's
DETAILS is a plist (:SCRIPT :ITEM :FILE :LINE)."
  (let ((body (scratch-body library skeleton poses))
        (names-in-scene (make-scene-names characters (script-library-objects library) skeleton))
        (cache (make-hash-table :test #'equal))
        (diagnostics '()))
    (dolist (script (remove-if-not #'script-p (needed-definitions library names)))
      (loop for item in (script-items script)
            for index from 0
            do (loop for (kind problem form) in (item-problems item body names-in-scene)
                     for place = (or (form-line-place library form cache)
                                     (item-place script index cache))
                     do (push (make-diagnostic
                               kind
                               (format nil "~@[~A:~]~@[~D: ~]script ~A: the item at ~A s, ~A, cannot play: ~A"
                                       (and place (file-namestring (car place))) (cdr place)
                                       (lisp-text (script-name script))
                                       (format-number (script-item-at item)) (item-text item) problem)
                               (list :script (script-name script) :item (script-item-form item)
                                     :file (car place) :line (cdr place)))
                              diagnostics))))
    (nreverse diagnostics)))

(defun library-failure-diagnostic (condition)
  "The error diagnostic for a script library (or its pose library) that cannot be read."
  (make-diagnostic :script-library (condition-line condition)
                   (let ((position (and (typep condition 'spec-error) (spec-error-position condition))))
                     (list :file (car position)
                           :line (and position (cdr position) (position-line (car position) (cdr position)))
                           :condition condition))))
