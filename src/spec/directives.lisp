;;;; directives.lisp -- parse the directive sequences of events and macro-ops.
;;;;
;;;; Parsed directives:
;;;;   (:achieve AST FORM)   :state EXPR          (:op OP-DEF)        :op NAME
;;;;   (:label SLOT NAME)    :label L             (:time TIME-AST)    :time TIME
;;;;   (:if COND-AST DIRECTIVES FORM)             :if (EXPR DIRECTIVE...)
;;;;   (:assign VAR INDEX)   :add/:sub of a plannable literal
;;;;   (:increment VAR DELTA) :add/:sub (VAR N) of a number variable
;;;;   (:code FORM)          (:c++ TEXT)

(in-package #:player.spec)

(defparameter *directive-keys* '(:state :op :label :time :if :add :sub :code :c++)
  "Every directive keyword an event may use.")

(defvar *label-slots* nil
  "While one event or macro is parsed: hash table of label name -> slot.")

(defvar *labels-in-scope* '()
  "Names of the labels set so far on the current path through the directives.")

(defun parse-directives (directives form &key (allowed *directive-keys*))
  "Parse DIRECTIVES (a keyword/argument list from FORM) with fresh label scope."
  (let ((*label-slots* (make-hash-table :test 'equal))
        (*labels-in-scope* '()))
    (parse-directive-list directives form allowed)))

(defun parse-directive-list (directives form allowed)
  "Parse DIRECTIVES in the current label scope."
  (unless (and (proper-list-p directives) (evenp (length directives)))
    (spec-fail 'spec-syntax-error form "directives must come as :KEYWORD ARGUMENT pairs"))
  (let ((*label-slot-function* #'label-slot-in-scope))
    (loop for (key argument) on directives by #'cddr
          do (unless (member key allowed)
               (spec-fail 'spec-syntax-error form "unknown or misplaced directive ~A (allowed here: ~{~A~^ ~})"
                          (lisp-text key) (mapcar #'lisp-text allowed)))
          nconc (parse-directive key (unquote argument) form allowed))))

(defun label-slot-in-scope (name form)
  "The slot of label NAME, which must have been set earlier on this path."
  (let ((key (name-key name)))
    (unless (member key *labels-in-scope* :test #'string=)
      (spec-fail 'label-error form "label ~A is used before it is set" (lisp-text name)))
    (gethash key *label-slots*)))

(defun set-label (name form)
  "Allocate (once per event) the slot of label NAME and put it in scope."
  (let* ((name (require-name name form "a label name"))
         (key (name-key name)))
    (push key *labels-in-scope*)
    (list :label
          (or (gethash key *label-slots*)
              (setf (gethash key *label-slots*)
                    (prog1 (spec-label-count *spec*) (incf (spec-label-count *spec*)))))
          name)))

(defun parse-directive (key argument form allowed)
  "Parse one directive; returns a list of parsed directives (usually one)."
  (ecase key
    (:state (list (list :achieve (parse-expression argument) argument)))
    (:op (list (list :op (or (find-op-named argument)
                             (spec-fail 'unknown-name-error form "unknown op ~A"
                                        (lisp-text argument))))))
    (:label (list (set-label argument form)))
    (:time (list (list :time (parse-time argument))))
    (:if (list (parse-if argument form allowed)))
    (:add (parse-assignments argument t form))
    (:sub (parse-assignments argument nil form))
    (:code (list (list :code (note-code-form argument))))
    (:c++ (list (list :c++ (parse-c++ argument form))))))

(defun parse-if (argument form allowed)
  "Parse :if (EXPR DIRECTIVE...); labels set inside stay inside."
  (unless (and (proper-list-p argument) argument)
    (spec-fail 'spec-syntax-error form ":if takes (EXPR DIRECTIVE...)"))
  (let ((condition (parse-expression (first argument) :runtime t))
        (*labels-in-scope* *labels-in-scope*))
    (list :if condition (parse-directive-list (rest argument) form allowed) argument)))

(defun numeric-assignment-p (lit)
  "True when LIT is (VAR N) for a runtime number variable."
  (and (proper-list-p lit) (= (length lit) 2) (symbolp (first lit))
       (let ((var (find-variable-named (first lit))))
         (and var (eq (var-kind var) :number)))))

(defun parse-assignments (lits addp form)
  "Parse an event's :add or :sub argument: literals, or (VAR N) for a number."
  (if (numeric-assignment-p lits)
      (list (parse-increment lits addp form))
      (mapcar (lambda (lit)
                (if (numeric-assignment-p lit)
                    (parse-increment lit addp form)
                    (destructuring-bind (var . index) (parse-effect lit addp form)
                      (list :assign var index))))
              (literal-list lits form))))

(defun parse-increment (lit addp form)
  "Parse (VAR N) as an increment (ADDP) or decrement of a number variable."
  (destructuring-bind (name amount) lit
    (let ((var (find-variable-named name)))
      (unless (if (eq (var-type var) :integer) (int64-p amount) (finite-real-p amount))
        (spec-fail 'type-error-in-spec form "~A is not ~:[a finite number~;an integer from -2^63 to 2^63-1~] for ~A"
                   (bounded-lisp-text amount 40) (eq (var-type var) :integer) (lisp-text name)))
      (let ((amount (if (integerp amount) amount (to-double amount))))
        (list :increment var (if addp amount (- amount)))))))
