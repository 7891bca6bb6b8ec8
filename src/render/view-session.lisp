;;;; view-session.lisp -- (view 'peedy) at the REPL: the viewer on a thread of
;;;; its own, returning a session at once.  The window, its GL context and the
;;;; controller belong to that thread (GLFW wants every call for a window on
;;;; one thread); the REPL reaches them only by posting work to the viewer's
;;;; inbox, run between frames: SEND-EVENT, CALL-IN-VIEW, STOP-VIEW.

(in-package #:player.render)

(defclass viewer-session (event-target)
  ((name :initarg :name :reader view-name)
   (inbox :initarg :inbox :reader view-inbox)
   (thread :initform nil :accessor view-thread)
   (started :initform nil :accessor view-started
            :documentation "True once the first frame was shown."))
  (:documentation "A viewer playing on its own thread (from VIEW).  SEND-EVENT
takes it in place of a controller."))

(defmethod print-object ((session viewer-session) stream)
  (print-unreadable-object (session stream :type t)
    (format stream "~A~:[ stopped~;~]" (view-name session) (view-running-p session))))

(defvar *view-session* nil
  "The session whose viewer is open, or NIL: GLFW serves one viewer thread at a time.")

(defvar *view-lock* (bt:make-lock "player view")
  "Held while a viewer thread is started or its session checked.")

(defun viewer-session-p (x)
  "Is X a viewer session?"
  (typep x 'viewer-session))

(defun view-running-p (session)
  "Is SESSION's viewer still open?"
  (check-argument 'view-running-p 'session session #'viewer-session-p "a viewer session (from view)")
  (not (inbox-closed (view-inbox session))))

(defun view-thread-function (session spec arguments)
  "What SESSION's thread runs: VIEW-SPEC of SPEC with ARGUMENTS, its inbox
closed at the end (with the error that ended it, if one did)."
  (let ((inbox (view-inbox session)))
    (handler-case (progn (apply #'view-spec spec :inbox inbox :terminal nil arguments)
                         (close-inbox inbox))
      (error (e)
        ;; Before the first frame VIEW signals it; later, nobody waits for it.
        (when (view-started session) (print-live-error e))
        (close-inbox inbox e)))))

(defun view (spec &key scripts initial body (size '(640 480)) (seed 0) dot)
  "Open a window playing a controller of SPEC (a spec or a spec's name) on its
own thread, as `player view` does, and return a VIEWER-SESSION once the first
frame is shown.  SCRIPTS, INITIAL, BODY, SIZE, SEED and DOT are VIEW-SPEC's.
Re-evaluating the spec's DEFSPEC updates the character in place (state and
time kept; errors printed, the window playing on).  SEND-EVENT takes the
session; STOP-VIEW closes it.  Trace lines go to the *STANDARD-OUTPUT* of the
caller.  Signals what VIEW-SPEC signals before its first frame (a
RENDER-ERROR when there is no display), and a PLAYER-ERROR while another
viewer is open."
  (check-body-presenter-arguments 'view spec scripts body seed nil *default-blend-time*)
  (check-argument 'view :initial initial #'initial-state-p *initial-state-phrase*)
  (let* ((spec (if (spec-p spec) spec (find-spec spec)))
         (session (make-instance 'viewer-session :name (lisp-text (spec-name spec)) :inbox (make-inbox)))
         (out *standard-output*) (err *error-output*))
    (bt:with-lock-held (*view-lock*)
      (when (and *view-session* (view-running-p *view-session*))
        (error 'player-error-with-message
               :message (format nil "a viewer is already open (~A): (stop-view ...) it first"
                                (view-name *view-session*))))
      (setf *view-session* session
            (view-thread session)
            (bt:make-thread (lambda ()
                              (let ((*standard-output* out) (*error-output* err))
                                (view-thread-function session spec
                                                      (list :scripts scripts :initial initial :body body
                                                            :size size :seed seed :dot dot))))
                            :name (format nil "player viewer ~A" (view-name session)))))
    ;; Wait for the first frame, so a window that cannot open is an error here.
    (handler-case (call-in-inbox (view-inbox session) (lambda (viewer)
                                                        (declare (ignore viewer))
                                                        (setf (view-started session) t))
                                 :what "open the viewer" :timeout 120)
      (player-error (e)
        (bt:join-thread (view-thread session))
        (error (or (inbox-reason (view-inbox session)) e))))
    session))

(defun call-in-view (session function)
  "Call FUNCTION with SESSION's controller on the viewer's thread, between two
frames, and return its values (a condition it signals is signalled here):
(call-in-view v #'controller-state).  A PLAYER-ERROR when the viewer has stopped."
  (check-argument 'call-in-view 'session session #'viewer-session-p "a viewer session (from view)")
  (check-argument 'call-in-view 'function function #'functionp "a function of a controller")
  (call-in-inbox (view-inbox session) (lambda (viewer) (funcall function (viewer-controller viewer)))
                 :what "reach the viewer's controller"))

(defun reload-view-scripts (session &optional path)
  "Read the script library of SESSION's viewer again, from PATH (default: the
file it was read from), as RELOAD-SCRIPT-LIBRARY does on the viewer's thread:
the next scripts play from it.  Returns T; signals here what
RELOAD-SCRIPT-LIBRARY signals (the old library playing on)."
  (check-argument 'reload-view-scripts 'session session #'viewer-session-p "a viewer session (from view)")
  (call-in-inbox (view-inbox session)
                 (lambda (viewer)
                   (let ((controller (viewer-controller viewer)))
                     (reload-script-library (controller-presenter controller) (spec-of controller) path)
                     (write-live-line *standard-output* "; read the script library again~%")
                     t))
                 :what "read the script library again"))

(defmethod target-send-event ((session viewer-session) event at when-busy)
  ;; At the viewer's playback time unless AT says otherwise.
  (call-in-inbox (view-inbox session)
                 (lambda (viewer)
                   (let ((controller (viewer-controller viewer)))
                     (send-event controller event
                                 :at (or at (max (viewer-now viewer) (controller-time controller)))
                                 :when-busy when-busy)))
                 :what "send an event"))

(defun stop-view (session)
  "Close SESSION's window and wait for its thread to end.  True when it was
open, NIL when it had stopped already."
  (check-argument 'stop-view 'session session #'viewer-session-p "a viewer session (from view)")
  (when (eq (bt:current-thread) (view-thread session))
    (error 'player-error-with-message
           :message "stop-view cannot wait for the viewer from the viewer's own thread: press Escape or close the window"))
  (let ((open (inbox-post (view-inbox session)
                          (lambda (viewer) (glfw-close-window (viewer-window viewer))))))
    (bt:join-thread (view-thread session))
    open))
