;;;; conditions.lisp -- what can go wrong with a scene of several characters:
;;;; a member naming a spec that is not there, two members of one name, an
;;;; event addressed to a member the scene lacks.  Each is a SPEC-ERROR, so it
;;;; names the file and line of the form at fault when it comes from a file.

(in-package #:player.cast)

(define-condition scene-error (spec-error)
  ()
  (:documentation "A DEFSCENE form, or an event addressed to a scene's members, is wrong."))

(define-condition missing-member-spec-error (scene-error)
  ()
  (:documentation "A scene member names a spec that is neither defined nor in a file beside the scene's."))

(define-condition duplicate-member-error (scene-error)
  ()
  (:documentation "Two members of one scene have the same name."))

(define-condition unknown-member-error (scene-error)
  ()
  (:documentation "An event address names a member the scene does not have, or no member at all."))

(defun scene-fail (class form control &rest arguments)
  "Signal a scene error of CLASS about FORM, with a message from CONTROL and
ARGUMENTS, at the current *SOURCE-POSITION*."
  (error class :form form :spec nil :message (apply #'format nil control arguments)))
