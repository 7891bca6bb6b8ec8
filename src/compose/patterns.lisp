;;;; patterns.lisp -- the paper's patterns, and restriction predicates built
;;;; from them with & and => (Clark & Palmer, Appendix A).
;;;;
;;;; "Predicates which are used to restrict graphs may be specified as
;;;; patterns, where a pattern p is one of the following: an identifier i, a
;;;; constant k, a wildcard _ or a pair of patterns (p1, p2)."  In Lisp:
;;;;
;;;;   _                 the wildcard (a symbol named "_", in any package)
;;;;   x, p1, ...        an identifier: any other symbol but NIL, T and keywords
;;;;   0, -1, :a, "s"    a constant: any other atom
;;;;   'v = (quote v)    the constant V, whatever it is
;;;;   (p1 . p2)         the pair pattern: matches a cons whose car matches p1
;;;;                     and whose cdr matches p2. The paper's (0, x) is (0 . x)
;;;;   (:eval f i ...)   (an extension, for the paper's (0, x) => (0, -x)): the
;;;;                     constant (f i ...), F a function designator applied to
;;;;                     the values of identifiers already bound: (0 :eval - x)
;;;;                     is the pair (0 . (:eval - x)), the paper's (0, -x).
;;;;
;;;; A pattern compiled by PATTERN matches with MATCH-PATTERN. Predicates for
;;;; RESTRICT are functions of (SOURCE TARGET); those made here (PRED-IMPLIES,
;;;; PRED-EDGE, PRED-NODES, PRED-AND) are EDGE-PREDICATEs: funcallable, and
;;;; remembering their patterns, so RESTRICT can refuse a pattern that names no
;;;; node of the graph, and their conjuncts, so RESTRICT can apply the paper's
;;;; reading of &.

(in-package #:player.compose)

;;; Patterns

(defstruct (pattern (:constructor %make-pattern (form)))
  "A compiled pattern; FORM is the pattern as written."
  (form nil :read-only t))

(defmethod print-object ((pattern pattern) stream)
  (print-unreadable-object (pattern stream :type t)
    (format stream "~A" (node-text (pattern-form pattern)))))

(defun wildcard-p (form)
  "Is FORM the wildcard _?"
  (and (symbolp form) (string= (symbol-name form) "_")))

(defun identifier-p (form)
  "Is FORM a pattern identifier?"
  (and (symbolp form) form (not (eq form t)) (not (keywordp form)) (not (wildcard-p form))))

(defun quoted-constant-p (form)
  "Is FORM (quote V)?"
  (and (consp form) (eq (car form) 'quote) (consp (cdr form)) (null (cddr form))))

(defun eval-pattern-p (form)
  "Is FORM (:eval F IDENTIFIER...)?"
  (and (consp form) (eq (car form) :eval)))

(defun check-pattern-form (form whole)
  "Signal a GRAPH-ERROR unless FORM, part of the pattern WHOLE, is well formed."
  (cond ((eval-pattern-p form)
         (unless (and (proper-list-p form) (cdr form)
                      (or (functionp (second form)) (and (symbolp (second form)) (second form)))
                      (every #'identifier-p (cddr form)))
           (graph-fail whole "pattern ~A: ~A is not (:eval FUNCTION IDENTIFIER...)"
                       (node-text whole) (node-text form))))
        ((quoted-constant-p form))
        ((consp form)
         (check-pattern-form (car form) whole)
         (check-pattern-form (cdr form) whole))))

(defun pattern (form)
  "Compile the pattern FORM (see the file header for the syntax). A PATTERN
is returned as it is."
  (if (pattern-p form)
      form
      (progn (check-pattern-form form form)
             (%make-pattern form))))

(defun binding (identifier bindings)
  "The value IDENTIFIER is bound to in BINDINGS (an alist from MATCH-PATTERN)."
  (cdr (assoc identifier bindings)))

(defun match-form (form value bindings)
  "Match the pattern FORM against VALUE, extending BINDINGS: (values MATCHED
BINDINGS). An identifier bound already must be bound to an EQUAL value: \"Identifiers
in patterns allow components across different patterns to be equated\"."
  (cond ((wildcard-p form) (values t bindings))
        ((identifier-p form)
         (let ((entry (assoc form bindings)))
           (cond ((null entry) (values t (acons form value bindings)))
                 ((equal (cdr entry) value) (values t bindings))
                 (t (values nil bindings)))))
        ((quoted-constant-p form) (values (equal (second form) value) bindings))
        ((eval-pattern-p form)
         (let ((arguments (mapcar (lambda (id) (assoc id bindings)) (cddr form))))
           (if (every #'identity arguments)
               (values (equal value (ignore-errors (apply (second form) (mapcar #'cdr arguments))))
                       bindings)
               (graph-fail form "pattern ~A uses an identifier not bound before it"
                           (node-text form)))))
        ((consp form)
         (if (consp value)
             (multiple-value-bind (ok bindings) (match-form (car form) (car value) bindings)
               (if ok
                   (match-form (cdr form) (cdr value) bindings)
                   (values nil bindings)))
             (values nil bindings)))
        ;; "The pattern k is true only when it is applied to the value k"
        (t (values (equal form value) bindings))))

(defun match-pattern (pattern value &optional bindings)
  "Match PATTERN (a pattern or its form) against VALUE: (values MATCHED
BINDINGS), BINDINGS extended with the identifiers PATTERN binds."
  (match-form (pattern-form (pattern pattern)) value bindings))

(defun could-match-p (form value)
  "Could the pattern FORM match VALUE, were its identifiers and :eval parts free?"
  (cond ((or (wildcard-p form) (identifier-p form) (eval-pattern-p form)) t)
        ((quoted-constant-p form) (equal (second form) value))
        ((consp form) (and (consp value) (could-match-p (car form) (car value))
                           (could-match-p (cdr form) (cdr value))))
        (t (equal form value))))

;;; Predicates

(defclass edge-predicate ()
  ((description :initarg :description :initform nil :reader predicate-description)
   (patterns :initarg :patterns :initform '() :reader predicate-patterns)
   (conjuncts :initarg :conjuncts :initform '() :reader predicate-conjuncts))
  (:metaclass sb-mop:funcallable-standard-class)
  (:documentation "A restriction predicate of (SOURCE TARGET) made by PRED-IMPLIES,
PRED-EDGE, PRED-NODES or PRED-AND: callable like any function, and knowing
its patterns (which RESTRICT checks against the graph) and, for a
conjunction, its conjuncts."))

(defmethod print-object ((predicate edge-predicate) stream)
  (print-unreadable-object (predicate stream :type t)
    (format stream "~A" (predicate-description predicate))))

(defun make-edge-predicate (function description &key patterns conjuncts)
  "An EDGE-PREDICATE calling FUNCTION on (SOURCE TARGET)."
  (let ((predicate (make-instance 'edge-predicate :description description
                                                  :patterns patterns :conjuncts conjuncts)))
    (sb-mop:set-funcallable-instance-function predicate function)
    predicate))

(defun node-test (x)
  "X as a test of one node: (values FUNCTION-OF-(VALUE BINDINGS) PATTERN-OR-NIL).
A function is called on the value alone and passes the bindings on; anything
else is a pattern."
  (if (functionp x)
      (values (lambda (value bindings) (values (funcall x value) bindings)) nil)
      (let ((pattern (pattern x)))
        (values (lambda (value bindings) (match-form (pattern-form pattern) value bindings))
                pattern))))

(defun description-text (x)
  "X (a pattern, pattern form or function) as a predicate description shows it."
  (cond ((pattern-p x) (node-text (pattern-form x)))
        ((functionp x) (or (ignore-errors (predicate-description x))
                           (let ((name (nth-value 2 (function-lambda-expression x))))
                             (if name (node-text name) "a function"))))
        (t (node-text x))))

(defun pred-implies (p1 p2)
  "P1 => P2 as a restriction predicate: \"The implication operator only makes
sense when the graph contains nodes which are pairs: G \\ p1 => p2 is
equivalent to G \\ p where: p(x, y) = if p1(x) then p2(y) else true\". X is
the source of an edge, Y its target. P1 and P2 are patterns (or unary
functions); identifiers bound by P1 are equated in P2: \"the predicate
(1, x) => (x, 1) is true when applied to values ((a, b), (c, d)) where either a
is not the constant 1 or both a and d are 1 and b and c are the same value\"."
  (multiple-value-bind (test1 pattern1) (node-test p1)
    (multiple-value-bind (test2 pattern2) (node-test p2)
      (make-edge-predicate
       (lambda (source target)
         (multiple-value-bind (ok bindings) (funcall test1 source '())
           (or (not ok) (values (funcall test2 target bindings)))))
       (format nil "~A => ~A" (description-text p1) (description-text p2))
       :patterns (remove nil (list pattern1 pattern2))))))

(defun pred-edge (p1 p2)
  "The edges from a node matching P1 to a node matching P2, identifiers bound
by P1 equated in P2 (so (pred-edge '(0 . x) '(0 :eval - x)) holds from (0 . 1)
to (0 . -1)). Where P1 => P2 leaves every other edge alone, this keeps only
the edges the implication is about: G \\ (pred-edge p1 p2) is the behaviour
\"when p1, then p2\" and nothing else (see cradle.lisp)."
  (multiple-value-bind (test1 pattern1) (node-test p1)
    (multiple-value-bind (test2 pattern2) (node-test p2)
      (make-edge-predicate
       (lambda (source target)
         (multiple-value-bind (ok bindings) (funcall test1 source '())
           (and ok (values (funcall test2 target bindings)))))
       (format nil "~A then ~A" (description-text p1) (description-text p2))
       :patterns (remove nil (list pattern1 pattern2))))))

(defun pred-nodes (p &key where)
  "The edges both of whose ends match P (each matched on its own), and, given
WHERE (a function of the bindings alist, see BINDING), for which WHERE holds at
both ends: the paper's G17 = G16 \\ ((p1, _), (p2, _)) & p1 <= p2 is
  (restrict g16 (pred-nodes '((p1 . _) . (p2 . _))
                            :where (lambda (b) (<= (binding 'p1 b) (binding 'p2 b)))))"
  (multiple-value-bind (test pattern) (node-test p)
    (flet ((holds (node)
             (multiple-value-bind (ok bindings) (funcall test node '())
               (and ok (or (null where) (funcall where bindings))))))
      (make-edge-predicate (lambda (source target) (and (holds source) (holds target)))
                           (format nil "~A~:[~; & where~]" (description-text p) where)
                           :patterns (and pattern (list pattern))))))

(defun pred-and (predicate &rest predicates)
  "P1 & P2 as a restriction predicate: true when every predicate is. \"The
conjunction operator is translated as follows: G \\ p1 & p2 is equivalent to
(G \\ p1) & (G \\ p2)\" -- RESTRICT follows that translation (the nodes of the
result are those both restrictions keep; see restriction.lisp)."
  (let* ((all (cons predicate predicates))
         (conjuncts (loop for p in all
                          append (if (and (typep p 'edge-predicate) (predicate-conjuncts p))
                                     (predicate-conjuncts p)
                                     (list (as-edge-predicate 'pred-and p)))))
         (functions (coerce conjuncts 'simple-vector)))
    (make-edge-predicate
     (lambda (source target)
       (every (lambda (f) (funcall (the function f) source target)) functions))
     (format nil "~{~A~^ & ~}" (mapcar #'description-text conjuncts))
     :patterns (remove-duplicates (loop for p in conjuncts
                                        when (typep p 'edge-predicate)
                                          append (predicate-patterns p)))
     :conjuncts conjuncts)))

(defun as-edge-predicate (function p)
  "P as a predicate of (SOURCE TARGET): a function as it is, anything else a
pattern both ends must match (PRED-NODES)."
  (declare (ignore function))
  (if (functionp p) p (pred-nodes p)))
