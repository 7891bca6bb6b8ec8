;;;; lisp-steps.lisp -- the Lisp backend's steps: one closure per IR step of
;;;; an event or macro-op (COMPILE-STEP), chained right to left by
;;;; COMPILE-STEPS (lisp-closures.lisp), and the closures of the runtime
;;;; conditions and numbers of :if, :time and :add/:sub (VAR N).

(in-package #:player.control)

;;; Steps

(defgeneric compile-step (step next machine)
  (:documentation "A closure of one argument (the controller) that performs
STEP and, on success, returns what NEXT returns; on failure, a FAILURE."))

(defun achieve-then (box failure next)
  "A closure achieving the goal in BOX, then calling NEXT; FAILURE if no plan."
  (lambda (controller)
    (let ((result (call-box box controller)))
      (cond ((eq result t) (funcall (the function next) controller))
            ((null result) failure)
            (t result)))))

(defmethod compile-step ((step achieve-step) next machine)
  (declare (ignore machine))
  (achieve-then (procedure-box (achieve-step-goal step)) (achieve-step-failure step) next))

(defmethod compile-step ((step op-step) next machine)
  (declare (ignore machine))
  (let* ((box (procedure-box (op-step-op step)))
         (run (lambda (controller)
                (let ((result (call-box box controller)))
                  (if (eq result t) (funcall (the function next) controller) result)))))
    (if (op-step-goal step)
        (achieve-then (procedure-box (op-step-goal step)) (op-step-failure step) run)
        run)))

(defmethod compile-step ((step label-step) next machine)
  (declare (ignore machine))
  (let ((slot (label-step-slot step)))
    (lambda (controller)
      (setf (svref (controller-labels controller) slot) (controller-schedule controller))
      (funcall (the function next) controller))))

(defun schedulable-time-p (time)
  "Can the clock be set to TIME: a finite number within *MAX-SECONDS* of 0?"
  (and (finite-real-p time) (<= (abs time) *max-seconds*)))

(defmethod compile-step ((step time-step) next machine)
  (destructuring-bind (kind argument) (time-step-time step)
    (let ((value (if (eq kind :relative) nil (compile-number argument machine)))
          ;; A relative time is whole microseconds from the span's start.
          (offset (if (eq kind :relative) (seconds->micros (to-double argument)) 0))
          (overflow (make-failure (list :overflow :time))))
      (lambda (controller)
        (let ((time (if value
                        (funcall (the function value) controller)
                        (+ (controller-span-start controller) offset))))
          (cond ((null time) (funcall (the function next) controller))
                ((null value)
                 (setf (controller-schedule controller) time)
                 (funcall (the function next) controller))
                ((schedulable-time-p time)
                 ;; Computed seconds, as a double (the C++ backend's), to microseconds.
                 (setf (controller-schedule controller) (seconds->micros (to-double time)))
                 (funcall (the function next) controller))
                ;; An arithmetic :time beyond the clock's range fails the event.
                (t overflow)))))))

(defmethod compile-step ((step if-step) next machine)
  (let ((condition (compile-condition (if-step-condition step) machine))
        (body (compile-steps (if-step-body step) machine next)))
    (lambda (controller)
      (if (funcall (the function condition) controller)
          (funcall (the function body) controller)
          (funcall (the function next) controller)))))

(defmethod compile-step ((step assign-step) next machine)
  (let ((var (assign-step-variable step)))
    (with-state-bits (machine)
      (let ((mask (state-bits (var-field-mask var)))
            (bit (state-bits (var-value-bit var (assign-step-index step)))))
        (lambda (controller)
          (set-state controller (state-bits (logior (logandc2 (state-bits (controller-bits controller)) mask) bit))
                     mask bit (controller-schedule controller) nil)
          (funcall (the function next) controller))))))

(declaim (inline plain-number-p))
(defun plain-number-p (x)
  "Is X a fixnum, or a double below 2^500 in magnitude, so that comparing it,
or adding, subtracting or multiplying it with another such, raises no float
trap?  Then the closures skip masking traps (which costs more than the sum).
A double's exponent bits say it: NaNs and infinities fail too, without a
comparison (which would trap on a NaN)."
  (or (typep x 'fixnum)
      (and (typep x 'double-float)
           (< (ldb (byte 11 20) (sb-kernel:double-float-high-bits x)) (+ 1023 500)))))

(defun checked-sum (value delta integerp)
  "VALUE + DELTA, or NIL when the sum leaves the variable's type: an integer
outside 64 bits (INTEGERP), or a float that is not finite (the C++ backend's
long long and double)."
  (if integerp
      (let ((sum (+ value delta)))
        (and (typep sum '(signed-byte 64)) sum))
      (let ((value (the double-float value)) (delta (the double-float delta)))
        (if (and (plain-number-p value) (plain-number-p delta))
            ;; Far from the limits, the sum is finite: no traps to mask.
            (+ value delta)
            (let ((sum (sb-int:with-float-traps-masked (:overflow :invalid :inexact)
                         (+ value delta))))
              (and (<= (abs sum) most-positive-double-float) sum))))))

(defmethod compile-step ((step increment-step) next machine)
  (declare (ignore machine))
  (let* ((var (increment-step-variable step))
         (slot (var-slot var))
         (delta (increment-step-delta step))
         (integerp (eq (var-type var) :integer))
         (delta (if integerp delta (to-double delta)))
         (overflow (make-failure (list :overflow (var-name var)))))
    (lambda (controller)
      (let ((sum (checked-sum (svref (controller-values controller) slot) delta integerp)))
        (if sum
            (progn (set-runtime-value controller var sum (controller-schedule controller))
                   (funcall (the function next) controller))
            overflow)))))

(defmethod compile-step ((step code-step) next machine)
  (let ((code (compile-code (code-step-form step) (machine-spec machine))))
    (lambda (controller)
      (funcall (the function code))
      (funcall (the function next) controller))))

(defmethod compile-step ((step c++-step) next machine)
  (declare (ignore step machine))
  next)

;;; Runtime conditions (:if)

(defun compile-condition (ast machine)
  "A predicate of the controller for :IF condition AST."
  (let ((spec (machine-spec machine)))
    (if (state-only-p ast)
        (let ((cubes (expression-cubes ast spec)))
          (with-state-bits (machine)
            (lambda (controller)
              (let ((bits (state-bits (controller-bits controller))))
                (dolist (cube cubes nil)
                  (when (zerop (logandc2 bits (state-bits cube))) (return t)))))))
        (ecase (first ast)
          (:not (let ((inner (compile-condition (second ast) machine)))
                  (lambda (controller) (not (funcall (the function inner) controller)))))
          (:and (let ((parts (mapcar (lambda (a) (compile-condition a machine)) (rest ast))))
                  (lambda (controller) (every (lambda (p) (funcall (the function p) controller)) parts))))
          (:or (let ((parts (mapcar (lambda (a) (compile-condition a machine)) (rest ast))))
                 (lambda (controller) (some (lambda (p) (funcall (the function p) controller)) parts))))
          (:cmp (compile-comparison (second ast) (cddr ast) machine))))))

(defun compile-comparison (operator operands machine)
  "A predicate comparing OPERANDS with OPERATOR. An unset time variable is like
NaN: every comparison with it is false, except /=."
  (let ((values (mapcar (lambda (a) (compile-number a machine)) operands))
        (function (symbol-function operator)))
    (if (= (length values) 2)
        (compile-binary-comparison operator function (first values) (second values))
        (lambda (controller)
          (let ((numbers (mapcar (lambda (v) (funcall (the function v) controller)) values)))
            (if (member nil numbers)
                (eq operator '/=)
                ;; IEEE comparisons, as in the C++: a NaN compares false.
                (sb-int:with-float-traps-masked (:invalid :overflow :inexact)
                  (apply function numbers))))))))

(defun compile-binary-comparison (operator function left right)
  "COMPILE-COMPARISON's predicate for two operands, LEFT and RIGHT (compiled
numbers): the same answers without a list of the numbers, and without
masking traps when both are plain numbers (PLAIN-NUMBER-P)."
  (lambda (controller)
    (let ((a (funcall (the function left) controller))
          (b (funcall (the function right) controller)))
      (cond ((or (null a) (null b)) (eq operator '/=))
            ((and (plain-number-p a) (plain-number-p b)) (funcall function a b))
            (t (sb-int:with-float-traps-masked (:invalid :overflow :inexact)
                 (funcall function a b)))))))

(defun compile-number (ast machine)
  "A function of the controller computing numeric AST, or NIL for an unset time."
  (ecase (first ast)
    (:num (let ((x (second ast))) (lambda (controller) (declare (ignore controller)) x)))
    ;; Times enter arithmetic as doubles, converted as the C++ backend converts them.
    (:now (lambda (controller) (micros->double (controller-schedule controller))))
    (:label (let ((slot (second ast)))
              (lambda (controller) (micros->double (svref (controller-labels controller) slot)))))
    (:value (let ((var (second ast)))
              (if (plannable-p var)
                  (lambda (controller) (variable-value controller var))
                  (let ((slot (var-slot var)))
                    (lambda (controller) (svref (controller-values controller) slot))))))
    (:arith (let ((parts (mapcar (lambda (a) (compile-number a machine)) (cddr ast)))
                  (function (symbol-function (second ast))))
              (if (and (= (length parts) 2) (member (second ast) '(+ - *)))
                  (compile-binary-arithmetic function (first parts) (second parts))
                  (lambda (controller)
                    (let ((numbers (mapcar (lambda (p) (funcall (the function p) controller)) parts)))
                      (unless (member nil numbers)
                        ;; IEEE arithmetic, as in the C++: overflow gives an infinity.
                        (sb-int:with-float-traps-masked (:invalid :overflow :inexact :divide-by-zero)
                          (apply function numbers))))))))))

(defun compile-binary-arithmetic (function left right)
  "COMPILE-NUMBER's function for +, - or * (FUNCTION) of two operands, LEFT
and RIGHT (compiled numbers): the same value without a list of the numbers,
and without masking traps when both are plain numbers (PLAIN-NUMBER-P)."
  (lambda (controller)
    (let ((a (funcall (the function left) controller))
          (b (funcall (the function right) controller)))
      (cond ((or (null a) (null b)) nil)
            ((and (plain-number-p a) (plain-number-p b)) (funcall function a b))
            (t (sb-int:with-float-traps-masked (:invalid :overflow :inexact :divide-by-zero)
                 (funcall function a b)))))))
