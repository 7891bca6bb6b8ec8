;;;; conditions.lisp -- the dialogue manager's errors.
;;;; A dialogue file is checked as a spec file is: an error names the form at
;;;; fault, with its file and line, so DIALOGUE-ERROR is a SPEC-ERROR and shares
;;;; its report; errors while a conversation runs name the turn's input.

(in-package #:player)

(define-condition dialogue-error (spec-error)
  ()
  (:documentation "A dialogue (or its catalogue, or a memory file) is malformed or
inconsistent, or a conversation cannot go on: FORM is the offending form."))

(defvar *current-dialogue-name* nil
  "While a dialogue is parsed: its name, for messages.")

(defun dialogue-fail (form control &rest arguments)
  "Signal a DIALOGUE-ERROR about FORM, with a message from CONTROL and ARGUMENTS.
Like SPEC-FAIL, it finds FORM's file and line in *FORM-PLACES*."
  (let ((*current-spec-name* nil)
        (placed (and *form-places* (consp form) (gethash form *form-places*))))
    ;; Without a file and line, the message names the dialogue instead.
    (apply #'spec-fail 'dialogue-error form
           (concatenate 'string "~@[dialogue ~A: ~]" control)
           (and *current-dialogue-name* (not placed) (display-name *current-dialogue-name*))
           arguments)))
