;;;; registry.lisp -- DEFSPEC, the table of defined specs, and loading spec files.

(in-package #:player.spec)

(defvar *specs* (make-hash-table :test 'equal)
  "Defined specs, by name key.")

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
      (setf (gethash (name-key name) *specs*) spec)
      (push spec *defined-specs*)
      (dolist (hook *spec-definition-hooks*)
        (funcall hook spec))
      spec)))

(defmacro defspec (&rest name-and-body)
  "Define (or, re-evaluated, redefine) the controller spec NAME:
  (defspec NAME [DOCSTRING] [(:max-depth N)] FORM...)
where each FORM is a state-variable, time-variable, state-class, op, macro-op,
autoscript or event form. See the README for the language."
  `(define-spec ',(if (consp name-and-body) (car name-and-body) nil)
                ',(if (consp name-and-body) (cdr name-and-body) nil)
                :source-file ,(or (car *source-position*) *compile-file-truename* *load-truename*)
                :package (find-package ,(package-name *package*))))

(defun find-spec (name &optional (errorp t))
  "The spec named NAME (a symbol or string). With ERRORP (the default), an
unknown name is a SPEC-ERROR; otherwise NIL. Any other NAME is an ARGUMENT-ERROR."
  (check-argument 'find-spec 'name name #'name-designator-p "a spec's name (a symbol or string)")
  (or (gethash (if (stringp name) (string-upcase name) (name-key name)) *specs*)
      (and errorp
           (error 'unknown-name-error :form name :spec nil :position nil
                  :message (format nil "no spec named ~A is defined~@[ (defined: ~{~A~^, ~})~]"
                                   (bounded-lisp-text name 80) (mapcar #'lisp-text (list-specs)))))))

(defun list-specs ()
  "The names of every defined spec."
  (sort (loop for spec being the hash-values of *specs* collect (spec-name spec))
        #'string< :key #'symbol-name))

(defun remove-spec (name)
  "Forget the spec named NAME (a symbol or string); true when there was one.
Any other NAME is an ARGUMENT-ERROR."
  (check-argument 'remove-spec 'name name #'name-designator-p "a spec's name (a symbol or string)")
  (remhash (if (stringp name) (string-upcase name) (name-key name)) *specs*))

(defun spec-designator-p (x)
  "Is X a spec or a spec's name (a symbol or a string)?"
  (or (symbolp x) (stringp x) (spec-p x)))

(defparameter *spec-designator* "a spec or a spec's name (a symbol or string)"
  "How argument errors describe a spec designator.")
