;;;; cpp-steps.lisp -- the C++ backend's EMIT-STEP methods, one per IR step
;;;; class (the twins of lisp-closures.lisp's COMPILE-STEP), and :if conditions.

(in-package #:player.cpp)

;;; Steps

(defvar *indent* "  ")
(defvar *owner* nil "Name of the event or macro whose steps are emitted, for hook names.")
(defvar *hook-count* 0)
(defvar *planning* nil
  "True while the timed layer's planning twins are emitted (cpp-timeline.lisp):
steps then call the twins and record state changes instead of making them.")

(defun planning-id (id)
  "The planning twin of the procedure or setter named ID: plan_ID_ (no other
generated name ends in an underscore after a name that is not a C++ keyword)."
  (concatenate 'string "plan_" id "_"))

(defun goal-call-id (goal)
  "The procedure steps call to achieve GOAL: its achiever, or the planning twin."
  (if *planning* (planning-id (goal-fn-id goal)) (goal-fn-id goal)))

(defun op-call-id (op)
  "The procedure steps call to run OP: its executor, or the planning twin."
  (if *planning* (planning-id (op-id op)) (op-id op)))

(defun setter-call-id (var)
  "The setter of number VAR steps call: set_VAR, or its planning twin."
  (let ((setter (format nil "set_~A" (var-id var))))
    (if *planning* (planning-id setter) setter)))

(defun emit-steps (steps indent machine owner)
  "Emit STEPS at INDENT."
  (let ((*indent* indent) (*owner* owner) (*hook-count* 0))
    (dolist (step steps) (emit-step step machine))))

(defun emit-line (control &rest arguments)
  "One line of C++ at the current indentation."
  (write-string *indent* *out*)
  (apply #'emit control arguments))

(defgeneric emit-step (step machine)
  (:documentation "Write the C++ for STEP; on failure the code returns 2."))

(defun emit-achieve-call (goal failure)
  "Call GOAL's achiever, failing with FAILURE's goal text when there is no plan."
  (emit-line "{ const int r = ~A(); if (r == 0) return fail(~A); if (r != 1) return 2; }"
             (goal-call-id goal) (c++-string (lisp-text (failure-goal-form failure)))))

(defmethod emit-step ((step achieve-step) machine)
  (declare (ignore machine))
  (emit-achieve-call (achieve-step-goal step) (achieve-step-failure step)))

(defmethod emit-step ((step op-step) machine)
  (declare (ignore machine))
  (when (op-step-goal step)
    (emit-achieve-call (op-step-goal step) (op-step-failure step)))
  (emit-line "if (~A() != 1) return 2;" (op-call-id (op-step-op step))))

(defmethod emit-step ((step label-step) machine)
  (declare (ignore machine))
  (emit-line "state_.labels[~D] = schedule_;  // :label ~A" (label-step-slot step)
             (c++-comment-text (lisp-text (label-step-name step)))))

(defmethod emit-step ((step time-step) machine)
  (destructuring-bind (kind argument) (time-step-time step)
    (if (eq kind :relative)
        (emit-line "schedule_ = span_start_ + ~A;" (c++-time argument))
        (emit-line "{ const double t = ~A; if (!std::isnan(t)) { if (!(std::fabs(t) <= ~A)) return fail(~A); schedule_ = Time::from_seconds(t); } }"
                   (c++-number argument machine) (c++-double *max-seconds*)
                   (c++-string "(:overflow :time)")))))

(defmethod emit-step ((step if-step) machine)
  (emit-line "if (~A) {" (c++-condition (if-step-condition step) machine))
  (let ((*indent* (concatenate 'string *indent* "  ")))
    (dolist (inner (if-step-body step)) (emit-step inner machine)))
  (emit-line "}"))

(defmethod emit-step ((step assign-step) machine)
  (let* ((var (assign-step-variable step))
         (mask (var-field-mask var))
         (bit (var-value-bit var (assign-step-index step))))
    (if *planning*
        (emit-line "record_delta_(~A, ~A, schedule_, nullptr);" (c++-bits mask) (c++-bits bit))
        (dolist (line (state-change-lines machine "schedule_" mask bit))
          (emit-line "~A" line)))))

;;; :add/:sub (VAR N): a sum that would leave the variable's type (64 bits, or
;;; a finite double) fails the event with the goal (:overflow VAR), leaving the
;;; variable as it was, as the Lisp backend does.

(defmethod emit-step ((step increment-step) machine)
  (declare (ignore machine))
  (let* ((var (increment-step-variable step))
         (failure (c++-string (lisp-text (list :overflow (var-name var))))))
    (if (eq (var-type var) :integer)
        (emit-integer-increment var (increment-step-delta step) failure)
        (emit-float-increment var (increment-step-delta step) failure))))

(defun integer-overflow-test (field delta)
  "C++ that is true when FIELD + DELTA would leave 64 bits (no overflow in the
test itself: the bound is computed here), or NIL when DELTA is 0."
  (destructuring-bind (low high) *int64-range*
    (cond ((plusp delta) (format nil "~A > ~A" field (c++-int64 (- high delta))))
          ((minusp delta) (format nil "~A < ~A" field (c++-int64 (- low delta)))))))

(defun integer-sum (field delta)
  "C++ for FIELD + DELTA; a DELTA of 2^63 (the :sub of -2^63) is written as a
subtraction, since it has no literal."
  (if (c++-int64-p delta)
      (format nil "~A + ~A" field (c++-int64 delta))
      (format nil "~A - ~A" field (c++-int64 (- delta)))))

(defun emit-integer-increment (var delta failure)
  "Add DELTA to integer VAR, failing with FAILURE where the sum leaves 64 bits."
  (let* ((field (format nil "state_.~A" (var-id var)))
         (test (integer-overflow-test field delta)))
    (when test
      (emit-line "if (~A) return fail(~A);" test failure))
    (emit-line "~A(~A, schedule_);" (setter-call-id var) (integer-sum field delta))))

(defun emit-float-increment (var delta failure)
  "Add DELTA to float VAR, failing with FAILURE where the sum is not finite."
  (emit-line "{")
  (let ((*indent* (concatenate 'string *indent* "  ")))
    (emit-line "const double next = state_.~A + ~A;" (var-id var) (c++-double delta))
    (emit-line "if (!std::isfinite(next)) return fail(~A);" failure)
    (emit-line "~A(next, schedule_);" (setter-call-id var)))
  (emit-line "}"))

(defun code-comment-text (form)
  "The :code FORM as comment text, cut to a line's length."
  (c++-comment-text (truncate-text (lisp-text form) 160)))

(defmethod emit-step ((step code-step) machine)
  (declare (ignore machine))
  (emit-line "// :code ~A has no C++ meaning: the embedder implements the hook."
             (code-comment-text (code-step-form step)))
  (emit-line "presenter_.code_hook(~A);"
             (c++-string (format nil "~A/~D" (lisp-text *owner*) (incf *hook-count*)))))

(defmethod emit-step ((step c++-step) machine)
  (declare (ignore machine))
  (emit-line "~A" (c++-step-text step)))

;;; Conditions and numbers

(defun c++-cube-test (cubes)
  "C++ testing the state against the disjunction CUBES."
  (if (null cubes)
      "false"
      (format nil "(~{~A~^ || ~})"
              (mapcar (lambda (cube) (c++-cube-holds cube "state_.bits")) cubes))))

(defun c++-condition (ast machine)
  "C++ for the :IF condition AST."
  (if (state-only-p ast)
      (c++-cube-test (expression-cubes ast (machine-spec machine)))
      (ecase (first ast)
        (:not (format nil "!~A" (c++-condition (second ast) machine)))
        (:and (format nil "(~{~A~^ && ~})" (mapcar (lambda (a) (c++-condition a machine)) (rest ast))))
        (:or (format nil "(~{~A~^ || ~})" (mapcar (lambda (a) (c++-condition a machine)) (rest ast))))
        (:cmp (c++-comparison (second ast) (mapcar (lambda (a) (c++-number a machine)) (cddr ast)))))))

(defun c++-comparison (operator operands)
  "C++ comparing OPERANDS as Lisp's OPERATOR does (chains; /= is all-distinct)."
  (if (eq operator '/=)
      (format nil "(~{~A~^ && ~})"
              (loop for (a . rest) on operands
                    append (loop for b in rest collect (format nil "~A != ~A" a b))))
      (format nil "(~{~A~^ && ~})"
              (loop for (a b) on operands while b
                    collect (format nil "~A ~A ~A" a (if (eq operator '=) "==" (symbol-name operator)) b)))))

(defun c++-number (ast machine)
  "C++ (a double expression; NaN for a time never set) for numeric AST."
  (ecase (first ast)
    (:num (c++-double (second ast)))
    (:now "schedule_.to_double()")
    (:label (format nil "state_.labels[~D].to_double()" (second ast)))
    (:value (let ((var (second ast)))
              (if (plannable-p var)
                  (format nil "static_cast<double>(~A)"
                          (enum-integer-expression var))
                  (format nil "static_cast<double>(state_.~A)" (var-id var)))))
    (:arith (let ((parts (mapcar (lambda (a) (c++-number a machine)) (cddr ast))))
              (if (and (eq (second ast) '-) (null (rest parts)))
                  (format nil "(-~A)" (first parts))
                  (format nil "(~{~A~^ ~})"
                          (loop for (p . rest) on parts
                                collect p
                                when rest collect (symbol-name (second ast)))))))))

(defun enum-integer-expression (var)
  "C++ for the integer value of enumerated integer VAR."
  (format nil "kValues_~A[~A]" (var-id var) (field-index-expression var "state_.bits")))
