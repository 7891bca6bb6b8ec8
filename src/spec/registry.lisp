;;;; registry.lisp -- DEFSPEC, the table of defined specs, and loading spec files.
;;;; Specs are defined from two threads at once during live authoring (the
;;;; viewer's, reloading a watched file, and the REPL's), so the table is read
;;;; and written only by the four functions under "The table", which take its lock.

(in-package #:player.spec)

(defvar *specs* (make-hash-table :test 'equal)
  "Defined specs, by name key.  Touched only through REGISTERED-SPEC,
REGISTER-SPEC, UNREGISTER-SPEC and REGISTERED-SPECS, under *SPECS-LOCK*.")

(defvar *specs-lock* (bt:make-lock "player specs")
  "The lock every read and write of *SPECS* holds.")

;;;# The table

(defun spec-key (name)
  "The key of *SPECS* for NAME, a symbol or a string (matched case-insensitively)."
  (if (stringp name) (string-upcase name) (name-key name)))

(defun registered-spec (name)
  "The spec registered under NAME (a symbol or string), or NIL."
  (let ((key (spec-key name)))
    (bt:with-lock-held (*specs-lock*)
      (values (gethash key *specs*)))))

(defun register-spec (spec)
  "Register SPEC under its name, replacing any spec of that name; return SPEC."
  (let ((key (spec-key (spec-name spec))))
    (bt:with-lock-held (*specs-lock*)
      (setf (gethash key *specs*) spec))))

(defun unregister-spec (name)
  "Forget the spec registered under NAME (a symbol or string); true when there was one."
  (let ((key (spec-key name)))
    (bt:with-lock-held (*specs-lock*)
      (remhash key *specs*))))

(defun registered-specs ()
  "A fresh list of every registered spec, in no particular order."
  (bt:with-lock-held (*specs-lock*)
    (loop for spec being the hash-values of *specs* collect spec)))

;;;# Defining specs

(defvar *defined-specs* nil
  "While LOAD-SPEC runs: the specs defined so far, most recent first.")

(defvar *spec-definition-hooks* '()
  "Functions DEFINE-SPEC calls with each spec it registers, after registering
it (following.lisp's keeps running controllers up to date).  A hook must not
signal: the definition has already happened.")

(defun define-spec (name body &key source-file (package *package*) (allow-code t) form-positions)
  "Parse BODY as spec NAME, register it (replacing any older definition) and
return it, then call each of *SPEC-DEFINITION-HOOKS* with it. Signals a SPEC-ERROR, leaving the old definition in place, when NAME
is not a symbol, BODY is not a proper list, either is circular or nested too
deeply, or BODY is malformed; unless ALLOW-CODE, also when the spec contains
:code or :c++ (an UNTRUSTED-CODE-ERROR).  FORM-POSITIONS, the character positions of BODY's
forms in SOURCE-FILE, let errors name the line of the form at fault."
  (with-spec-context (:spec-name (and (symbolp name) name))
    (check-form-structure (cons name body) :what "defspec form")
    (unless (and (symbolp name) name (not (keywordp name)) (not (eq name t)))
      (spec-fail 'spec-syntax-error (list 'defspec name) "a spec's name must be a symbol, not ~A"
                 (bounded-lisp-text name 60)))
    (unless (proper-list-p body)
      (spec-fail 'spec-syntax-error nil "the body of defspec ~A is not a proper list" (lisp-text name)))
    (let ((spec (parse-spec name body :source-file source-file :package package
                                      :form-positions form-positions)))
      (unless allow-code (refuse-code spec))
      (register-spec spec)
      (push spec *defined-specs*)
      (dolist (hook *spec-definition-hooks*)
        (funcall hook spec))
      spec)))

(defmacro defspec (&rest name-and-body)
  "Define (or, re-evaluated, redefine) the controller spec NAME:
  (defspec NAME [DOCSTRING] [(:max-depth N)] FORM...)
where each FORM is a state-variable, time-variable, state-class, op, macro-op,
autoscript or event form. See doc/language.md for the language."
  `(define-spec ',(if (consp name-and-body) (car name-and-body) nil)
                ',(if (consp name-and-body) (cdr name-and-body) nil)
                :source-file ,(or (car *source-position*) *compile-file-truename* *load-truename*)
                :package (find-package ,(package-name *package*))))

(defun find-spec (name &optional (errorp t))
  "The spec named NAME (a symbol or string). With ERRORP (the default), an
unknown name is a SPEC-ERROR; otherwise NIL. Any other NAME is an ARGUMENT-ERROR."
  (check-argument 'find-spec 'name name #'name-designator-p "a spec's name (a symbol or string)")
  (or (registered-spec name)
      (and errorp
           (error 'unknown-name-error :form name :spec nil :position nil
                  :message (format nil "no spec named ~A is defined~@[ (defined: ~{~A~^, ~})~]"
                                   (bounded-lisp-text name 80) (mapcar #'lisp-text (list-specs)))))))

(defun list-specs ()
  "The names of every defined spec."
  (sort (mapcar #'spec-name (registered-specs))
        #'string< :key #'symbol-name))

(defun remove-spec (name)
  "Forget the spec named NAME (a symbol or string); true when there was one.
Any other NAME is an ARGUMENT-ERROR."
  (check-argument 'remove-spec 'name name #'name-designator-p "a spec's name (a symbol or string)")
  (unregister-spec name))

(defun spec-designator-p (x)
  "Is X a spec or a spec's name (a symbol or a string)?"
  (or (symbolp x) (stringp x) (spec-p x)))

(defparameter *spec-designator* "a spec or a spec's name (a symbol or string)"
  "How argument errors describe a spec designator.")
