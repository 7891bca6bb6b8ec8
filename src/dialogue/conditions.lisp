;;;; conditions.lisp -- the dialogue manager's errors.
;;;; A dialogue file is checked as a spec file is: an error names the form at
;;;; fault, with its file and line, so DIALOGUE-ERROR is a SPEC-ERROR and shares
;;;; its report; errors while a conversation runs name the turn's input.

(in-package #:player.dialogue)

(define-condition dialogue-error (spec-error)
  ()
  (:report report-dialogue-error)
  (:documentation "A dialogue (or its catalogue, or a memory file) is malformed or
inconsistent, or a conversation cannot go on: FORM is the offending form."))

(defun report-dialogue-error (condition stream)
  "Write CONDITION as one sentence: file and line, the form's label (its kind
and name, in the dialogue's spelling), the message, and the form when no label names it."
  (let ((position (spec-error-position condition))
        (label (spec-error-label condition))
        (form (spec-error-form condition)))
    (if position
        (format stream "~A:~@[~D: ~]" (file-namestring (car position))
                (and (cdr position) (position-line (car position) (cdr position))))
        ;; Without a file and line (a dialogue defined at the REPL), its name.
        (when (spec-error-spec condition)
          (format stream "dialogue ~A~:[: ~;, ~]" (display-name (spec-error-spec condition)) label)))
    (when label (format stream "~A: " label))
    (write-string (spec-error-message condition) stream)
    (when (and form (consp form) (not label))
      (format stream " in ~A" (bounded-lisp-text form 160)))))

(defvar *current-dialogue-name* nil
  "While a dialogue is parsed: its name, for messages.")

(defun dialogue-fail (form control &rest arguments)
  "Signal a DIALOGUE-ERROR about FORM, with a message from CONTROL and
ARGUMENTS, at FORM's file and line when *FORM-PLACES* knows them."
  (let ((place (and *form-places* (consp form) (gethash form *form-places*)))
        (message (apply #'format nil control arguments)))
    (if place
        (error 'dialogue-error :form form :position place :label (dialogue-form-label form)
                               :spec *current-dialogue-name* :message message)
        (error 'dialogue-error :form form :spec *current-dialogue-name* :message message))))
