;;;; spec-options.lisp -- the (:KEY VALUE) options at the head of a DEFSPEC:
;;;; which there are, what each may say, and how they are read into the spec.
;;;; (:state-space, :start-states and :unplanned-states are described in
;;;; state-space.lisp; (:graph EXPR) in src/compose/graph-option.lisp.)

(in-package #:player.spec)

(defparameter *spec-option-keys* '(:max-depth :optimize :macros :scripts :body :when-busy
                                   :state-space :unplanned-states :planning-budget)
  "Options a DEFSPEC may give as (:KEY VALUE) lists before its forms.")

(defparameter *expanding-option-keys* '(:graph)
  "Options written (:KEY VALUE [:OPTION VALUE...]) that stand for spec forms
(see EXPAND-SPEC-OPTION).")

(defgeneric expand-spec-option (key option)
  (:documentation "The spec forms the defspec option OPTION, (KEY ...), stands
for, put before the forms written after it, and as a second value the
:max-depth they need when the spec gives none (or NIL).  src/compose/ defines
(:graph EXPR ...).")
  (:method (key option)
    (declare (ignore key))
    (spec-fail 'spec-syntax-error option "the option ~A is not available" (lisp-text (first option)))))

(defparameter *optimize-criteria* '(:steps :duration)
  "What (:optimize CRITERION) may ask the planner to minimise: the number of
operators (the paper's, the default), or their total :duration.")

(defparameter *macro-semantics* '(:declared :exact)
  "What (:macros SEMANTICS) may say the state after a macro-op is: its start
state with the declared effects (the paper's, the default), or, :EXACT, the
state its :seq produced with the declared effects on top -- checked, when the
spec is planned, to be the state the planner assumed (macro-exactness.lisp).")

(defparameter *planning-budget-ceiling* (expt 10 12)
  "The largest (:planning-budget N): a spec that needs more says :unlimited.")

(defun parse-planning-budget (option)
  "The value of OPTION, (:planning-budget N|:unlimited): a positive integer up
to *PLANNING-BUDGET-CEILING*, or :UNLIMITED."
  (let ((value (unquote (second option))))
    (cond ((and (symbolp value) (word-p value "UNLIMITED")) :unlimited)
          ((typep value `(integer 1 ,*planning-budget-ceiling*)) value)
          (t (spec-fail 'type-error-in-spec option ":planning-budget must be a positive integer up to ~:D, or :unlimited"
                        *planning-budget-ceiling*)))))

(defun parse-spec-header (body)
  "Read the docstring and (:KEY VALUE) options at the head of BODY; return the
rest, after the forms options such as (:graph EXPR) stand for."
  (let ((expanded '()) (depth-given nil) (needed-depth nil))
    (when (stringp (first body))
      (setf (spec-documentation *spec*) (pop body)))
    (loop while (and (consp (first body)) (keywordp (first (first body))))
          do (let ((option (pop body)))
               (if (and (proper-list-p option) (>= (length option) 2)
                        (member (first option) *expanding-option-keys*))
                   (multiple-value-bind (forms depth) (expand-spec-option (first option) option)
                     (setf expanded (append expanded forms)
                           needed-depth (and depth (max depth (or needed-depth 0)))))
                   (progn (when (eq (first option) :max-depth) (setf depth-given t))
                          (parse-spec-option option)))))
    (when (and needed-depth (not depth-given))
      (setf (spec-max-depth *spec*) (min 1000 needed-depth)))
    (append expanded body)))

(defun parse-spec-option (option)
  "Record the (:KEY VALUE) OPTION of a defspec's head in *SPEC*."
  (when (eq (first option) :start-states)
    (return-from parse-spec-option (record-start-states-option option)))
  (unless (and (proper-list-p option) (= (length option) 2)
               (member (first option) *spec-option-keys*))
    (spec-fail 'spec-syntax-error option "unknown or malformed spec option (allowed: ~{(~A VALUE)~^ ~}, (:graph EXPR ...), (:start-states EXPR ...))"
               (mapcar #'lisp-text *spec-option-keys*)))
  (case (first option)
    (:max-depth
     (let ((depth (second option)))
       (unless (typep depth '(integer 0 1000))
         (spec-fail 'type-error-in-spec option ":max-depth must be an integer from 0 to 1000"))
       (setf (spec-max-depth *spec*) depth)))
    (:optimize
     (setf (getf (spec-options *spec*) :optimize) (parse-optimize-criterion option)))
    (:when-busy
     (setf (getf (spec-options *spec*) :when-busy) (parse-when-busy (second option) option)))
    (:macros
     (setf (getf (spec-options *spec*) :macros) (parse-keyword-choice option *macro-semantics*)))
    (:state-space
     (setf (getf (spec-options *spec*) :state-space) (parse-keyword-choice option *state-space-regimes*)))
    (:planning-budget
     (setf (getf (spec-options *spec*) :planning-budget) (parse-planning-budget option)))
    (:unplanned-states
     (setf (getf (spec-options *spec*) :unplanned-states)
           (parse-keyword-choice option *unplanned-state-policies*)))
    (t (setf (getf (spec-options *spec*) (first option)) (second option)))))

(defun parse-optimize-criterion (option)
  "The criterion keyword of OPTION, (:optimize CRITERION); CRITERION is a name
of *OPTIMIZE-CRITERIA*, as a keyword or not."
  (let ((criterion (unquote (second option))))
    (or (find-if (lambda (known) (word-p criterion (symbol-name known))) *optimize-criteria*)
        (spec-fail 'spec-syntax-error option "unknown :optimize criterion ~A (allowed: ~{~A~^ or ~})"
                   (bounded-lisp-text criterion 40) (mapcar #'lisp-text *optimize-criteria*)))))

(defun parse-keyword-choice (option choices)
  "The keyword among CHOICES that OPTION's value, (KEY VALUE), names (as a
keyword or a plain symbol); a SPEC-SYNTAX-ERROR naming OPTION otherwise."
  (let ((value (unquote (second option))))
    (or (and (symbolp value)
             (find-if (lambda (known) (word-p value (symbol-name known))) choices))
        (spec-fail 'spec-syntax-error option "unknown ~A value ~A (allowed: ~{~A~^, ~})"
                   (lisp-text (first option)) (bounded-lisp-text value 40)
                   (mapcar #'lisp-text choices)))))
