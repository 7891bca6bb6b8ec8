;;;; initial-values.lisp -- a spec's variables with their starting values:
;;;; the declared initial values, overridden by a caller's alist.  Every
;;;; backend starts from these (the Lisp controller and the generated C++).

(in-package #:player.spec)

(defun resolve-initial-value (var raw)
  "RAW as the stored value of VAR: a value index (plannable) or a number.
Signals a SPEC-ERROR naming (VAR . RAW) when RAW does not fit."
  (let ((form (cons (var-name var) raw)))
    (ecase (var-kind var)
      (:boolean (multiple-value-bind (truth ok) (boolean-word raw)
                  (unless ok
                    (spec-fail 'type-error-in-spec form "~A is boolean; ~A is not true, false, t or nil"
                               (lisp-text (var-name var)) (lisp-text raw)))
                  (if truth 1 0)))
      (:enumerated (value-index var raw form))
      (:number (runtime-number var raw form))
      (:time (if (realp raw)
                 (spec-seconds raw form (format nil "time variable ~A" (lisp-text (var-name var))))
                 (spec-fail 'type-error-in-spec form "time variable ~A needs a number of seconds"
                            (lisp-text (var-name var))))))))

(defun initial-assignments (spec overrides)
  "For each variable of SPEC, its stored initial value, with OVERRIDES (an alist
of variable name -> value) applied. Unknown names are errors."
  (with-spec-context (:spec spec :spec-name (spec-name spec))
    (dolist (entry overrides)
      (unless (and (consp entry) (symbolp (car entry)) (find-variable-named (car entry)))
        (spec-fail 'unknown-name-error entry "unknown variable ~A in the initial state"
                   (lisp-text (if (consp entry) (car entry) entry)))))
    (loop for var in (spec-variables spec)
          for entry = (assoc (name-key (var-name var)) overrides
                             :key (lambda (name) (name-key name)) :test #'string=)
          collect (cons var (if entry (resolve-initial-value var (cdr entry)) (var-initial var))))))
