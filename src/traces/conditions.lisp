;;;; conditions.lisp -- what can go wrong with a recorded trace: the file is
;;;; not a recording (RECORDING-ERROR, naming file and line), or the replay
;;;; does not match it (RECORDING-MISMATCH, naming the first difference).

(in-package #:player.traces)

(define-condition recording-error (player-error-with-message)
  ((file :initarg :file :initform nil :reader recording-error-file
         :documentation "The recording file at fault, or NIL.")
   (line :initarg :line :initform nil :reader recording-error-line
         :documentation "The 1-based line of the form at fault, or NIL."))
  (:documentation "A recording file cannot be read as one: not readable as
data, no (:recording ...) header first, a header field of the wrong kind, or a
trace line or frame of the wrong shape.  The message begins FILE:LINE:."))

(defun recording-fail (file line control &rest arguments)
  "Signal a RECORDING-ERROR about FILE (or NIL) at LINE (or NIL), its message
from CONTROL and ARGUMENTS after \"FILE:LINE: \"."
  (error 'recording-error
         :file file :line line
         :message (format nil "~@[~A:~]~@[~D:~]~:[~; ~]~?"
                          (and file (native-namestring file)) line (or file line)
                          control arguments)))

(define-condition recording-mismatch (player-error-with-message)
  ((verification :initarg :verification :reader recording-mismatch-verification
                 :documentation "The VERIFICATION that found the difference."))
  (:documentation "A replay of a recorded scenario differs from the recording;
the message names the first difference.  `bin/player verify` exits 1 on it."))
