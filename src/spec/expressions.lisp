;;;; expressions.lisp -- parse state expressions, conditions and times into ASTs.
;;;;
;;;; State expression AST (what goals and preconditions are made of):
;;;;   (:const BOOLEAN) (:lit VARIABLE-DEF VALUE-INDEX) (:class CLASS-DEF)
;;;;   (:not E) (:and E...) (:or E...)
;;;; Runtime additions, allowed only in :IF conditions:
;;;;   (:cmp OP N N...)  with numeric ASTs  (:num X) (:value VARIABLE-DEF) (:now)
;;;;   (:label SLOT) (:arith OP N...)

(in-package #:player.spec)

(defvar *label-slot-function* nil
  "While directives are parsed: function of (NAME FORM) giving the slot of a set label.")

(defun find-variable-named (name)
  "The variable of *SPEC* whose name is NAME (a string or symbol), or NIL."
  (let ((key (if (symbolp name) (name-key name) (string-upcase name))))
    (find key (spec-variables *spec*) :key (lambda (v) (name-key (var-name v)))
                                      :test #'string=)))

(defun find-class-named (name)
  "The state class of *SPEC* named NAME, or NIL."
  (gethash (name-key name) (spec-classes *spec*)))

(defun value-name (value)
  "The text a domain VALUE is matched by in var.value literals."
  (typecase value
    (symbol (symbol-name value))
    (string value)
    (t (princ-to-string value))))

(defun value-index (var raw form)
  "The index of RAW (a value, or a value's name as a string) in VAR's domain;
a domain error naming FORM when it is not there."
  (let ((domain (var-domain var)))
    (or (if (eq (var-kind var) :boolean)
            (let ((text (cond ((stringp raw) raw) ((symbolp raw) (symbol-name raw)))))
              (cond ((and text (member text '("TRUE" "T") :test #'string-equal)) 1)
                    ((and text (member text '("FALSE" "NIL") :test #'string-equal)) 0)))
            (position-if (lambda (value)
                           (if (and (numberp value) (numberp raw))
                               (= value raw)
                               (string-equal (value-name value) (value-name raw))))
                         domain))
        (spec-fail 'domain-error form "~A is not a value of ~A (its values are ~{~A~^ ~})"
                   (if (stringp raw) (string-downcase raw) (lisp-text raw))
                   (lisp-text (var-name var))
                   (map 'list #'lisp-text domain)))))

(defun parse-expression (form &key runtime)
  "Parse state expression FORM. With RUNTIME (inside :IF) numeric comparisons
and runtime-only variables are allowed too."
  (let ((form (unquote form)))
    (multiple-value-bind (truth booleanp) (boolean-word form)
      (cond (booleanp `(:const ,truth))
            ((symbolp form) (parse-expression-symbol form runtime))
            ((not (proper-list-p form))
             (spec-fail 'spec-syntax-error form "malformed expression"))
            ((word-p (first form) "NOT")
             (unless (= (length form) 2)
               (spec-fail 'spec-syntax-error form "NOT takes exactly one expression"))
             `(:not ,(parse-expression (second form) :runtime runtime)))
            ((word-p (first form) "AND" "OR")
             (cons (if (word-p (first form) "AND") :and :or)
                   (mapcar (lambda (e) (parse-expression e :runtime runtime)) (rest form))))
            ((and (cddr form) (word-p (second form) "AND" "OR"))
             (parse-infix form runtime))
            ((and runtime (comparison-operator (first form)))
             (parse-comparison form))
            (t (spec-fail 'spec-syntax-error form
                          "malformed expression (expected a variable, var.value, a class, true, false, (not E), (and E...), (or E...) or (E and E ...)~:[~; or a comparison~])"
                          runtime))))))

(defun parse-infix (form runtime)
  "Parse the paper's infix (E and E and ...) or (E or E ...)."
  (unless (oddp (length form))
    (spec-fail 'spec-syntax-error form "infix expression must alternate expressions and AND/OR"))
  (let ((connectives (loop for c in (rest form) by #'cddr collect c)))
    (unless (every (lambda (c) (word-p c "AND" "OR")) connectives)
      (spec-fail 'spec-syntax-error form "infix expression must alternate expressions and AND/OR"))
    (unless (every (lambda (c) (string-equal (symbol-name c) (symbol-name (first connectives))))
                   connectives)
      (spec-fail 'spec-syntax-error form
                 "AND and OR are mixed without parentheses; group them, e.g. ((a and b) or c)"))
    (cons (if (word-p (first connectives) "AND") :and :or)
          (loop for e in form by #'cddr collect (parse-expression e :runtime runtime)))))

(defun parse-expression-symbol (symbol runtime)
  "Parse a lone symbol: a boolean variable, var.value, or a class name."
  (let ((var (find-variable-named symbol)))
    (cond (var
           (case (var-kind var)
             (:boolean `(:lit ,var 1))
             (:enumerated
              (spec-fail 'spec-syntax-error symbol
                         "~A is not boolean: write ~A.VALUE" (lisp-text symbol) (lisp-text symbol)))
             (t (spec-fail 'goal-error symbol
                           "runtime-only variable ~A cannot be a state expression~:[; compare it instead, e.g. (> ~A 0)~;~]"
                           (lisp-text symbol) (not runtime) (lisp-text symbol)))))
          ((find-class-named symbol) `(:class ,(find-class-named symbol)))
          (t (or (parse-dotted-literal symbol runtime)
                 (spec-fail 'unknown-name-error symbol "unknown variable or state class ~A"
                            (lisp-text symbol)))))))

(defun parse-dotted-literal (symbol runtime)
  "Parse var.value, or NIL when no prefix of SYMBOL names a variable."
  (loop for (var-name . value-name) in (split-dotted symbol)
        for var = (find-variable-named var-name)
        when var
          do (return
               (if (plannable-p var)
                   `(:lit ,var ,(value-index var value-name symbol))
                   (let ((number (ignore-errors
                                  (let ((*read-eval* nil))
                                    (read-from-string value-name)))))
                     (unless runtime
                       (spec-fail 'goal-error symbol
                                  "runtime-only variable ~A cannot appear in a goal or precondition"
                                  (lisp-text (var-name var))))
                     (unless (finite-real-p number)
                       (spec-fail 'type-error-in-spec symbol "~A is a number variable; ~A is not a number"
                                  (lisp-text (var-name var)) (string-downcase value-name)))
                     `(:cmp = (:value ,var) (:num ,(to-double number))))))))

(defun comparison-operator (thing)
  "The comparison keyword THING names, or NIL."
  (loop for (name . op) in '(("<" . <) ("<=" . <=) (">" . >) (">=" . >=) ("=" . =) ("/=" . /=))
        when (word-p thing name) return op))

(defun parse-comparison (form)
  "Parse (OP N N ...) in an :IF condition."
  (when (< (length form) 3)
    (spec-fail 'spec-syntax-error form "a comparison needs at least two operands"))
  `(:cmp ,(comparison-operator (first form)) ,@(mapcar #'parse-number-expression (rest form))))

(defun arithmetic-operator (thing)
  "The arithmetic operator THING names, or NIL."
  (loop for (name . op) in '(("+" . +) ("-" . -) ("*" . *))
        when (word-p thing name) return op))

(defun parse-number-expression (form)
  "Parse a numeric expression of :IF or :TIME."
  (let ((form (unquote form)))
    (cond ((realp form) `(:num ,(to-double (check-spec-number form form "a number in an expression"))))
          ((and (symbolp form) form (find-variable-named form))
           (let ((var (find-variable-named form)))
             (unless (or (member (var-kind var) '(:number :time))
                         (and (eq (var-kind var) :enumerated) (every #'realp (var-domain var))))
               (spec-fail 'type-error-in-spec form "~A is not a number or time variable"
                          (lisp-text form)))
             `(:value ,var)))
          ((and (consp form) (word-p (first form) "NOW"))
           (unless (null (rest form))
             (spec-fail 'spec-syntax-error form "(now) takes no arguments"))
           '(:now))
          ((and (consp form) (word-p (first form) "LABEL"))
           (unless (and (proper-list-p form) (= (length form) 2) (symbolp (second form)))
             (spec-fail 'spec-syntax-error form "write (label NAME)"))
           (unless *label-slot-function*
             (spec-fail 'label-error form "labels exist only inside events and macro-ops"))
           `(:label ,(funcall *label-slot-function* (second form) form)))
          ((and (proper-list-p form) (consp form) (arithmetic-operator (first form)) (rest form))
           `(:arith ,(arithmetic-operator (first form))
                    ,@(mapcar #'parse-number-expression (rest form))))
          (t (spec-fail 'spec-syntax-error form
                        "malformed number (expected a number, a number or time variable, (now), (label L) or + - * of them)")))))

(defun parse-time (form)
  "Parse the argument of :TIME: a bare number is seconds after the start of the
event (or macro); anything else is an absolute time expression."
  (let ((form (unquote form)))
    (if (realp form)
        `(:relative ,(spec-seconds form form ":time"))
        `(:absolute ,(parse-number-expression form)))))

(defun state-only-p (ast)
  "True when parsed expression AST mentions no numeric comparison, so the
plannable state alone decides it."
  (case (first ast)
    (:cmp nil)
    ((:not :and :or) (every #'state-only-p (rest ast)))
    (t t)))
