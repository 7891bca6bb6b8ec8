;;;; library.lisp -- ODE's conditions, and its library loaded and initialised once.
;;;; libode is loaded on first use, not when Player loads, so a machine without
;;;; it still plans, simulates and renders; only physics asks for it.

(in-package #:player.ode)

(define-condition ode-error (player-error-with-message)
  ()
  (:documentation "The physics engine refused something: a bad shape, mass or
step, or a call on a world already destroyed.  The message names it."))

(define-condition ode-unavailable (ode-error)
  ()
  (:documentation "libode is not installed; the message names the Debian package, libode8."))

(defun ode-fail (control &rest arguments)
  "Signal an ODE-ERROR whose message is CONTROL applied to ARGUMENTS."
  (error 'ode-error :message (apply #'format nil control arguments)))

(defvar *ode-traps-masked* nil
  "True inside WITH-ODE-TRAPS-MASKED, so nested uses do not switch the FPU modes again.")

(defmacro with-ode-traps-masked (&body body)
  "Run BODY with SBCL's floating-point traps masked: ODE divides by zero and
compares with infinities on purpose (dInfinity bounds, degenerate contacts).
Nested inside another, it costs nothing (switching FPU modes is not free, and
a step makes hundreds of calls)."
  `(flet ((body () ,@body))
     (declare (dynamic-extent #'body))
     (if *ode-traps-masked*
         (body)
         (let ((*ode-traps-masked* t))
           (sb-int:with-float-traps-masked (:invalid :divide-by-zero :overflow :inexact)
             (body))))))

(defvar *ode-library-names* '("libode.so.8")
  "Sonames tried, in order (the versioned name: the bare one comes with libode-dev).")

(defvar *ode-state* nil
  "NIL until ODE is loaded and initialised; then :READY.")

(defvar *ode-lock* (bt:make-lock "ode")
  "Serialises the first load and dInitODE2, which must run once.")

(defvar *ode-messages* 0
  "How many warnings ODE has given (a degenerate contact the solver got past).")

(cffi:defcallback ode-message :void ((number :int) (format :pointer) (arguments :pointer))
  ;; ODE's messages are warnings it recovers from ("LCP internal error" on
  ;; redundant contacts); counted, not printed on the user's stderr.
  (declare (ignore number format arguments))
  (incf *ode-messages*))

(defun ensure-ode ()
  "Load libode and initialise it (dInitODE2), once per process.  Signals
ODE-UNAVAILABLE naming the Debian package libode8 when it is missing."
  (or *ode-state*
      (bt:with-lock-held (*ode-lock*)
        (or *ode-state*
            (progn
              (unless (load-first-foreign-library *ode-library-names*)
                (error 'ode-unavailable
                       :message (format nil "physics needs the Open Dynamics Engine, which is not installed: ~
                                             install the Debian package libode8 (tried ~{~A~^, ~})"
                                        *ode-library-names*)))
              (when (zerop (with-ode-traps-masked (%d-init-ode2 0)))
                (ode-fail "the Open Dynamics Engine failed to initialise (dInitODE2)"))
              (%d-set-message-handler (cffi:callback ode-message))
              ;; ODE is closed when the Lisp exits, never before: worlds may live until then.
              (push (lambda () (when *ode-state* (with-ode-traps-masked (%d-close-ode))))
                    sb-ext:*exit-hooks*)
              (setf *ode-state* :ready))))))

(defun ode-available-p ()
  "Can physics run here: is libode installed (and now loaded)?"
  (handler-case (and (ensure-ode) t)
    (ode-unavailable () nil)))

(defvar *ode-thread-data* (make-hash-table :test #'eq :weakness :key :synchronized t)
  "The threads ODE's per-thread collision data has been allocated for.")

(defun ensure-ode-thread ()
  "Load ODE and allocate its collision data for the calling thread, once per thread
\(a viewer thread steps worlds too)."
  (ensure-ode)
  (let ((thread (bt:current-thread)))
    (unless (gethash thread *ode-thread-data*)
      (when (zerop (with-ode-traps-masked (%d-allocate-ode-data-for-thread #xFFFFFFFF)))
        (ode-fail "the Open Dynamics Engine could not allocate its data for this thread"))
      (setf (gethash thread *ode-thread-data*) t))))

;;; A saved core starts uninitialised: ODE's state does not survive SAVE-LISP-AND-DIE.
(pushnew 'forget-ode-state sb-ext:*save-hooks*)

(defun forget-ode-state ()
  "Forget that ODE was initialised, so the next process (a saved core) initialises it again."
  (setf *ode-state* nil)
  (clrhash *ode-thread-data*))
