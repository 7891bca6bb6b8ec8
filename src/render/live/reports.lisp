;;;; reports.lisp -- how live authoring shows an error without stopping: one
;;;; "player: error: ..." line on standard error, as the command line prints
;;;; its errors (written whole, see output.lisp), and the text kept for the
;;;; viewer's title.

(in-package #:player.render)

(defun print-live-error (condition)
  "Print CONDITION as one \"player: error: ...\" line on *ERROR-OUTPUT*; return the line's text."
  (let ((line (condition-line condition)))
    (write-live-line *error-output* "player: error: ~A~%" line)
    line))

(defmacro with-live-errors-reported ((viewer) &body body)
  "Run BODY; a REDEFINITION-WARNING signalled inside (a pending switch refused
when it fell due) is reported for VIEWER and muffled (see CALL-WITH-LIVE-ERRORS-REPORTED)."
  `(call-with-live-errors-reported ,viewer (lambda () ,@body)))
