;;;; code-forms.lisp -- a spec's :code forms compiled: each into a function
;;;; of no arguments, the first time it runs, so machines with :code compile
;;;; as fast as those without.  What the compiler warns of -- an undefined
;;;; function or variable, a call with the wrong arguments -- is an error at
;;;; that point, a CODE-ERROR naming the form's file and line, instead of
;;;; code that fails later without saying where it is written.  CHECK
;;;; compiles them all ahead (CODE-DIAGNOSTICS).

(in-package #:player.control)

(defun warning-problem (warning)
  "What WARNING, signalled compiling a :code form, says is wrong, a phrase,
or NIL when it is only a matter of style."
  (let ((text (first (split-lines (princ-to-string warning))))
        (arguments (and (typep warning 'simple-condition) (simple-condition-format-arguments warning))))
    (cond ((not (typep warning 'style-warning)) (format nil "does not compile: ~A" text))
          ((not (eql 0 (search "undefined " text))) nil)
          ;; SBCL's "undefined function: NAME", once the form is compiled.
          ((and (= 2 (length arguments)) (symbolp (second arguments)))
           (format nil "calls the undefined ~(~A~) ~A" (first arguments) (lisp-text (second arguments))))
          (t (format nil "draws the warning: ~A" text)))))

(defun split-lines (text)
  "TEXT's lines, a list of strings."
  (loop for start = 0 then (1+ end)
        for end = (position #\Newline text :start start)
        collect (subseq text start end)
        while end))

(defun compile-code-form (form)
  "FORM compiled as a function of no arguments, and the list of problems the
compiler warned of (phrases, see WARNING-PROBLEM).  Nothing is printed:
stderr is for the one error line."
  (let ((problems '()))
    (let ((function (let ((*error-output* (make-broadcast-stream)))
                      (handler-bind ((warning (lambda (warning)
                                                (let ((problem (warning-problem warning)))
                                                  (when problem (pushnew problem problems :test #'string=)))
                                                (muffle-warning warning))))
                        ;; A unit of its own: inside another (ASDF's, a
                        ;; caller's), undefined functions are reported
                        ;; only when that one ends.
                        (with-compilation-unit (:override t)
                          (compile nil `(lambda () ,form)))))))
      (values function (nreverse problems)))))

(defun checked-code-function (form spec)
  "The function of the :code FORM of SPEC, compiled; a CODE-ERROR at FORM's
file and line when the compiler warned of a problem."
  (multiple-value-bind (function problems) (compile-code-form form)
    (when problems
      (code-fail spec form ":code ~{~A~^; ~}" problems))
    function))

(defun compile-code (form spec)
  "A function of no arguments evaluating FORM, a :code form of SPEC, compiled
the first time it runs (when the functions it calls should be defined);
then, what the compiler warns of is a CODE-ERROR (see CHECKED-CODE-FUNCTION)."
  (let ((function nil))
    (lambda ()
      (let ((compiled (or function (setf function (checked-code-function form spec)))))
        ;; Not HANDLER-CASE: the code's error is left as it is for its own
        ;; handlers; only the line the CLI prints learns where the code is.
        (handler-bind ((error (lambda (condition) (note-code-failure condition form spec))))
          (funcall (the function compiled)))))))

(defun note-code-failure (condition form spec)
  "Remember, for CONDITION-LINE, that CONDITION escaped the :code FORM of SPEC:
the line names FORM's file and line and says what it signalled."
  (unless (typep condition 'code-error)
    (note-condition-place condition
                          (condition-line (code-condition spec form ":code signalled an error: ~A"
                                                          (condition-line condition))))))

(defun code-diagnostics (spec)
  "CHECK's findings about SPEC's :code forms, compiled now: a :CODE
diagnostic, the CODE-ERROR's message, for each the compiler warns of."
  (loop for form in (spec-code-forms spec)
        for problem = (handler-case (progn (checked-code-function form spec) nil)
                        (code-error (condition) condition))
        when problem
          collect (make-diagnostic :code (princ-to-string problem) form)))
