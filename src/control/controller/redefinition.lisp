;;;; redefinition.lisp -- switching a running controller to a new machine
;;;; (its spec edited and compiled again), keeping its state and its time.
;;;;
;;;; The rule: a controller switches only at a safe point, between events.  A
;;;; whole-event controller is always between events unless the switch comes
;;;; from inside its own event (a :code form); a timed controller is at one
;;;; when nothing runs or waits.  Otherwise the new machine waits in the
;;;; controller's PENDING slot and is installed by the next SEND-EVENT or
;;;; ADVANCE that finds the controller idle.  A state the new spec cannot hold
;;;; is refused, and the old machine keeps running: bad input never corrupts
;;;; a running controller.

(in-package #:player.control)

(define-condition redefinition-warning (warning)
  ((error :initarg :error :reader redefinition-warning-error
          :documentation "The PLAYER-ERROR that stopped the switch.")
   (controller :initarg :controller :reader redefinition-warning-controller))
  (:report (lambda (condition stream)
             (format stream "a running controller kept its old machine: ~A"
                     (redefinition-warning-error condition))))
  (:documentation "Signalled (with WARN) when a redefinition that was waiting
for a safe point, or that came through a spec's redefinition, could not be
installed; the controller runs on with its old machine."))

(defun transferred-state (controller spec)
  "CONTROLLER's current values, expressed in SPEC: an alist for INITIAL-ASSIGNMENTS.
Variables SPEC does not have are dropped; new ones take their initial values."
  (loop for (name . value) in (controller-state controller)
        for var = (with-spec-context (:spec spec) (find-variable-named name))
        when (and var (not (and (eq (var-kind var) :time) (null value))))
          collect (cons (var-name var) value)))

(defun transferred-assignments (controller machine)
  "The assignments that express CONTROLLER's current state in MACHINE's spec;
a STATE-TRANSFER-ERROR when a current value does not exist there, or when
MACHINE has no plans from that state (the reachable regime)."
  (let* ((new-spec (machine-spec machine))
         (assignments (handler-case (initial-assignments new-spec (transferred-state controller new-spec))
                        (spec-error (e)
                          (error 'state-transfer-error
                                 :message (format nil "cannot keep the controller's state in the new spec: ~A" e))))))
    ;; a spec planned for its reachable states only may have no plans from it
    (handler-case (check-planned-state machine (loop for (var . value) in assignments
                                                     when (plannable-p var) sum (var-value-bit var value)))
      (state-outside-planned-set (e)
        (error 'state-transfer-error
               :message (format nil "cannot keep the controller's state in the new spec: ~A" e))))
    assignments))

(defun switch-machine (controller machine)
  "Make compiled MACHINE CONTROLLER's, now, keeping its state, clock and
presenter; autoscripts that stop or start applying are told so, and a timed
controller's timers start over from now.  Signals STATE-TRANSFER-ERROR,
changing nothing, when a current value does not exist in the new spec."
  (let* ((assignments (transferred-assignments controller machine))
         (new-spec (machine-spec machine))
         (before (active-autoscripts controller))
         (time (micros->seconds (controller-microseconds controller)))
         (presenter (controller-presenter controller)))
    (setf (controller-machine controller) machine
          (controller-pending controller) nil
          (controller-labels controller) (make-array (spec-label-count new-spec) :initial-element 0))
    (install-assignments controller assignments)
    (let ((after (active-autoscripts controller)))
      (flet ((same-autoscript-p (a b)
               (and (eq (first a) (first b))
                    (string= (name-key (second a)) (name-key (second b)))
                    (equalp (third a) (third b)))))
        (loop for (proc var value) in (set-difference before after :test #'same-autoscript-p)
              do (stop-autoscript presenter proc var value time))
        (loop for (proc var value) in (set-difference after before :test #'same-autoscript-p)
              do (start-autoscript presenter proc var value time))))
    (when (controller-timeline controller)
      ;; Its timers start over, from now, with the new spec's.
      (setf (controller-timeline controller) (make-timeline controller)))
    controller))

(defun safe-point-p (controller)
  "Is CONTROLLER between events, so that it may switch machines now?"
  (and (not (eq controller *controller*))
       (not (and (controller-timeline controller)
                 (timeline-busy-p (controller-timeline controller))))))

(defun redefine-controller (controller machine)
  "Switch CONTROLLER to MACHINE (a compiled machine, a spec or a spec's name,
compiled) keeping its state, clock and presenter: at once when it is between
events, else at its next safe point (the first SEND-EVENT or ADVANCE that
finds a timed controller idle).  Returns :SWITCHED or :PENDING.  Signals
STATE-TRANSFER-ERROR, changing nothing, when a current value does not exist
in the new spec (checked now; a pending switch is checked again when it
happens, and refused with a REDEFINITION-WARNING)."
  (check-argument 'redefine-controller 'controller controller #'controller-p
                  "a controller (from make-controller)")
  (check-argument 'redefine-controller 'machine machine #'machine-designator-p *machine-designator*)
  (let ((machine (ensure-compiled-machine machine)))
    (transferred-assignments controller machine)
    (cond ((safe-point-p controller)
           (switch-machine controller machine)
           :switched)
          (t (setf (controller-pending controller) machine)
             :pending))))

(defun install-pending-machine (controller)
  "Switch CONTROLLER to its pending machine if it is at a safe point now.  A
state the new spec cannot hold drops the pending machine with a
REDEFINITION-WARNING, the old one running on.  True when it switched."
  (let ((machine (controller-pending controller)))
    (when (and machine (safe-point-p controller))
      (setf (controller-pending controller) nil)
      (handler-case (progn (switch-machine controller machine) t)
        (state-transfer-error (e)
          (warn 'redefinition-warning :error e :controller controller)
          nil)))))

(defun recompile (controller &optional (spec nil spec-given))
  "Compile SPEC (default: the current definition of the controller's spec,
e.g. after re-evaluating its DEFSPEC) and switch CONTROLLER to it now, keeping
its current state, clock and presenter. Autoscripts that stop or start applying
are told so; a timed controller must be idle, and its timers start over.
Signals STATE-TRANSFER-ERROR, leaving CONTROLLER unchanged, when a current
value does not exist in the new spec or a timed controller is busy."
  (check-argument 'recompile 'controller controller #'controller-p "a controller (from make-controller)")
  (if spec-given
      (check-argument 'recompile 'spec spec #'spec-designator-p *spec-designator*)
      (setf spec (spec-name (spec-of controller))))
  (when (and (controller-timeline controller) (timeline-busy-p (controller-timeline controller)))
    (error 'state-transfer-error
           :message "cannot recompile a timed controller while an event runs or waits: finish or advance past it first"))
  (switch-machine controller (compile-spec spec)))
