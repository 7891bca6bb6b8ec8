;;;; ctl.lisp -- CTL over a behaviour: the formulas, and the labelling
;;;; algorithm that finds the states where each holds.
;;;;
;;;; Clark & Palmer (§5): "An area for further work is to define a logic for
;;;; the state transition systems used for animation and to develop a
;;;; verification method." The logic is CTL (surveyed in their reference [2],
;;;; Arnold): formulas are s-expressions
;;;;   ATOM | t | true | false | (not F) | (and F...) | (or F...) | (implies F G)
;;;;   (EX F) (AX F) (EF F) (AF F) (EG F) (AG F) (EU F G) (AU F G)
;;;; An animation may stop (a state with no successor), so paths are maximal:
;;;; infinite, or ending at a dead end. (EX t) is false exactly at dead ends,
;;;; so (AG (EX t)) is deadlock-freedom; EG F holds along a path that ends at
;;;; a dead end with F true all the way; AX F holds at a dead end (no successor
;;;; contradicts it), so AX F = (not (EX (not F))) everywhere.
;;;;
;;;; Each operator's states are computed once, bottom-up, as a bit vector
;;;; (Clarke, Emerson and Sistla's labelling): EX by successors, EU by a
;;;; backward search from G through F, EG as a greatest fixpoint counting each
;;;; state's successors still in it; A-forms by duality.

(in-package #:player.logic)

(defparameter *ctl-operators*
  '(("EX" . 1) ("AX" . 1) ("EF" . 1) ("AF" . 1) ("EG" . 1) ("AG" . 1) ("EU" . 2) ("AU" . 2)
    ("NOT" . 1) ("IMPLIES" . 2) ("AND" . nil) ("OR" . nil))
  "The operators of formulas and their numbers of arguments (NIL: any).")

(defun operator (formula)
  "FORMULA's operator, an upcased name from *CTL-OPERATORS*, or NIL for an atom."
  (and (consp formula) (symbolp (first formula)) (first formula)
       (car (find (symbol-name (first formula)) *ctl-operators* :key #'car :test #'string-equal))))

(defun check-arity (formula)
  "FORMULA's arguments, checked against its operator's arity."
  (let ((arity (cdr (assoc (operator formula) *ctl-operators* :test #'string=))))
    (unless (and (proper-list-p formula) (or (null arity) (= arity (length (rest formula)))))
      (formula-fail formula "(~A ...) takes ~D argument~:P" (operator formula) arity))
    (rest formula)))

(defun constant-formula (formula)
  "(VALUES VALUE T) when FORMULA is a truth constant (t, true, false, nil)."
  (cond ((eq formula t) (values t t))
        ((null formula) (values nil t))
        ((and (symbolp formula) (word-p formula "TRUE")) (values t t))
        ((and (symbolp formula) (word-p formula "FALSE")) (values nil t))
        (t (values nil nil))))

(defun all-states (behaviour value)
  "A bit vector over BEHAVIOUR's states, every bit VALUE (0 or 1)."
  (make-array (behaviour-state-count behaviour) :element-type 'bit :initial-element value))

(defun sat-ex (behaviour set)
  "The states with a successor in SET."
  (let ((result (all-states behaviour 0)))
    (loop for i from 0
          for targets across (behaviour-successors behaviour)
          when (some (lambda (j) (= 1 (sbit set j))) targets)
            do (setf (sbit result i) 1))
    result))

(defun sat-eu (behaviour hold goal)
  "E[HOLD U GOAL]: the states from which a path through HOLD states reaches a GOAL state."
  (let ((result (copy-seq goal))
        (predecessors (behaviour-predecessor-vector behaviour))
        (queue (loop for i below (length goal) when (= 1 (sbit goal i)) collect i)))
    (loop while queue
          do (dolist (p (svref predecessors (pop queue)))
               (when (and (= 0 (sbit result p)) (= 1 (sbit hold p)))
                 (setf (sbit result p) 1)
                 (push p queue))))
    result))

(defun sat-eg (behaviour hold)
  "EG HOLD over maximal paths: the largest set of HOLD states each of which is
a dead end or has a successor in the set."
  (let* ((n (behaviour-state-count behaviour))
         (result (copy-seq hold))
         (successors (behaviour-successors behaviour))
         (predecessors (behaviour-predecessor-vector behaviour))
         (counts (make-array n :element-type 'fixnum :initial-element 0))
         (queue '()))
    (dotimes (i n)
      (when (= 1 (sbit result i))
        (setf (aref counts i) (count-if (lambda (j) (= 1 (sbit result j))) (svref successors i)))
        (when (and (zerop (aref counts i)) (svref successors i))
          (setf (sbit result i) 0)
          (push i queue))))
    (loop while queue
          do (dolist (p (svref predecessors (pop queue)))
               (when (and (= 1 (sbit result p)) (zerop (decf (aref counts p))))
                 (setf (sbit result p) 0)
                 (push p queue))))
    result))

(defun formula-holds-states (behaviour formula)
  "The states of BEHAVIOUR where the CTL FORMULA holds, as a bit vector
(bit I for state I). A FORMULA-ERROR naming the part of FORMULA that is not
CTL or names something BEHAVIOUR lacks."
  (multiple-value-bind (value constantp) (constant-formula formula)
    (when constantp
      (return-from formula-holds-states (all-states behaviour (if value 1 0)))))
  (let ((op (operator formula)))
    (flet ((sat (f) (formula-holds-states behaviour f)))
      (if (null op)
          (let ((predicate (funcall (behaviour-atom behaviour) formula behaviour))
                (result (all-states behaviour 0)))
            (loop for state across (behaviour-states behaviour)
                  for i from 0
                  when (funcall predicate state) do (setf (sbit result i) 1))
            result)
          (let ((arguments (check-arity formula)))
            (destructuring-bind (&optional a b) arguments
              (cond ((string= op "NOT") (bit-not (sat a)))
                    ((string= op "AND") (reduce #'bit-and (mapcar #'sat arguments)
                                                :initial-value (all-states behaviour 1)))
                    ((string= op "OR") (reduce #'bit-ior (mapcar #'sat arguments)
                                               :initial-value (all-states behaviour 0)))
                    ((string= op "IMPLIES") (bit-ior (bit-not (sat a)) (sat b)))
                    ((string= op "EX") (sat-ex behaviour (sat a)))
                    ((string= op "AX") (bit-not (sat-ex behaviour (bit-not (sat a)))))
                    ((string= op "EF") (sat-eu behaviour (all-states behaviour 1) (sat a)))
                    ((string= op "AG") (bit-not (sat-eu behaviour (all-states behaviour 1) (bit-not (sat a)))))
                    ((string= op "EG") (sat-eg behaviour (sat a)))
                    ((string= op "AF") (bit-not (sat-eg behaviour (bit-not (sat a)))))
                    ((string= op "EU") (sat-eu behaviour (sat a) (sat b)))
                    ((string= op "AU")
                     ;; not A[a U b] = E[not b U (not a and not b)] or EG not b
                     (let ((not-a (bit-not (sat a))) (not-b (bit-not (sat b))))
                       (bit-not (bit-ior (sat-eu behaviour not-b (bit-and not-a not-b))
                                         (sat-eg behaviour not-b))))))))))))
