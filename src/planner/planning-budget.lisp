;;;; planning-budget.lisp -- how much work planning one spec may do.
;;;;
;;;; The state limits (*STATE-LIMIT*, *REACHABLE-STATE-LIMIT*) bound memory,
;;;; not time: a 78 KB spec of 1,700 ops and 6 million states, or one of 500
;;;; variables in the reachable regime, plans for many seconds before the user
;;;; hears anything.  So PLAN-SPEC pays for its work as it does it, out of one
;;;; budget per spec: a state expanded by the reachable search, a plan taken
;;;; off WorkingQ, a regressed cube tested against SolvedStates, 64 states
;;;; marked solved.  Each costs more on a wider state (its cubes are integers
;;;; as wide as the state).  The units are counted, not timed, so whether a
;;;; spec plans never depends on the machine's load; the step that passes the
;;;; budget stops planning with a PLANNING-BUDGET-EXCEEDED naming the spec,
;;;; its file, and how far planning got (issue 31).

(in-package #:player.planner)

(defparameter *planning-budget* 1500000000
  "Most units of work planning one spec may do, or NIL for no limit; a unit is
a 64-bit word of SolvedStates read, and PLANNING-STEP-COST says how many units
a step of the search is.  A spec raises or lifts it with (:planning-budget N)
or (:planning-budget :unlimited).  Chosen by measurement on this project's
2-core machine, where a unit takes 0.4-5 ns: the specs slowest to plan for
their units (6 million states and a 860-value variable; 300 booleans in the
reachable regime) pass it in about 4 s.  Peedy uses about 400,000 units,
the synthetic family at 26 variables 70 million, the random 26-variable spec
of `make bench` 770 million.")

(defvar *planning-work* nil
  "Units of work the planning under way has done, or NIL when none is counted.")

(defvar *planning-limit* nil
  "Most units the planning under way may do, or NIL for no limit.")

(defvar *planning-step-cost* 1
  "How many units one step of the planning under way costs (PLANNING-STEP-COST).")

(defvar *planning-spec* nil "The spec being planned (WITH-PLANNING-BUDGET binds it).")

(defvar *planning-reachable* nil
  "True while the spec under way is planned for its reachable states only.")

(defvar *planning-stage* nil
  "How far the planning under way got: NIL while its reachable states are
searched, else (GOALS-PLANNED GOAL-COUNT STATE-COUNT).")

(define-condition planning-budget-exceeded (player-error)
  ((spec :initarg :spec :reader planning-budget-spec :documentation "The spec's name, as text.")
   (file :initarg :file :initform nil :reader planning-budget-file
         :documentation "The file the spec was loaded from, as text, or NIL.")
   (budget :initarg :budget :reader planning-budget-budget :documentation "The budget passed, in units.")
   (stage :initarg :stage :initform nil :reader planning-budget-stage
          :documentation "NIL when the reachable search passed it, else (PLANNED GOALS STATES).")
   (reachable :initarg :reachable :initform nil :reader planning-budget-reachable
              :documentation "True when the spec was planned for its reachable states only."))
  (:report (lambda (condition stream)
             (destructuring-bind (&optional planned goals states) (planning-budget-stage condition)
               (format stream "spec ~A~@[ (~A)~] passed its planning budget of ~:D units ~:[while searching its reachable states~;~:*after planning ~:D of ~:D goal~:P over ~:D state~:P~]; raise it with (:planning-budget N) or (:planning-budget :unlimited)~:[, or plan fewer states with (:state-space :reachable) and (:unplanned-states :search)~;, or make fewer states reachable or fewer goals~]"
                       (planning-budget-spec condition) (planning-budget-file condition)
                       (planning-budget-budget condition) planned goals states
                       (planning-budget-reachable condition)))))
  (:documentation "Planning a spec did more work than its planning budget allows
(*PLANNING-BUDGET*, or the spec's (:planning-budget N))."))

(defun planning-step-cost (spec)
  "What a step of planning (a plan taken off WorkingQ, a cube regressed and
tested) costs on SPEC, in units of a 64-bit word of SolvedStates read.
Measured on wide and large-domain specs: a step takes about 40 ns, plus
4-5 ns per plannable variable (a cube is tested variable by variable), plus
about 15 ns per 64-bit word of the state (its cubes are bignums that wide,
made anew by each LOGAND); a word read takes 1.5-4 ns."
  (+ 20 (* 2 (length (plannable-variables spec))) (* 6 (ceiling (1+ (spec-bit-count spec)) 64))))

(defun state-expansion-cost (roots transitions)
  "What the reachable search pays to expand a state, from ROOTS (one-hot
states) under TRANSITIONS: each transition tests its precondition and applies
its effects on integers as wide as the state, then looks the state up."
  (* (length transitions)
     (+ 10 (ceiling (integer-length (reduce #'logior roots :initial-value 0)) 64))))

(defun spec-planning-budget (spec)
  "The units planning SPEC may do: its (:planning-budget N) option, NIL under
(:planning-budget :unlimited), else *PLANNING-BUDGET*."
  (let ((option (getf (spec-options spec) :planning-budget)))
    (cond ((null option) *planning-budget*)
          ((eq option :unlimited) nil)
          (t option))))

(defmacro with-planning-budget ((spec) &body body)
  "Run BODY, planning SPEC, counting its work against SPEC's planning budget.
Returns BODY's value and, second, the units of work it did."
  `(let ((*planning-work* 0)
         (*planning-limit* (spec-planning-budget ,spec))
         (*planning-step-cost* (planning-step-cost ,spec))
         (*planning-spec* ,spec)
         (*planning-stage* nil)
         (*planning-reachable* nil))
     (values (progn ,@body) *planning-work*)))

(defmacro noting-goals-planned ((planned goals states) &body body)
  "Run BODY with PLANNED of GOALS goals over STATES states as the stage a
budget error reports; NOTE-GOAL-PLANNED counts each goal BODY plans."
  `(let ((*planning-stage* (list ,planned ,goals ,states)))
     ,@body))

(defun note-planning-regime (layout)
  "Remember whether LAYOUT, the planning under way's, holds reachable states only."
  (setf *planning-reachable* (and (layout-reachable layout) t)))

(defun note-goal-planned ()
  "Count one more goal of the planning under way as planned."
  (when *planning-stage*
    (incf (first *planning-stage*))))

(declaim (inline spend-planning-work))
(defun spend-planning-work (steps)
  "Pay for STEPS steps of the planning under way (nothing when none is
counted), each of *PLANNING-STEP-COST* units; past its budget, signal
PLANNING-BUDGET-EXCEEDED."
  (let ((work *planning-work*))
    (when work
      (let ((now (+ work (* steps *planning-step-cost*))))
        (setf *planning-work* now)
        (when (and *planning-limit* (> now *planning-limit*))
          (planning-budget-passed))))))

(declaim (inline spend-planning-units spend-scanned-words))
(defun spend-planning-units (units)
  "Pay for UNITS units (words read) of the planning under way, if it is counted."
  (let ((work *planning-work*))
    (when work
      (setf *planning-work* (+ work units))
      (when (and *planning-limit* (> *planning-work* *planning-limit*))
        (planning-budget-passed)))))

(defun spend-scanned-words (count &optional result)
  "Pay for reading COUNT words of SolvedStates (a unit each, whatever the
width); return RESULT.  The scans of solved-states.lisp count their words in
a local counter and pay once, so the count costs nothing per word."
  (let ((work *planning-work*))
    (when (and work (plusp count))
      (setf *planning-work* (+ work count))
      (when (and *planning-limit* (> *planning-work* *planning-limit*))
        (planning-budget-passed))))
  result)

(defun planning-budget-passed ()
  "Signal the PLANNING-BUDGET-EXCEEDED of the planning under way."
  (let* ((spec *planning-spec*)
         (file (spec-source-file spec))
         (stage (and *planning-stage* (copy-list *planning-stage*))))
    ;; Unbound, so that printing the error or cleaning up plans nothing more.
    (setf *planning-work* nil)
    (error 'planning-budget-exceeded
           :spec (lisp-text (spec-name spec))
           :file (and file (if (pathnamep file) (sb-ext:native-namestring file) (princ-to-string file)))
           :budget *planning-limit* :stage stage
           :reachable (or (null stage) *planning-reachable*))))
