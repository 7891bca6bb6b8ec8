;;;; edge-tests.lisp -- statements about a move, written as data: the tests of
;;;; a graph expression's (edge P1 P2 TEST) predicate.
;;;;
;;;; The paper restricts behaviours by statements such as "p1 describes sphere
;;;; moves which travel a constant distance". A pattern says which moves a
;;;; statement is about and names their parts; TEST says what must hold of
;;;; them, over the identifiers the patterns bind:
;;;;   (and T...) (or T...) (not T) (implies T T)
;;;;   (= E E...) (/= E E) (< E E...) (<= E E...) (> E E...) (>= E E...) (equal E E)
;;;;   E: a number, an identifier, (+ E...) (- E...) (* E...) (mod E E) (abs E)
;;;; TEST is interpreted, never evaluated as Lisp, so a spec file stays data.
;;;; Arithmetic on a value that is not a number makes the test false.

(in-package #:player.compose)

(defparameter *test-connectives* '("AND" "OR" "NOT" "IMPLIES")
  "The logical words of an edge test.")

(defparameter *test-relations*
  '(("=" . =) ("/=" . /=) ("<" . <) ("<=" . <=) (">" . >) (">=" . >=) ("EQUAL" . equal))
  "The relations of an edge test, by name.")

(defparameter *test-functions* '(("+" . +) ("-" . -) ("*" . *) ("MOD" . mod) ("ABS" . abs))
  "The arithmetic of an edge test, by name.")

(defun pattern-identifiers (form)
  "The identifiers the pattern FORM binds."
  (cond ((identifier-p form) (list form))
        ((or (eval-pattern-p form) (quoted-constant-p form)) '())
        ((consp form) (union (pattern-identifiers (car form)) (pattern-identifiers (cdr form))))
        (t '())))

(defun test-operator (form table)
  "The function FORM's operator names in TABLE (an alist name -> function), or NIL."
  (and (consp form) (symbolp (first form))
       (cdr (assoc (symbol-name (first form)) table :test #'string=))))

(defun compile-test-value (form identifiers whole)
  "A function of bindings computing the value expression FORM of the test WHOLE."
  (cond ((realp form) (constantly form))
        ((and (symbolp form) (member form identifiers))
         (lambda (bindings) (binding form bindings)))
        ((test-operator form *test-functions*)
         (let ((function (test-operator form *test-functions*))
               (arguments (mapcar (lambda (f) (compile-test-value f identifiers whole)) (rest form))))
           (lambda (bindings)
             (let ((values (mapcar (lambda (a) (funcall a bindings)) arguments)))
               (and (every #'realp values)
                    (ignore-errors (apply function values)))))))
        (t (graph-expression-fail whole "in the test ~A, ~A is not a number, an identifier the patterns bind (~{~(~A~)~^ ~}) or (+|-|*|mod|abs E...)"
                                  (bounded-lisp-text whole 80) (bounded-lisp-text form 40) identifiers))))

(defun compile-edge-test (form identifiers &optional (whole form))
  "A function of bindings: is the test FORM true? IDENTIFIERS are those the
patterns bind; anything else named is a GRAPH-EXPRESSION-ERROR about WHOLE."
  (let ((word (and (consp form) (symbolp (first form)) (proper-list-p form)
                   (find (symbol-name (first form)) *test-connectives* :test #'string=))))
    (flet ((sub (f) (compile-edge-test f identifiers whole)))
      (cond ((member word '("AND" "OR") :test #'equal)
             (let ((parts (mapcar #'sub (rest form))))
               (if (equal word "AND")
                   (lambda (b) (every (lambda (p) (funcall p b)) parts))
                   (lambda (b) (some (lambda (p) (funcall p b)) parts)))))
            ((and (equal word "NOT") (= 2 (length form)))
             (let ((part (sub (second form)))) (lambda (b) (not (funcall part b)))))
            ((and (equal word "IMPLIES") (= 3 (length form)))
             (let ((if (sub (second form))) (then (sub (third form))))
               (lambda (b) (or (not (funcall if b)) (funcall then b)))))
            ((and (test-operator form *test-relations*) (proper-list-p form) (>= (length form) 3))
             (let ((relation (test-operator form *test-relations*))
                   (arguments (mapcar (lambda (f) (compile-test-value f identifiers whole)) (rest form))))
               (lambda (b)
                 (let ((values (mapcar (lambda (a) (funcall a b)) arguments)))
                   (if (eq relation 'equal)
                       (every (lambda (v) (equal v (first values))) (rest values))
                       (and (every #'realp values) (apply relation values)))))))
            (t (graph-expression-fail whole "~A is not a test: write (and|or|not|implies ...) or a relation (=|/=|<|<=|>|>=|equal E E...)"
                                      (bounded-lisp-text form 60)))))))

(defun pred-where (p1 p2 test &key description)
  "The moves from a node matching the pattern P1 to one matching P2
(identifiers bound by P1 equated in P2) for which TEST, a function of the
bindings, holds."
  (let ((pattern1 (pattern p1)) (pattern2 (pattern p2)))
    (make-edge-predicate
     (lambda (source target)
       (multiple-value-bind (ok bindings) (match-pattern pattern1 source)
         (and ok (multiple-value-bind (ok bindings) (match-pattern pattern2 target bindings)
                   (and ok (funcall test bindings) t)))))
     (or description (format nil "~A to ~A where ..." (node-text p1) (node-text p2)))
     :patterns (list pattern1 pattern2))))

(defun pred-not (predicate)
  "The moves PREDICATE (a function of SOURCE and TARGET) does not hold of:
the paper's \"opposite\" of a statement."
  (make-edge-predicate (lambda (source target) (not (funcall predicate source target)))
                       (format nil "not ~A" (description-text predicate))))

(defun pred-or (predicate &rest predicates)
  "The moves any of the predicates holds of."
  (let ((all (cons predicate predicates)))
    (make-edge-predicate (lambda (source target) (some (lambda (p) (funcall p source target)) all))
                         (format nil "~{~A~^ or ~}" (mapcar #'description-text all)))))
