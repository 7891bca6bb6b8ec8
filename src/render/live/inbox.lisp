;;;; inbox.lisp -- work handed to a thread that owns something (a viewer owns
;;;; its window, its GL context and its controller): other threads post
;;;; functions, the owner runs them at its next safe moment.  CALL-IN-INBOX
;;;; posts one and waits for its values, so a REPL can ask the owner.

(in-package #:player.render)

(defstruct (inbox (:constructor make-inbox ()))
  "Functions posted for the owning thread to run, oldest first, under LOCK;
CLOSED once the owner no longer runs them, with the REASON (a condition or NIL)."
  (lock (bt:make-lock "player inbox"))
  (ready (bt:make-condition-variable :name "player inbox done"))
  (items '())
  (closed nil)
  (reason nil))

(defun inbox-post (inbox function)
  "Queue FUNCTION (of one argument, what the owner passes) on INBOX; false
when the inbox is closed and FUNCTION will never run."
  (bt:with-lock-held ((inbox-lock inbox))
    (unless (inbox-closed inbox)
      (setf (inbox-items inbox) (append (inbox-items inbox) (list function)))
      t)))

(defun run-inbox (inbox argument)
  "On the owning thread: run every function posted on INBOX so far, oldest
first, on ARGUMENT."
  (let ((items (bt:with-lock-held ((inbox-lock inbox))
                 (shiftf (inbox-items inbox) '()))))
    (dolist (function items)
      (funcall function argument))))

(defun close-inbox (inbox &optional reason)
  "Mark INBOX closed (REASON: the condition that ended its owner, or NIL) and
wake the threads waiting for an answer from it."
  (bt:with-lock-held ((inbox-lock inbox))
    (setf (inbox-closed inbox) t
          (inbox-reason inbox) reason
          (inbox-items inbox) '())
    (bt:condition-notify (inbox-ready inbox))))

(defun inbox-closed-error (inbox what)
  "Signal a PLAYER-ERROR: INBOX's owner is gone, so WHAT cannot be done."
  (error 'player-error-with-message
         :message (format nil "cannot ~A: the viewer has stopped~@[ (~A)~]" what (inbox-reason inbox))))

(defun call-in-inbox (inbox function &key (what "do that") (timeout 30))
  "Run FUNCTION on INBOX's owning thread (it gets what the owner passes) and
return its values here; a condition it signals is signalled here instead.
Signals a PLAYER-ERROR when the owner has stopped or does not answer within
TIMEOUT seconds."
  (let ((done nil) (values '()) (failure nil))
    (unless (inbox-post inbox (lambda (argument)
                                (handler-case (setf values (multiple-value-list (funcall function argument)))
                                  (error (e) (setf failure e)))
                                (bt:with-lock-held ((inbox-lock inbox))
                                  (setf done t)
                                  (bt:condition-notify (inbox-ready inbox)))))
      (inbox-closed-error inbox what))
    (let ((deadline (+ (get-internal-real-time) (* timeout internal-time-units-per-second))))
      (bt:with-lock-held ((inbox-lock inbox))
        (loop until (or done (inbox-closed inbox) (> (get-internal-real-time) deadline))
              do (bt:condition-wait (inbox-ready inbox) (inbox-lock inbox) :timeout 0.5))))
    (cond (failure (error failure))
          (done (values-list values))
          (t (inbox-closed-error inbox what)))))
