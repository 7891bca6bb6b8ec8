;;;; random-events.lisp -- random events for the backend comparison: specs
;;;; from RANDOM-SPEC extended with integer, float and time variables, :if with
;;;; comparisons, :add/:sub on numbers, labels and times, and autoscripts.
;;;; Seeded, so every spec and run reproduces.

(in-package #:player-tests)

(defparameter *compare-gear* t
  "Whether random :if comparisons may read the plannable integer variable GEAR.
(It was off while g++ rejected an out-of-bounds value index there; that is
fixed, and C++-COMPARISON-ON-AN-INTEGER-ENUMERATION-COMPILES guards it.)")

(defvar *c++-statistics* nil
  "A plist describing the last random comparison: specs, runs, events, seconds...")

(defvar *extra-labels* '() "Labels in scope while an event's directives are generated.")
(defvar *extra-label-count* 0 "Labels made so far in the event being generated.")

(defstruct (c++-extras (:conc-name extras-))
  "What C++-EVENT-GENERATOR adds to a random spec, as spec forms."
  (variable-forms '()) (event-forms '()) (autoscript-forms '())
  ;; Whether the plannable integer variable GEAR was declared.
  (gear nil))

(defun extra-symbol (name) (rs-symbol "~A" name))

(defun random-number-form (prng extras depth)
  "A random numeric expression for :if: numbers, number and time variables,
(now), labels in scope, and + - * of them."
  (let ((choice (rs-below prng (if (plusp depth) 10 8))))
    (case choice
      (0 (extra-symbol "counter"))
      (1 (extra-symbol "level"))
      ((2 3) (rs-pick prng '(0 1 2 3 -1 0.5 1.5 2.25 10)))
      (4 '(now))
      (5 (extra-symbol "heard"))
      (6 (if *extra-labels*
             (list (extra-symbol "label") (rs-pick prng *extra-labels*))
             (extra-symbol "counter")))
      (7 (if (and *compare-gear* (extras-gear extras)) (extra-symbol "gear") (extra-symbol "level")))
      (t (list (rs-pick prng '(+ - *))
               (random-number-form prng extras (1- depth))
               (random-number-form prng extras (1- depth)))))))

(defun random-comparison (prng extras)
  "A random numeric comparison, sometimes a chain of three."
  (list* (rs-pick prng '(< <= > >= = /=))
         (random-number-form prng extras 1)
         (random-number-form prng extras 1)
         (when (rs-chance prng 0.15) (list (random-number-form prng extras 0)))))

(defun random-if-condition (prng model extras)
  "A random :if condition: a state expression, a comparison, or both mixed."
  (let ((choice (rs-below prng 20)))
    (cond ((< choice 6) (render-expression model (random-expression prng model)))
          ((< choice 15) (random-comparison prng extras))
          ((< choice 17) (list (extra-symbol "not") (random-comparison prng extras)))
          (t (list (extra-symbol (rs-pick prng '("and" "or")))
                   (random-comparison prng extras)
                   (render-expression model (random-condition prng model)))))))

(defun random-time-argument (prng)
  "A random :time argument: seconds after the event's start, or an absolute time."
  (case (rs-below prng 6)
    ((0 1) (rs-pick prng '(0 0.5 1.25 2 3)))
    (2 (if *extra-labels*
           (list '+ (list (extra-symbol "label") (rs-pick prng *extra-labels*)) 1.5)
           1.5))
    (3 (list '+ '(now) (rs-pick prng '(0.25 1 2))))
    (4 (list '- '(now) 0.5))
    (t (list '+ (extra-symbol "heard") 2))))

(defun random-plannable-literal (prng model extras)
  "A random :add or :sub directive on a plannable variable, as (KEY ARGUMENT)."
  (if (and (extras-gear extras) (rs-chance prng 0.15))
      (list :add (rs-symbol "gear.~D" (rs-between prng 1 3)))
      (let* ((i (rs-below prng (model-variable-count model)))
             (var (svref (model-variables model) i))
             (k (rs-below prng (length (mvar-domain var)))))
        (if (and (eq (mvar-kind var) :boolean) (= k 0))
            (list :sub (render-literal model i k))
            (list :add (render-literal model i k))))))

(defun random-directives (prng model extras depth count)
  "COUNT random directives (a flat KEY ARGUMENT list) at :if nesting DEPTH."
  (loop repeat count
        append (let ((choice (rs-below prng 100)))
                 (cond ((< choice 12) (list :state (render-expression model (random-condition prng model))))
                       ((< choice 30) (list :op (mop-name (rs-pick prng (model-ops model)))))
                       ((< choice 40) (random-plannable-literal prng model extras))
                       ((< choice 50) (list (rs-pick prng '(:add :sub))
                                            (list (extra-symbol "counter") (rs-between prng 1 3))))
                       ((< choice 57) (list (rs-pick prng '(:add :sub))
                                            (list (extra-symbol "level") (rs-pick prng '(0.25 0.5 1.5 0.1d0)))))
                       ((< choice 66) (let ((label (rs-symbol "l~D" (incf *extra-label-count*))))
                                        (push label *extra-labels*)
                                        (list :label label)))
                       ((< choice 77) (list :time (random-time-argument prng)))
                       ((< depth 2)
                        (list :if (let ((*extra-labels* *extra-labels*))
                                    (cons (random-if-condition prng model extras)
                                          (random-directives prng model extras (1+ depth)
                                                             (rs-between prng 1 3))))))
                       (t (list :op (mop-name (rs-pick prng (model-ops model)))))))))

(defun random-autoscript-forms (prng model extras)
  "Zero to three autoscripts on plannable variables, sometimes one on COUNTER or LEVEL."
  (let* ((choices (append (loop for var across (model-variables model)
                                append (loop for value across (mvar-domain var)
                                             collect (list (mvar-name var)
                                                           (if (eq (mvar-kind var) :boolean)
                                                               (extra-symbol (if value "true" "false"))
                                                               value))))
                          (when (extras-gear extras)
                            (loop for k from 1 to 3 collect (list (extra-symbol "gear") k)))))
         (picked (rs-sample prng choices (rs-between prng 0 3)))
         (procs 0))
    (flet ((procs () (loop repeat (rs-between prng 1 2) collect (rs-symbol "p~D" (incf procs)))))
      (append (loop for (var value) in picked
                    collect (list (extra-symbol "autoscript") var value (procs)))
              (when (rs-chance prng 0.4)
                (list (list (extra-symbol "autoscript") (extra-symbol "counter") (rs-between prng 0 4) (procs))))
              (when (rs-chance prng 0.2)
                (list (list (extra-symbol "autoscript") (extra-symbol "level") (rs-pick prng '(0 0.5 1.5)) (procs))))))))

(defun c++-event-generator (extras)
  "An :EVENT-GENERATOR for RANDOM-SPEC that fills EXTRAS (runtime variables,
events with every kind of directive, autoscripts) and adds no model events:
the events it makes use syntax the model cannot express."
  (lambda (prng model)
    (setf (extras-gear extras) (rs-chance prng 0.35))
    (let* ((names (loop for i below (rs-between prng 3 5) collect (rs-symbol "e~D" i)))
           (all-names (append (mapcar #'mevent-name (model-events model)) names)))
      (setf (extras-variable-forms extras)
            (append (list (list (extra-symbol "state-variable") (extra-symbol "counter")
                                (extra-symbol "integer") (rs-between prng 0 3))
                          (list (extra-symbol "state-variable") (extra-symbol "level")
                                (extra-symbol "float") (rs-pick prng '(0 0.5 1.25 2.5)))
                          (list (extra-symbol "time-variable") (extra-symbol "heard")
                                (rs-sample prng all-names (rs-between prng 1 3))))
                    (when (extras-gear extras)
                      (list (list (extra-symbol "state-variable") (extra-symbol "gear")
                                  (extra-symbol "integer") (rs-between prng 1 3) '(1 2 3)))))
            (extras-event-forms extras)
            (loop for name in names
                  collect (let ((*extra-labels* '()) (*extra-label-count* 0))
                            (list* (extra-symbol "event") name
                                   (random-directives prng model extras 0 (rs-between prng 1 6)))))
            (extras-autoscript-forms extras) (random-autoscript-forms prng model extras)))
    '()))

(defun c++-random-spec (seed &rest random-spec-options)
  "The spec forms for SEED: RANDOM-SPEC's (given RANDOM-SPEC-OPTIONS, such as
:ENUM-VALUES), plus runtime and time variables after the plannable ones, the
generated events and autoscripts. (VALUES FORMS MODEL EXTRAS)."
  (let ((extras (make-c++-extras)))
    (multiple-value-bind (forms model)
        (apply #'random-spec seed :name (rs-symbol "c++-random-~D" seed)
                                  :event-generator (c++-event-generator extras)
                                  random-spec-options)
      (let ((split (1+ (model-variable-count model))))
        (values (append (subseq forms 0 split)
                        (extras-variable-forms extras)
                        (nthcdr split forms)
                        (extras-event-forms extras)
                        (extras-autoscript-forms extras))
                model extras)))))

(defun random-initial-state (prng model extras)
  "A random initial-state alist: every plannable variable, and some runtime ones."
  (append (loop for var across (model-variables model)
                collect (cons (mvar-name var) (rs-pick prng (mvar-domain var))))
          (list (cons (extra-symbol "counter") (rs-between prng -1 4)))
          (when (rs-chance prng 0.5)
            (list (cons (extra-symbol "level") (rs-pick prng '(-1 0 0.75 2.5 1.1d0)))))
          (when (rs-chance prng 0.4)
            (list (cons (extra-symbol "heard") (rs-pick prng '(0 0.5 3)))))
          (when (and (extras-gear extras) (rs-chance prng 0.6))
            (list (cons (extra-symbol "gear") (rs-between prng 1 3))))))
