;;;; conditions.lisp -- the condition of src/logic/: a formula that is not one,
;;;; names something the behaviour does not have, or a behaviour too large.

(in-package #:player.logic)

(define-condition formula-error (player-error-with-message)
  ((formula :initarg :formula :initform nil :reader formula-error-formula
            :documentation "The offending formula or part of one."))
  (:documentation "A temporal formula that cannot be checked: not written as
CTL, naming a state or variable the behaviour does not have, or a behaviour
too large to explore. The message names the offending part."))

(defun formula-fail (formula control &rest arguments)
  "Signal a FORMULA-ERROR about FORMULA."
  (error 'formula-error :formula formula
                        :message (format nil "formula ~A: ~?" (bounded-lisp-text formula 100) control arguments)))
