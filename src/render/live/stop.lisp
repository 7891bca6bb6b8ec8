;;;; stop.lisp -- asking every open viewer to close, from outside its loop.
;;;; A signal handler (SIGTERM, SIGINT, SIGHUP: the command line installs
;;;; them) may run at any instant on any thread, so it only records the
;;;; request; each viewer's loop looks at it once a frame and closes its
;;;; window the ordinary way, so the window, GL and the audio are let go.

(in-package #:player.render)

(defvar *viewer-stop-request* nil
  "NIL, or why every viewer should close now (a signal's number, say): set by
REQUEST-VIEWER-STOP, read by the viewers' loops once a frame.")

(defun request-viewer-stop (&optional (reason t))
  "Ask every open viewer to close at its next frame, recording REASON (true);
safe to call from a signal handler: it only sets a variable.  Returns REASON."
  (setf *viewer-stop-request* (or reason t)))

(defun viewer-stop-request ()
  "The REASON given to REQUEST-VIEWER-STOP since the last CLEAR-VIEWER-STOP-REQUEST, or NIL."
  *viewer-stop-request*)

(defun clear-viewer-stop-request ()
  "Forget any request to close the viewers."
  (setf *viewer-stop-request* nil))
