;;;; random-specs.lisp -- a seeded generator of random Player specs, for property tests.
;;;;
;;;; RANDOM-SPEC returns two things for a seed: the spec forms (what DEFINE-SPEC
;;;; takes) and a MODEL, a plain-data description of the same spec that does not
;;;; depend on Player at all: variables with their domains, operators as data
;;;; (precondition ASTs and effect lists), events as lists of directives. The
;;;; reference planner (reference-bfs.lisp) reads only the model, so a property
;;;; test can compare what Player does with what the model says it should do.
;;;;
;;;; Model expression ASTs (never Player's own ASTs):
;;;;   (:const BOOLEAN)          true / false
;;;;   (:is VAR-INDEX VALUE-INDEX)  variable VAR-INDEX holds its VALUE-INDEXth value
;;;;                             (booleans: value 0 is false, 1 is true)
;;;;   (:not E) (:and E...) (:or E...)
;;;; A model state is a simple-vector of value indices, one per variable, in
;;;; declaration order.
;;;;
;;;; Everything random comes from RS-PRNG, a 64-bit LCG seeded explicitly, so a
;;;; seed names the same spec on every Lisp and every run.
;;;;
;;;; Reuse: pass RANDOM-SPEC an :EVENT-GENERATOR, a function of (PRNG MODEL)
;;;; returning more MODEL-EVENTs (drawn from the same seeded PRNG, so they are
;;;; deterministic too). Event directives are data: (:state AST), (:op NAME),
;;;; (:assign VAR-INDEX VALUE-INDEX) for :add/:sub, (:if AST DIRECTIVE...), and
;;;; anything else as (KEY ARGUMENT) verbatim, e.g. (:label l1) or (:time 2).
;;;; MODEL-SPEC-FORMS renders a (possibly edited) model again; RANDOM-EXPRESSION,
;;;; RANDOM-CONDITION and RANDOM-EFFECTS make random pieces, RENDER-EXPRESSION
;;;; and RENDER-LITERAL turn model ASTs and effects into spec syntax.

(in-package #:player-tests)

;;; A tiny deterministic PRNG

(defstruct (rs-prng (:constructor %make-rs-prng (state)))
  "A 64-bit linear congruential generator (Knuth's MMIX constants)."
  (state 0 :type (unsigned-byte 64)))

(defparameter *rs-lcg-multiplier* 6364136223846793005)
(defparameter *rs-lcg-increment* 1442695040888963407)

(defun rs-next (prng)
  "The next 31-bit output of PRNG (the high bits of the LCG state)."
  (let ((state (ldb (byte 64 0) (+ (* (rs-prng-state prng) *rs-lcg-multiplier*)
                                   *rs-lcg-increment*))))
    (setf (rs-prng-state prng) state)
    (ldb (byte 31 33) state)))

(defun make-rs-prng (seed)
  "A generator whose whole output is determined by the integer SEED."
  (let ((prng (%make-rs-prng (ldb (byte 64 0) (logxor seed #x9E3779B97F4A7C15)))))
    (loop repeat 4 do (rs-next prng))      ; mix small seeds
    prng))

(defun rs-below (prng n)
  "A pseudo-random integer in [0, N)."
  (assert (plusp n))
  (mod (rs-next prng) n))

(defun rs-between (prng low high)
  "A pseudo-random integer in [LOW, HIGH]."
  (+ low (rs-below prng (1+ (- high low)))))

(defun rs-chance (prng probability)
  "True with PROBABILITY (a real in [0, 1])."
  (< (rs-below prng 1000000) (round (* probability 1000000))))

(defun rs-pick (prng sequence)
  "A pseudo-random element of the non-empty SEQUENCE."
  (elt sequence (rs-below prng (length sequence))))

(defun rs-shuffle (prng list)
  "A fresh list holding LIST's elements in a pseudo-random order."
  (let ((vector (coerce list 'simple-vector)))
    (loop for i from (1- (length vector)) downto 1
          do (rotatef (svref vector i) (svref vector (rs-below prng (1+ i)))))
    (coerce vector 'list)))

(defun rs-sample (prng list k)
  "K distinct elements of LIST (fewer if LIST is shorter), in a pseudo-random order."
  (subseq (rs-shuffle prng list) 0 (min k (length list))))

;;; The model

(defstruct (model-variable (:conc-name mvar-))
  "A plannable state variable of a model."
  (name nil :type symbol)
  ;; :BOOLEAN or :ENUMERATED
  (kind :boolean)
  ;; The values, by value index: #(NIL T) for a boolean, symbols otherwise.
  (domain #(nil t) :type simple-vector)
  ;; Value index of the declared initial value.
  (initial 0))

(defstruct (model-op (:conc-name mop-))
  "An op (KIND :OP) or macro-op (KIND :MACRO) of a model."
  (name nil :type symbol)
  (kind :op)
  ;; Precondition AST, or NIL for none (a macro always has one).
  (precond nil)
  ;; ((VAR-INDEX . VALUE-INDEX) ...), at most one per variable.
  (effects '())
  (must-ask nil)
  ;; For a macro: the names of the ops its :seq runs, in order.
  (seq '()))

(defstruct (model-event (:conc-name mevent-))
  "An event of a model: a name and directives (see RENDER-DIRECTIVE): (:state
AST), (:op NAME), (:assign VAR-INDEX VALUE-INDEX), (:if AST DIRECTIVE...), or
any other (KEY ARGUMENT), rendered verbatim."
  (name nil :type symbol)
  (directives '()))

(defstruct (spec-model (:conc-name model-))
  "The plain-data description of a generated spec."
  (name nil :type symbol)
  (seed 0)
  (max-depth 30)
  ;; MODEL-VARIABLEs in declaration order.
  (variables #() :type simple-vector)
  ;; MODEL-OPs in declaration order (ops and macros interleaved).
  (ops '())
  ;; MODEL-EVENTs in declaration order.
  (events '()))

(defun model-find-op (model name)
  "The MODEL-OP of MODEL named NAME (a symbol), or NIL."
  (find name (model-ops model) :key #'mop-name))

(defun model-variable-count (model)
  "How many variables MODEL has."
  (length (model-variables model)))

;;; Rendering the model as spec forms

(defun rs-symbol (format-control &rest arguments)
  "A symbol in PLAYER-USER named by FORMAT-CONTROL and ARGUMENTS (upcased)."
  (intern (string-upcase (apply #'format nil format-control arguments)) '#:player-user))

(defun render-literal (model var-index value-index)
  "The literal symbol meaning 'variable VAR-INDEX holds value VALUE-INDEX', for
:add, or for a boolean set to false, the bare variable (for :sub)."
  (let ((var (svref (model-variables model) var-index)))
    (if (eq (mvar-kind var) :boolean)
        (mvar-name var)
        (rs-symbol "~A.~A" (mvar-name var) (svref (mvar-domain var) value-index)))))

(defun render-expression (model ast)
  "Model expression AST as a spec state expression."
  (ecase (first ast)
    (:const (if (second ast) (rs-symbol "true") (rs-symbol "false")))
    (:is (destructuring-bind (i k) (rest ast)
           (let ((var (svref (model-variables model) i)))
             (cond ((eq (mvar-kind var) :enumerated) (render-literal model i k))
                   ((= k 1) (mvar-name var))
                   (t (list (rs-symbol "not") (mvar-name var)))))))
    (:not (list (rs-symbol "not") (render-expression model (second ast))))
    (:and (cons (rs-symbol "and") (mapcar (lambda (e) (render-expression model e)) (rest ast))))
    (:or (cons (rs-symbol "or") (mapcar (lambda (e) (render-expression model e)) (rest ast))))))

(defun render-variable (var)
  "The state-variable form of model variable VAR."
  (if (eq (mvar-kind var) :boolean)
      (list (rs-symbol "state-variable") (mvar-name var) (rs-symbol "boolean")
            (rs-symbol (if (= 1 (mvar-initial var)) "true" "false")))
      (list (rs-symbol "state-variable") (mvar-name var) (rs-symbol "string")
            (svref (mvar-domain var) (mvar-initial var))
            (coerce (mvar-domain var) 'list))))

(defun render-literal-list (literals)
  "LITERALS as the argument of :add or :sub: a lone symbol when there is one."
  (if (and literals (null (rest literals)) (symbolp (first literals)))
      (first literals)
      literals))

(defun render-effect-options (model effects)
  "The :add and :sub options of EFFECTS, as a plist (empty parts left out)."
  (let ((adds '()) (subs '()))
    (loop for (i . k) in effects
          for var = (svref (model-variables model) i)
          do (if (and (eq (mvar-kind var) :boolean) (= k 0))
                 (push (render-literal model i k) subs)
                 (push (render-literal model i k) adds)))
    (append (when adds (list :add (render-literal-list (nreverse adds))))
            (when subs (list :sub (render-literal-list (nreverse subs)))))))

(defun render-op (model op)
  "The op or macro-op form of model op OP."
  (if (eq (mop-kind op) :macro)
      (list* (rs-symbol "macro-op") (mop-name op)
             :precond (render-expression model (or (mop-precond op) '(:const t)))
             (append (render-effect-options model (mop-effects op))
                     (list :seq (loop for name in (mop-seq op) append (list :op name)))))
      (list* (rs-symbol "op") (mop-name op)
             (append (when (mop-precond op)
                       (list :precond (render-expression model (mop-precond op))))
                     (render-effect-options model (mop-effects op))
                     (when (mop-must-ask op) (list :must-ask (rs-symbol "true")))))))

(defun render-directive (model directive)
  "One model directive as the KEY ARGUMENT pair of an event form:
  (:state AST)          -> :state EXPR
  (:op NAME)            -> :op NAME
  (:assign I K)         -> :add LITERAL, or :sub V for a boolean set to false
  (:if AST DIRECTIVE...) -> :if (EXPR KEY ARGUMENT ...)
  (KEY ARGUMENT)        -> KEY ARGUMENT verbatim (:label, :time, :code, ...)."
  (case (first directive)
    (:state (list :state (render-expression model (second directive))))
    (:assign (destructuring-bind (i k) (rest directive)
               (if (and (eq (mvar-kind (svref (model-variables model) i)) :boolean) (= k 0))
                   (list :sub (render-literal model i k))
                   (list :add (render-literal model i k)))))
    (:if (list :if (cons (render-expression model (second directive))
                         (loop for inner in (cddr directive)
                               append (render-directive model inner)))))
    (t (destructuring-bind (key argument) directive
         (list key argument)))))

(defun render-event (model event)
  "The event form of model event EVENT."
  (list* (rs-symbol "event") (mevent-name event)
         (loop for directive in (mevent-directives event)
               append (render-directive model directive))))

(defun model-spec-forms (model)
  "The DEFINE-SPEC body of MODEL: (:max-depth N), variables, ops, events."
  (append (list (list :max-depth (model-max-depth model)))
          (map 'list #'render-variable (model-variables model))
          (mapcar (lambda (op) (render-op model op)) (model-ops model))
          (mapcar (lambda (event) (render-event model event)) (model-events model))))

(defun model-goal-form (model event)
  "The goal form Player reports when EVENT (a one-directive model event) fails:
the :state expression as rendered, or the requested op's :precond as rendered."
  (destructuring-bind (key argument) (first (mevent-directives event))
    (ecase key
      (:state (render-expression model argument))
      (:op (let ((op (model-find-op model argument)))
             (and (mop-precond op) (render-expression model (mop-precond op))))))))

;;; Random pieces

(defun random-literal-ast (prng model &key (negation-probability 0.2))
  "A random (:is I K), sometimes negated when the variable is enumerated."
  (let* ((i (rs-below prng (model-variable-count model)))
         (var (svref (model-variables model) i))
         (literal `(:is ,i ,(rs-below prng (length (mvar-domain var))))))
    (if (and (eq (mvar-kind var) :enumerated) (rs-chance prng negation-probability))
        `(:not ,literal)
        literal)))

(defun random-expression (prng model &key (depth 2) (constant-probability 0.03))
  "A random model expression AST at most DEPTH connectives deep."
  (cond ((rs-chance prng constant-probability) `(:const ,(rs-chance prng 0.5)))
        ((or (<= depth 0) (rs-chance prng 0.45)) (random-literal-ast prng model))
        (t (let ((child (lambda () (random-expression prng model :depth (1- depth)
                                                                 :constant-probability constant-probability))))
             (case (rs-below prng 6)
               ((0 1 2) `(:and ,@(loop repeat (rs-between prng 2 3) collect (funcall child))))
               ((3 4) `(:or ,@(loop repeat (rs-between prng 2 3) collect (funcall child))))
               (t `(:not ,(funcall child))))))))

(defun random-conjunction (prng model &key (max-literals 3))
  "A conjunction of 1..MAX-LITERALS literals on distinct variables (a lone literal unwrapped)."
  (let ((literals (loop for i in (rs-sample prng (loop for i below (model-variable-count model) collect i)
                                            (rs-between prng 1 max-literals))
                        for var = (svref (model-variables model) i)
                        collect `(:is ,i ,(rs-below prng (length (mvar-domain var)))))))
    (if (rest literals) `(:and ,@literals) (first literals))))

(defun random-condition (prng model)
  "A precondition or goal: usually a small conjunction, sometimes any expression."
  (if (rs-chance prng 0.6)
      (random-conjunction prng model)
      (random-expression prng model)))

(defun random-effects (prng model &key (max-effects 3))
  "1..MAX-EFFECTS effects on distinct variables, ((VAR-INDEX . VALUE-INDEX) ...)."
  (loop for i in (rs-sample prng (loop for i below (model-variable-count model) collect i)
                            (rs-between prng 1 max-effects))
        for var = (svref (model-variables model) i)
        collect (cons i (rs-below prng (length (mvar-domain var))))))

(defun random-variables (prng &key max-variables max-states enum-probability enum-values)
  "Between 1 and MAX-VARIABLES variables V0, V1..., some enumerated with the
values ENUM-VALUES; enumerated ones turn boolean until at most MAX-STATES states."
  (let* ((count (rs-between prng 1 max-variables))
         (kinds (loop repeat count
                      collect (if (rs-chance prng enum-probability) :enumerated :boolean))))
    (loop while (> (reduce #'* kinds :key (lambda (k) (if (eq k :boolean) 2 (length enum-values))))
                   max-states)
          do (let ((position (position :enumerated kinds :from-end t)))
               (if position
                   (setf (nth position kinds) :boolean)
                   (setf kinds (butlast kinds)))))
    (coerce (loop for kind in kinds
                  for i from 0
                  collect (if (eq kind :boolean)
                              (make-model-variable :name (rs-symbol "v~D" i) :kind :boolean
                                                   :domain (vector nil t)
                                                   :initial (rs-below prng 2))
                              (make-model-variable :name (rs-symbol "v~D" i) :kind :enumerated
                                                   :domain (map 'simple-vector #'rs-symbol enum-values)
                                                   :initial (rs-below prng (length enum-values)))))
            'simple-vector)))

(defun random-max-depth (prng)
  "Usually deep enough never to cut a plan; sometimes small, to exercise :max-depth."
  (if (rs-chance prng 0.8) 30 (rs-between prng 0 3)))

(defun random-spec (seed &key (name (rs-symbol "random-spec-~D" seed))
                              (max-variables 8) (max-states 1000)
                              (enum-probability 0.35) (enum-values '("lo" "mid" "hi"))
                              op-count (precondition-probability 0.75)
                              (must-ask-probability 0.15) (no-effect-probability 0.04)
                              macro-count goal-count op-event-count
                              (max-depth nil max-depth-p) event-generator)
  "A random spec for SEED. Returns (VALUES FORMS MODEL): the DEFINE-SPEC body
and its plain-data SPEC-MODEL.

The spec has 1..MAX-VARIABLES plannable variables V0, V1... (booleans, and
with ENUM-PROBABILITY string variables over ENUM-VALUES), at most MAX-STATES
states in all; OP-COUNT ops O0... with random preconditions (with
PRECONDITION-PROBABILITY) and :add/:sub effects, :must-ask with
MUST-ASK-PROBABILITY; MACRO-COUNT macro-ops M0... whose :seq runs helper ops
S0... that have no precondition (so a macro can never fail halfway); GOAL-COUNT
events G0... of one (:state GOAL) each; OP-EVENT-COUNT events DO-X of one
(:op X) each, preferring must-ask ops and macros. Unless MAX-DEPTH is given, it
is usually 30 and sometimes 0..3. Everything not given is drawn from the seed.
EVENT-GENERATOR, when given, is called last with the PRNG and the model and
returns MODEL-EVENTs to append (see RENDER-DIRECTIVE for their directives)."
  (let* ((prng (make-rs-prng seed))
         (model (make-spec-model
                 :name name :seed seed
                 :max-depth (if max-depth-p max-depth (random-max-depth prng))
                 :variables (random-variables prng :max-variables max-variables
                                                   :max-states max-states
                                                   :enum-probability enum-probability
                                                   :enum-values enum-values)))
         (nvars (model-variable-count model))
         (op-count (or op-count (rs-between prng (max 2 nvars) (+ 3 (* 2 nvars)))))
         (macro-count (or macro-count (rs-pick prng '(0 0 1 1 2 3))))
         (ops '()))
    ;; Plain ops.
    (dotimes (i op-count)
      (push (make-model-op :name (rs-symbol "o~D" i)
                           :precond (when (rs-chance prng precondition-probability)
                                      (random-condition prng model))
                           :effects (unless (rs-chance prng no-effect-probability)
                                      (random-effects prng model))
                           :must-ask (rs-chance prng must-ask-probability))
            ops))
    ;; Macros and the precondition-free helpers their :seq runs.
    (when (plusp macro-count)
      (let ((helpers (loop for i below (rs-between prng 1 3)
                           collect (make-model-op :name (rs-symbol "s~D" i)
                                                  :effects (unless (rs-chance prng 0.2)
                                                             (random-effects prng model))
                                                  :must-ask (rs-chance prng 0.3)))))
        (setf ops (append helpers ops))
        (dotimes (i macro-count)
          (push (make-model-op :name (rs-symbol "m~D" i) :kind :macro
                               :precond (if (rs-chance prng 0.8)
                                            (random-condition prng model)
                                            '(:const t))
                               :effects (random-effects prng model)
                               :seq (loop repeat (rs-between prng 1 3)
                                          collect (mop-name (rs-pick prng helpers))))
                ops))))
    (setf (model-ops model) (rs-shuffle prng (nreverse ops)))
    ;; Events.
    (let* ((goal-count (or goal-count (rs-between prng 2 5)))
           (op-event-count (or op-event-count (rs-between prng 1 3)))
           (preferred (remove-if-not (lambda (op) (or (mop-must-ask op) (eq (mop-kind op) :macro)))
                                     (model-ops model)))
           (others (remove-if (lambda (op) (member op preferred)) (model-ops model)))
           (requested (let ((candidates (append (rs-shuffle prng preferred) (rs-shuffle prng others))))
                        (subseq candidates 0 (min op-event-count (length candidates))))))
      (setf (model-events model)
            (append (loop for i below goal-count
                          collect (make-model-event :name (rs-symbol "g~D" i)
                                                    :directives `((:state ,(random-condition prng model)))))
                    (loop for op in requested
                          collect (make-model-event :name (rs-symbol "do-~A" (mop-name op))
                                                    :directives `((:op ,(mop-name op))))))))
    (when event-generator
      (setf (model-events model)
            (append (model-events model) (funcall event-generator prng model))))
    (values (model-spec-forms model) model)))
