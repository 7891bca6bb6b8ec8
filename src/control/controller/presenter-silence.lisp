;;;; presenter-silence.lisp -- which presenters need not be told anything.
;;;; A presenter to which only the protocol's base methods apply (the null
;;;; presenter, or one that adds nothing that matters) is quiet: a timed
;;;; controller skips its per-op calls, and a whole-event controller's closures
;;;; skip the presenter altogether (SILENT-P). Methods can be defined at any
;;;; time, so the protocol's generic functions are watched and a controller
;;;; asks again after one changed.

(in-package #:player.control)

(defparameter *quiet-methods*
  '((present-op null-presenter) (present-macro-start presenter) (present-macro-end presenter)
    (present-event presenter) (present-resume presenter) (present-failure presenter)
    (present-state presenter) (present-cut presenter) (present-queued presenter))
  "(FUNCTION CLASS): the protocol's reports of what a timed controller plays,
and the class whose method of it, in presenter.lisp, does nothing (a null
presenter's PRESENT-OP only answers the declared duration).")

(defun quiet-method-p (function class presenter)
  "Is the method of FUNCTION specialized on CLASS (presenter.lisp) the only one
that applies to PRESENTER (bar less specific primaries it never calls)?"
  (let* ((generic (fdefinition function))
         (arity (length (sb-mop:generic-function-lambda-list generic))))
    (multiple-value-bind (methods known)
        (sb-mop:compute-applicable-methods-using-classes
         generic (cons (class-of presenter) (make-list (1- arity) :initial-element (find-class t))))
      (and known methods
           (every (lambda (method) (null (method-qualifiers method))) methods)
           (eq (first (sb-mop:method-specializers (first methods))) (find-class class))))))

(defun quiet-presenter-p (presenter)
  "Does PRESENTER do nothing when told that an op starts, a macro begins or
ends, an event starts, resumes, fails or ends, or an op is cut: do only the
methods of *QUIET-METHODS* apply to it (a null presenter)?  A timed controller
then skips telling it (asked once, when the controller is made)."
  (every (lambda (entry) (quiet-method-p (first entry) (second entry) presenter))
         *quiet-methods*))

(defun quiet-autoscripts-p (presenter)
  "Does PRESENTER do nothing when autoscripts start and stop or the state
changes: do only the base class's empty methods of START-AUTOSCRIPT,
STOP-AUTOSCRIPT and PRESENT-STATE-CHANGE apply to it?  A
timed controller then applies state changes without looking for autoscripts
(asked once, when the controller is made)."
  (and (quiet-method-p 'start-autoscript 'presenter presenter)
       (quiet-method-p 'stop-autoscript 'presenter presenter)
       (quiet-method-p 'present-state-change 'presenter presenter)))

;;; Silence, for the whole-event controller: a presenter that does nothing
;;; with anything SEND-EVENT tells it is not told (the closures' SILENT-P).
;;; Which methods apply can change as methods are defined, so a count of the
;;; protocol's changes tells a controller when to ask again.

(defparameter *silence-functions*
  (append (mapcar #'first *quiet-methods*) '(start-autoscript stop-autoscript present-state-change))
  "The protocol functions whose methods decide whether a presenter is silent.")

(defvar *protocol-generation* 0
  "How many times a method of *SILENCE-FUNCTIONS* was added or removed: a
controller asks SILENT-PRESENTER-P again when this moved.")
(declaim (type fixnum *protocol-generation*))

(defclass protocol-watcher () ()
  (:documentation "A MOP dependent of the presenter protocol's generic
functions, counting their changes in *PROTOCOL-GENERATION*."))

(defmethod sb-mop:update-dependent ((generic generic-function) (watcher protocol-watcher) &rest initargs)
  (declare (ignore initargs))
  (incf *protocol-generation*))

(defvar *protocol-watcher*
  (let ((watcher (make-instance 'protocol-watcher)))
    (dolist (function *silence-functions* watcher)
      (sb-mop:add-dependent (fdefinition function) watcher)))
  "The one PROTOCOL-WATCHER, registered once (a reload keeps it).")

(defun silent-presenter-p (presenter)
  "Is PRESENTER silent: do nothing but the base methods of QUIET-PRESENTER-P's
and QUIET-AUTOSCRIPTS-P's functions apply to it, so that a whole-event
controller need not tell it anything and its ops take their declared
durations (a null presenter)?"
  (and (quiet-presenter-p presenter) (quiet-autoscripts-p presenter)))

(defun note-presenter-silence (controller)
  "Bring CONTROLLER's record of whether its presenter is silent (SILENT-P) up
to date: asked again only when the presenter or the protocol's methods changed."
  (let ((presenter (controller-presenter controller))
        (generation *protocol-generation*))
    (unless (and (eq presenter (controller-checked-presenter controller))
                 (= generation (controller-checked-generation controller)))
      (setf (controller-silent-presenter controller)
            (if (silent-presenter-p presenter) presenter :none)
            (controller-checked-presenter controller) presenter
            (controller-checked-generation controller) generation))))
