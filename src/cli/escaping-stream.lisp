;;;; escaping-stream.lisp -- an output stream that shows control characters
;;;; instead of sending them on: what `chat` prints carries text from files and
;;;; users (templates, typed requests, user names), and an ESC or BEL in it
;;;; must not clear the terminal, retitle it or print fake lines (issue 31).

(in-package #:player.cli)

(defclass escaping-stream (sb-gray:fundamental-character-output-stream)
  ((target :initarg :target :reader escaping-target
           :documentation "The stream the escaped text goes to."))
  (:documentation "Writes to its TARGET every character but the control
characters other than line breaks, which it writes as ESCAPED-TEXT does (\\x1B)."))

(defmethod sb-gray:stream-write-char ((stream escaping-stream) char)
  (if (and (control-character-p char) (char/= char #\Newline))
      (write-string (escaped-text (string char)) (escaping-target stream))
      (write-char char (escaping-target stream)))
  char)

(defmethod sb-gray:stream-line-column ((stream escaping-stream))
  nil)

(defmethod sb-gray:stream-finish-output ((stream escaping-stream))
  (finish-output (escaping-target stream)))

(defmethod sb-gray:stream-force-output ((stream escaping-stream))
  (force-output (escaping-target stream)))

(defmacro with-escaped-output (() &body body)
  "Run BODY with *STANDARD-OUTPUT* showing control characters (but line breaks)
escaped, then flush it."
  `(let ((*standard-output* (make-instance 'escaping-stream :target *standard-output*)))
     (unwind-protect (progn ,@body)
       (finish-output *standard-output*))))
