;;;; controller.lisp -- the controller API: make agents, send them events,
;;;; read their state, and recompile them in place after a spec changes.

(in-package #:player)

(defun install-assignments (controller assignments)
  "Set CONTROLLER's state and runtime values from ASSIGNMENTS ((VAR . VALUE) ...)."
  (let ((values (make-array (count-if-not #'plannable-p (mapcar #'car assignments))
                            :initial-element nil)))
    (setf (controller-bits controller)
          (loop for (var . value) in assignments
                if (plannable-p var) sum (var-value-bit var value)
                else do (setf (svref values (var-slot var)) value))
          (controller-values controller) values)))

(defun make-controller (machine &key initial-state (presenter (make-trace-presenter)) (clock 0))
  "A new agent running MACHINE (from COMPILE-SPEC, or a spec or its name, which
is compiled). INITIAL-STATE is an alist ((VARIABLE . VALUE) ...) overriding the
declared initial values; booleans take true/false/t/nil. PRESENTER receives
what the agent does (default: a TRACE-PRESENTER). Autoscripts of the initial
values start at CLOCK. Signals a SPEC-ERROR for an unknown variable or a value
outside its domain."
  (let* ((machine (ensure-compiled-machine machine))
         (spec (machine-spec machine))
         (assignments (initial-assignments spec initial-state))
         (controller (%make-controller
                      :machine machine :presenter presenter :clock (to-double clock)
                      :labels (make-array (spec-label-count spec) :element-type 'double-float
                                                                  :initial-element 0d0))))
    (install-assignments controller assignments)
    (start-initial-autoscripts controller (controller-clock controller))
    controller))

(defun event-names (machine)
  "The names of the events MACHINE (or a controller's machine) accepts, in spec order."
  (let ((machine (if (controller-p machine) (controller-machine machine) machine)))
    (mapcar #'event-name (spec-events (machine-spec machine)))))

(defun find-compiled-event (controller name)
  "The compiled event NAME of CONTROLLER's machine; UNKNOWN-EVENT if none.
Symbols are remembered in an EQ table so the usual lookup allocates nothing."
  (let ((machine (controller-machine controller)))
    (or (and (symbolp name) (gethash name (compiled-machine-event-symbols machine)))
        (let ((compiled (and (or (symbolp name) (stringp name))
                             (gethash (if (stringp name) (string-upcase name) (name-key name))
                                      (compiled-machine-events machine)))))
          (cond ((null compiled)
                 (error 'unknown-event :name name :known (event-names controller)))
                ((symbolp name)
                 (setf (gethash name (compiled-machine-event-symbols machine)) compiled))
                (t compiled))))))

(defun send-event (controller event &key at)
  "Process EVENT (a symbol or string) on CONTROLLER, starting at time AT
(default: when the previous event's last op ended). Returns T when every
directive succeeded; otherwise (VALUES NIL GOAL) with the goal, as written, that
could not be achieved: the rest of the event is skipped and the state is the
one after the last completed op. Signals UNKNOWN-EVENT, changing nothing, for
an event the spec does not define."
  (let* ((compiled (find-compiled-event controller event))
         (event (compiled-event-event compiled))
         (start (if at (to-double at) (controller-clock controller)))
         (presenter (controller-presenter controller))
         (*controller* controller))
    (setf (controller-schedule controller) start
          (controller-span-start controller) start
          (controller-span-end controller) start)
    (present-event presenter (event-name event) start)
    (dolist (var (event-time-variables event))
      (set-runtime-value controller var start start))
    (let ((result (funcall (the function (compiled-event-run compiled)) controller)))
      (unless (eq result t)
        (present-failure presenter (event-name event) (failure-goal-form result)
                         (controller-schedule controller)))
      (setf (controller-clock controller) (controller-span-end controller))
      (present-state presenter controller)
      (if (eq result t)
          t
          (values nil (failure-goal-form result))))))

(defun find-controller-variable (controller name)
  "The variable NAME of CONTROLLER's spec, or an UNKNOWN-NAME-ERROR."
  (let ((*spec* (spec-of controller)))
    (or (and (or (symbolp name) (stringp name)) (find-variable-named name))
        (spec-fail 'unknown-name-error name "unknown variable ~A" (lisp-text name)))))

(defun state-value (controller name)
  "The current value of variable NAME in CONTROLLER: T/NIL for booleans, the
domain value for enumerated variables, a number (or NIL for a time never set)."
  (let ((var (find-controller-variable controller name)))
    (if (eq (var-kind var) :boolean)
        (= 1 (value-index-of controller var))
        (variable-value controller var))))

(defun controller-state (controller)
  "CONTROLLER's state as an alist ((VARIABLE . VALUE) ...) in declaration order."
  (loop for var in (spec-variables (spec-of controller))
        collect (cons (var-name var)
                      (if (eq (var-kind var) :boolean)
                          (= 1 (value-index-of controller var))
                          (variable-value controller var)))))

(defun active-autoscripts (controller)
  "The (PROC VARIABLE-NAME VALUE) triples running in CONTROLLER now."
  (loop for auto in (spec-autoscripts (spec-of controller))
        for var = (autoscript-variable auto)
        when (eql (autoscript-value-index auto)
                  (if (plannable-p var)
                      (value-index-of controller var)
                      (svref (controller-values controller) (var-slot var))))
          append (mapcar (lambda (proc) (list proc (var-name var) (autoscript-value auto)))
                         (autoscript-procs auto))))

(defun transferred-state (controller spec)
  "CONTROLLER's current values, expressed in SPEC: an alist for INITIAL-ASSIGNMENTS.
Variables SPEC does not have are dropped; new ones take their initial values."
  (loop for (name . value) in (controller-state controller)
        for var = (let ((*spec* spec)) (find-variable-named name))
        when (and var (not (and (eq (var-kind var) :time) (null value))))
          collect (cons (var-name var) value)))

(defun recompile (controller &optional (spec (spec-name (spec-of controller))))
  "Compile SPEC (default: the current definition of the controller's spec,
e.g. after re-evaluating its DEFSPEC) and switch CONTROLLER to it, keeping its
current state, clock and presenter. Autoscripts that stop or start applying
are told so. Signals STATE-TRANSFER-ERROR, leaving CONTROLLER unchanged, when a
current value does not exist in the new spec."
  (let* ((machine (compile-spec spec))
         (new-spec (machine-spec machine))
         (assignments (handler-case (initial-assignments new-spec (transferred-state controller new-spec))
                        (spec-error (e)
                          (error 'state-transfer-error
                                 :message (format nil "cannot keep the controller's state in the new spec: ~A" e)))))
         (before (active-autoscripts controller))
         (time (controller-clock controller))
         (presenter (controller-presenter controller)))
    (setf (controller-machine controller) machine
          (controller-labels controller) (make-array (spec-label-count new-spec)
                                                     :element-type 'double-float :initial-element 0d0))
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
    controller))
