;;;; output.lisp -- one lock for the lines live authoring prints.
;;;; A viewer opened from the REPL prints trace lines, notes and errors from its
;;;; own thread while the REPL's thread prints too; both go to the same
;;;; terminal.  Every line the viewer writes is written whole under this lock,
;;;; so two threads' lines never interleave mid-line.

(in-package #:player.render)

(defvar *output-lock* (bt:make-recursive-lock "player live output")
  "Held while a thread writes lines of live output.  Recursive, so a group of
lines (WITH-OUTPUT-LOCK) may hold single ones (WRITE-LIVE-LINE).")

(defun call-with-output-lock (function)
  "Call FUNCTION with no arguments holding the live output lock; return its values."
  (bt:with-recursive-lock-held (*output-lock*)
    (funcall function)))

(defmacro with-output-lock (() &body body)
  "Run BODY holding the live output lock, so the lines it writes are not cut
by another thread's (see CALL-WITH-OUTPUT-LOCK)."
  `(call-with-output-lock (lambda () ,@body)))

(defun write-live-line (stream control &rest arguments)
  "Write (FORMAT STREAM CONTROL ARGUMENTS...), CONTROL ending in ~%, to the
stream STREAM (not T or NIL) under the live output lock, and finish STREAM's
output so the line is seen whole before another thread writes."
  (with-output-lock ()
    (apply #'format stream control arguments)
    (finish-output stream)))
