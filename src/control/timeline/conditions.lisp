;;;; conditions.lisp -- what the timed engine signals when it cannot go on.

(in-package #:player.control)

(define-condition timeline-error (player-error-with-message) ()
  (:documentation "A timed controller cannot go on (e.g. triggers firing each
other for ever); its message says why."))
