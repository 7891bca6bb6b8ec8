;;;; progress.lisp -- a command still working after 2 s says so, once, on a
;;;; terminal: a long check or render then shows it is alive, while a
;;;; script's stderr stays empty (or holds only the one error line).

(in-package #:player.cli)

(defparameter *progress-delay* 2
  "Seconds a command works before its progress line is printed.")

(defparameter *interactive-commands* '("view" "chat")
  "Commands that run as long as their user wants: no progress line.")

(defun terminal-stream-p (fd)
  "Is the file descriptor FD a terminal?"
  (let ((answer (ignore-errors (cffi:foreign-funcall "isatty" :int fd :int))))
    (and answer (not (eql answer 0)))))

(defun progress-line (arguments seconds)
  "The progress line of the command line ARGUMENTS, working for SECONDS."
  (format nil "player: ~A is still working (~D s)..." (escaped-text (or (first arguments) "player")) seconds))

(defun start-progress-note (arguments &key (delay *progress-delay*) (stream *error-output*)
                                           (interactive (terminal-stream-p 2)))
  "When INTERACTIVE (by default: stderr is a terminal) and ARGUMENTS name no
command of *INTERACTIVE-COMMANDS*, a thread that prints
PROGRESS-LINE to STREAM once the command ARGUMENTS has worked DELAY seconds;
the thread, or NIL.  It dies with the process."
  (when (and interactive (not (member (first arguments) *interactive-commands* :test #'equal)))
    (sb-thread:make-thread
     (lambda ()
       (sleep delay)
       (ignore-errors (format stream "~A~%" (progress-line arguments delay))
                      (finish-output stream)))
     :name "player progress")))
