;;;; lisp-closures.lisp -- the Lisp backend: compile a machine into closures.
;;;;
;;;; As in the paper's generated C++, each goal gets one shared state-achieving
;;;; procedure (its plans as a chain of cube tests), each op one operator-
;;;; execution procedure, each event one procedure. Steps compile right to
;;;; left into a chain, each closure calling NEXT on success (cl-ppcre's
;;;; CREATE-MATCHER-AUX style). A chain returns T, or the FAILURE of the goal
;;;; that could not be achieved.

(in-package #:player.control)

(defstruct (compiled-machine (:include machine) (:constructor %make-compiled-machine))
  "A MACHINE whose events are compiled to Lisp closures: what COMPILE-SPEC
returns and controllers run. The C++ backend needs only the MACHINE."
  ;; Event name key -> COMPILED-EVENT.
  (events (make-hash-table :test 'equal))
  ;; Event symbol -> COMPILED-EVENT, filled as events are sent, so the usual
  ;; lookup by symbol allocates nothing and takes no lock. Never changed once
  ;; published: a new symbol replaces the whole table (copy on write), so
  ;; controllers on several threads may read it while one adds to it.
  (event-symbols (make-hash-table :test 'eq))
  ;; The same pairs as an open-addressed SYMBOL-INDEX, replaced with the
  ;; table: what FIND-COMPILED-EVENT reads (a probe or two, no hash-table call).
  (symbol-index (make-symbol-index '()) :type simple-vector)
  ;; The goal and op procedure boxes, for closures compiled later (EVENT-SUFFIXES).
  (procedures nil)
  ;; The WATCHes of its watched variables (see TRANSITION-STATE), made once.
  (watches nil :type list)
  (watches-made nil :type boolean))

;;; A symbol index: (SYMBOL . VALUE) pairs in a simple-vector of 2^k slot
;;; pairs, SYMBOL at 2i and VALUE at 2i+1, placed by the symbol's SXHASH
;;; (SBCL keeps it in the symbol) and linear probing; at most half full, so
;;; every probe ends at an empty slot (key 0, never a symbol).

(defun make-symbol-index (pairs)
  "A symbol index of PAIRS ((SYMBOL . VALUE) ..., distinct symbols)."
  (let* ((size (loop for size = 2 then (* 2 size)
                     when (>= size (* 2 (1+ (length pairs)))) return size))
         (index (make-array (* 2 size) :initial-element 0))
         (mask (1- size)))
    (loop for (symbol . value) in pairs
          do (loop for i = (logand (sxhash symbol) mask) then (logand (1+ i) mask)
                   when (eql (svref index (* 2 i)) 0)
                     return (setf (svref index (* 2 i)) symbol
                                  (svref index (1+ (* 2 i))) value)))
    index))

(declaim (inline symbol-index-value))
(defun symbol-index-value (index symbol)
  "The value of SYMBOL in symbol INDEX, or NIL."
  (declare (simple-vector index) (symbol symbol))
  (let ((mask (1- (ash (length index) -1))))
    (loop for i of-type fixnum = (logand (sxhash symbol) mask) then (logand (1+ i) mask)
          for key = (svref index (* 2 i))
          do (cond ((eq key symbol) (return (svref index (1+ (* 2 i)))))
                   ((eql key 0) (return nil))))))

(defun machine-watches (machine)
  "MACHINE's WATCHes (see TRANSITION-STATE): made once for a compiled machine."
  (cond ((not (compiled-machine-p machine)) (make-watches machine))
        ((compiled-machine-watches-made machine) (compiled-machine-watches machine))
        (t (prog1 (setf (compiled-machine-watches machine) (make-watches machine))
             (setf (compiled-machine-watches-made machine) t)))))

(defmethod print-object ((machine compiled-machine) stream)
  (print-unreadable-object (machine stream :type t)
    (format stream "~A ~D goal~:P, ~D state~:P, ~D event~:P"
            (lisp-text (spec-name (machine-spec machine))) (length (machine-goal-table machine))
            (layout-state-count (machine-layout machine)) (hash-table-count (compiled-machine-events machine)))))

(defvar *procedures* nil
  "While a machine compiles: hash table of GOAL or OP-DEF -> box (a cons whose
CAR is the procedure), so procedures can call each other before they exist.")

(defstruct (compiled-event (:constructor make-compiled-event (event run steps policy)))
  "An event compiled to a closure of one argument, the controller. STEPS are
its top-level IR steps; a timed controller asks for EVENT-SUFFIXES, compiled
from them the first time."
  (event nil :type event-def)
  (run nil :type function)
  (steps '() :type list)
  (suffixes nil :type (or null simple-vector))
  ;; Its :when-busy policy, else its spec's (EVENT-POLICY), known when it is
  ;; compiled: a timed controller asks for every event it is sent.
  (policy :queue :type keyword)
  ;; Does the event run :code of its own: T, NIL, or :UNKNOWN until a timed
  ;; controller asks (EVENT-RUNS-CODE-P, src/control/timeline/footprints.lisp).
  (runs-code :unknown :type (member t nil :unknown))
  ;; Is its plan decided by the plannable state alone (T, NIL, or :UNKNOWN
  ;; until a timed controller asks), and its plans taped so far, by start
  ;; state: see src/control/timeline/tapes.lisp.
  (tapeable :unknown :type (member t nil :unknown))
  (tapes nil))

(defun compile-event-suffixes (steps machine)
  "For each top-level step K of STEPS, a closure running the event from K on
(noting K in the controller as it goes), so a timed controller can finish an
interrupted event from where it was cut; then one that does nothing."
  (let* ((count (length steps))
         (suffixes (make-array (1+ count))))
    (setf (svref suffixes count) #'succeed)
    (loop for k from (1- count) downto 0
          for step in (reverse steps)
          do (let ((body (compile-step step (svref suffixes (1+ k)) machine))
                   (k k))
               (setf (svref suffixes k)
                     (lambda (controller)
                       (setf (controller-step controller) k)
                       (funcall (the function body) controller)))))
    suffixes))

;; Inline: a timed controller asks for every event it plans.
(declaim (inline event-suffixes))
(defun event-suffixes (compiled machine)
  "The suffix closures (see COMPILE-EVENT-SUFFIXES) of COMPILED, an event of
compiled MACHINE; compiled on first use, so whole-event controllers never pay
for them."
  (or (compiled-event-suffixes compiled)
      (let ((*procedures* (compiled-machine-procedures machine)))
        (setf (compiled-event-suffixes compiled)
              (compile-event-suffixes (compiled-event-steps compiled) machine)))))

(defun procedure-box (key)
  "The box of KEY's shared procedure, created empty on first request."
  (or (gethash key *procedures*)
      (setf (gethash key *procedures*) (list nil))))

(defun compile-spec (spec)
  "Plan SPEC (a spec or the name of one) and compile it into a COMPILED-MACHINE
whose events run as Lisp closures. Signals SPEC-ERROR for an unknown name and
STATE-SPACE-TOO-LARGE for a spec beyond the planner's reach."
  (let* ((spec (designated-spec spec 'compile-spec))
         (start (get-internal-real-time))
         (machine (plan-spec spec :constructor #'%make-compiled-machine))
         (*procedures* (make-hash-table :test 'eq)))
    (loop for goal across (machine-goal-table machine)
          do (setf (car (procedure-box goal))
                   ;; the reachable regime's guard (unplanned-states.lisp); else the achiever itself
                   (guard-planned-states (compile-achiever goal machine) goal machine)))
    (dolist (op (spec-ops spec))
      (setf (car (procedure-box op)) (compile-executor op machine)))
    (dolist (event (spec-events spec))
      (setf (gethash (name-key (event-name event)) (compiled-machine-events machine))
            (let ((steps (directive-steps (event-directives event) machine)))
              (make-compiled-event event (compile-steps steps machine) steps (event-policy event spec)))))
    (setf (compiled-machine-procedures machine) *procedures*)
    (setf (machine-compile-seconds machine)
          (/ (float (- (get-internal-real-time) start) 1d0) internal-time-units-per-second))
    machine))

(defun ensure-compiled-machine (designator)
  "DESIGNATOR as a COMPILED-MACHINE: itself, or else the compiled machine of a
planned machine's spec, of a spec, or of a spec's name."
  (cond ((compiled-machine-p designator) designator)
        ((machine-p designator) (compile-spec (machine-spec designator)))
        (t (check-argument 'compile-spec 'machine designator #'machine-designator-p *machine-designator*)
           (compile-spec designator))))

(defun succeed (controller)
  "The end of every chain: nothing left to do, so CONTROLLER's event succeeded."
  (declare (ignore controller))
  t)

(defun compile-steps (steps machine &optional (final #'succeed))
  "Chain STEPS into one closure that ends by calling FINAL."
  (reduce (lambda (step next) (compile-step step next machine))
          steps :from-end t :initial-value final))

(declaim (inline call-box))
(defun call-box (box controller)
  "Run the procedure in BOX on CONTROLLER."
  (funcall (the function (car box)) controller))

;;; State-achieving procedures

(defun compile-achiever (goal machine)
  "GOAL's state-achieving procedure: run the first plan whose condition holds.
Returns T, NIL when no plan applies, or a FAILURE from inside a macro-op."
  (let* ((plans (goal-plans goal))
         (conditions (map 'simple-vector #'plan-condition plans))
         (runners (map 'simple-vector (lambda (plan) (compile-plan-runner (plan-ops plan))) plans))
         (count (length plans)))
    (with-state-bits (machine)
      (lambda (controller)
        (let ((bits (state-bits (controller-bits controller))))
          (dotimes (i count nil)
            (when (zerop (logandc2 bits (state-bits (svref conditions i))))
              (return (funcall (the function (svref runners i)) controller)))))))))

(defun compile-plan-runner (ops)
  "A closure running OPS in order, stopping at the first failure."
  (cond ((null ops) #'succeed)
        ;; One op (most plans' last step): its procedure's answer is the plan's.
        ((null (rest ops))
         (let ((box (procedure-box (first ops))))
           (lambda (controller) (call-box box controller))))
        (t (let ((boxes (mapcar #'procedure-box ops)))
             (lambda (controller)
               (dolist (box boxes t)
                 (let ((result (call-box box controller)))
                   (unless (eq result t) (return result)))))))))

;;; Operator-execution procedures

(defun compile-executor (op machine)
  "OP's execution procedure: play it (a macro: run its :seq), then apply its
effects. Its precondition is the caller's business."
  (if (eq (op-kind op) :macro)
      (compile-macro-executor op machine)
      (with-state-bits (machine)
        (let ((mask (state-bits (op-effect-mask op))) (bits (state-bits (op-effect-bits op)))
              (code (and (eq (op-kind op) :code) (compile-code (op-code op) (machine-spec machine))))
              ;; Times are whole microseconds (EXACT-TIMES.LISP); presenters see seconds.
              (duration (seconds->micros (op-duration op))))
          (lambda (controller)
            (when code (funcall (the function code)))
            (let ((recorder (controller-recorder controller)))
              (if recorder
                  ;; A timed controller planning ahead records the op and
                  ;; its end's change (one plain call, no protocol dispatch).
                  (record-op-played recorder controller op mask bits)
                  (let* ((start (controller-schedule controller))
                         ;; A silent presenter's PRESENT-OP answers the
                         ;; declared duration: no need to ask it.
                         (end (+ start (if (silent-p controller)
                                           duration
                                           (let ((presenter (controller-presenter controller)))
                                             (seconds->micros
                                              (presenter-seconds (present-op presenter op (micros->seconds start))
                                                                 presenter 'present-op op)))))))
                    (note-op-end controller end)
                    (unless (zerop mask)
                      (set-state controller
                                 (state-bits (logior (logandc2 (state-bits (controller-bits controller)) mask) bits))
                                 mask bits end op)))))
            t)))))

(defun compile-macro-executor (op machine)
  "A macro-op's procedure: run its :SEQ on its own span; then the state is the
one it started from with the declared effects applied (changes the sub-ops
made along the way are internal to the macro)."
  (let ((mask (op-effect-mask op)) (bits (op-effect-bits op)))
    (let ((seq (compile-steps (directive-steps (op-seq op) machine) machine))
          (bit (ash 1 (position op (spec-ops (machine-spec machine)))))
          (reentered (make-failure (op-name op)))
          (field-masks (plannable-field-masks (machine-spec machine))))
      (lambda (controller)
        (if (logtest bit (controller-active-macros controller))
            reentered
            (let ((presenter (controller-presenter controller))
                  (start (controller-schedule controller))
                  (outer-start (controller-span-start controller))
                  (outer-end (controller-span-end controller))
                  (before (controller-bits controller)))
              (cond ((controller-recorder controller)
                     (record-macro-start (controller-recorder controller) op start))
                    ((not (silent-p controller)) (present-macro-start presenter op (micros->seconds start))))
              (setf (controller-span-start controller) start
                    (controller-span-end controller) start
                    (controller-active-macros controller)
                    (logior bit (controller-active-macros controller)))
              (let* ((result (funcall (the function seq) controller))
                     (end (controller-span-end controller)))
                (setf (controller-active-macros controller)
                      (logandc2 (controller-active-macros controller) bit)
                      (controller-span-start controller) outer-start
                      (controller-span-end controller) (if (micros< outer-end end) end outer-end)
                      (controller-schedule controller) end)
                (cond ((controller-recorder controller)
                       (record-macro-end (controller-recorder controller) op start end))
                      ((not (silent-p controller))
                       (present-macro-end presenter op (micros->seconds start) (micros->seconds end))))
                (when (eq result t)
                  (change-state-to controller (state-with-fields before mask bits) end field-masks op))
                result)))))))
