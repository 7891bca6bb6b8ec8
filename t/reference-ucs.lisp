;;;; reference-ucs.lisp -- duration-optimal plans, (:optimize :duration), checked
;;;; against an independent reference: a plain explicit-state Dijkstra
;;;; (uniform-cost search) over a SPEC-MODEL (random-specs.lisp) with durations.
;;;;
;;;; The reference enumerates every state of the model, evaluates preconditions
;;;; and goals with reference-bfs.lisp's evaluator, and never calls the planner.
;;;; The semantics it encodes (the language's, restated):
;;;;  * a plan's cost is its ops' total duration, then its number of ops; an
;;;;    op costs its :duration, a macro-op the sum of its :seq ops' durations;
;;;;  * the operators and their effects are reference-bfs.lisp's;
;;;;  * a plan has at most :max-depth ops, so the answer for a state is the
;;;;    cheapest plan among those of at most :max-depth ops.
;;;; Durations are multiples of 1/8 s, so the reference counts eighths of a
;;;; second in fixnums and every sum is exact.

(in-package #:player-tests)

;;; Durations

(defparameter *reference-durations* '(0 1 2 4 8 8 8 12 16 40 800)
  "The durations random ops draw from, in eighths of a second (0 s to 100 s; 1 s most often).")

(defun random-durations (seed model)
  "A hash table: the name of each plain op of MODEL -> a duration in eighths
of a second, drawn from *REFERENCE-DURATIONS* with SEED."
  (let ((prng (make-rs-prng (+ 7919 seed)))
        (durations (make-hash-table)))
    (dolist (op (model-ops model) durations)
      (unless (eq (mop-kind op) :macro)
        (setf (gethash (mop-name op) durations) (rs-pick prng *reference-durations*))))))

(defun reference-op-duration (model op durations)
  "OP's duration in eighths of a second: a macro's is the sum of its :seq ops'."
  (if (eq (mop-kind op) :macro)
      (loop for name in (mop-seq op)
            sum (reference-op-duration model (model-find-op model name) durations))
      (gethash (mop-name op) durations)))

(defun timed-spec-forms (forms durations criterion)
  "FORMS (RANDOM-SPEC's) with (:optimize CRITERION) after the options and each
plain op given its duration from DURATIONS (eighths of a second) as :duration."
  (loop for form in forms
        collect (if (and (consp form) (symbolp (first form)) (string= (first form) "OP"))
                    (append form (list :duration (/ (gethash (second form) durations) 8.0)))
                    form)
          into timed
        finally (return (cons (list :optimize criterion) timed))))

;;; The search

(defun reference-timed-predecessors (model durations)
  "A vector: for each state number, a list of (PREVIOUS . DURATION), one per
plan operator leading from state PREVIOUS into it (self-loops left out)."
  (let* ((count (model-state-count model))
         (predecessors (make-array count :initial-element '()))
         (operators (model-plan-operators model)))
    (dotimes (index count predecessors)
      (let ((state (model-index-state model index)))
        (dolist (op operators)
          (when (model-op-applicable-p op state)
            (let ((next (model-state-index model (model-apply-effects op state))))
              (unless (= next index)
                (push (cons index (reference-op-duration model op durations))
                      (svref predecessors next))))))))))

(defconstant +reference-length-bits+ 10 "Bits of a queue key holding a plan length (:max-depth <= 1000).")
(defconstant +reference-state-bits+ 20 "Bits of a queue key holding a state number.")

(defun reference-key (cost length state)
  "One fixnum ordering (COST, LENGTH) lexicographically, carrying STATE."
  (logior (ash (logior (ash cost +reference-length-bits+) length) +reference-state-bits+) state))

(defun reference-key-parts (key)
  "(VALUES COST LENGTH STATE) of a REFERENCE-KEY."
  (values (ash key (- (+ +reference-length-bits+ +reference-state-bits+)))
          (ldb (byte +reference-length-bits+ +reference-state-bits+) key)
          (ldb (byte +reference-state-bits+ 0) key)))

(defun heap-push (key heap)
  "Add fixnum KEY to the min-heap HEAP (an adjustable vector)."
  (vector-push-extend key heap)
  (loop with child = (1- (fill-pointer heap))
        for parent = (floor (1- child) 2)
        while (and (plusp child) (< (aref heap child) (aref heap parent)))
        do (rotatef (aref heap child) (aref heap parent))
           (setf child parent)))

(defun heap-pop (heap)
  "Remove and return the least key of the non-empty min-heap HEAP."
  (let ((least (aref heap 0))
        (last (vector-pop heap)))
    (when (plusp (fill-pointer heap))
      (setf (aref heap 0) last)
      (loop with parent = 0
            for left = (1+ (* 2 parent))
            for best = (loop with best = parent
                             for child from left below (min (+ left 2) (fill-pointer heap))
                             when (< (aref heap child) (aref heap best)) do (setf best child)
                             finally (return best))
            until (= best parent)
            do (rotatef (aref heap parent) (aref heap best))
               (setf parent best)))
    least))

(defun reference-costs (model goal predecessors &key (max-depth (model-max-depth model)))
  "For every state number of MODEL, (COST . LENGTH) of the cheapest plan of at
most MAX-DEPTH operators from that state to one where model expression GOAL
holds (COST in eighths of a second; the fewest ops among the cheapest), or
NIL when there is none. Dijkstra backwards from the goal states over (state,
length) pairs, cheapest first: a pair is expanded unless a pair of the same
state already came off the queue with no more ops (it was no dearer, so
anything this one leads to, that one leads to as cheaply in as few ops)."
  (let* ((count (model-state-count model))
         (costs (make-array count :initial-element nil))
         (fewest (make-array count :initial-element (1+ max-depth)))
         (queue (make-array 64 :adjustable t :fill-pointer 0)))
    (dotimes (index count)
      (when (model-eval goal (model-index-state model index))
        (heap-push (reference-key 0 0 index) queue)))
    (loop while (plusp (fill-pointer queue))
          do (multiple-value-bind (cost length index) (reference-key-parts (heap-pop queue))
               (when (< length (svref fewest index))
                 (setf (svref fewest index) length)
                 (unless (svref costs index)
                   (setf (svref costs index) (cons cost length)))
                 (when (< length max-depth)
                   (loop for (previous . duration) in (svref predecessors index)
                         when (< (1+ length) (svref fewest previous))
                           do (heap-push (reference-key (+ cost duration) (1+ length) previous)
                                         queue))))))
    costs))

(defun exhaustive-costs (model goal predecessors &key (max-depth (model-max-depth model)))
  "REFERENCE-COSTS by brute force, to check it: the cheapest plan of exactly K
ops from every state, for K from 0 to MAX-DEPTH, then the best over K."
  (let* ((count (model-state-count model))
         (exactly (make-array count :initial-element nil))
         (best (make-array count :initial-element nil)))
    (dotimes (index count)
      (when (model-eval goal (model-index-state model index))
        (setf (svref exactly index) 0)))
    (loop for length from 0 to max-depth
          do (dotimes (index count)
               (let ((cost (svref exactly index))
                     (known (svref best index)))
                 (when (and cost (or (null known) (< cost (car known))))
                   (setf (svref best index) (cons cost length)))))
             (let ((next (make-array count :initial-element nil)))
               (dotimes (index count)
                 (when (svref exactly index)
                   (loop for (previous . duration) in (svref predecessors index)
                         for cost = (+ (svref exactly index) duration)
                         when (or (null (svref next previous)) (< cost (svref next previous)))
                           do (setf (svref next previous) cost))))
               (setf exactly next)))
    best))

;;; Checking Player's plan tables

(defun event-goal (model event)
  "The model goal of EVENT's only directive: its :state, or the requested op's
precondition; NIL for an op without one (nothing to plan)."
  (destructuring-bind (key argument) (first (mevent-directives event))
    (ecase key
      (:state argument)
      (:op (mop-precond (model-find-op model argument))))))

(defun player-goal-of-event (machine event-name)
  "The goal MACHINE planned for the event named EVENT-NAME's only directive, or NIL."
  (let* ((event (find (symbol-name event-name) (player.spec::spec-events (machine-spec machine))
                      :key (lambda (e) (symbol-name (player.spec::event-name e))) :test #'string=))
         (directive (first (player.spec::event-directives event))))
    (ecase (first directive)
      (:achieve (player.planner::machine-goal-for machine (second directive)))
      (:op (let ((op (second directive)))
             (and (player.spec::op-precond op) (player.planner::machine-goal-for machine (player.spec::op-precond op))))))))

(defun first-plan-for (goal state-bits)
  "The first plan of Player GOAL whose condition holds in one-hot STATE-BITS, or NIL."
  (find-if (lambda (plan) (player.spec::state-in-cube-p state-bits (player.planner::plan-condition plan)))
           (player.planner::goal-plans goal)))

(defun check-timed-plan (model durations goal start ops)
  "NIL when OPS (op names, first to run first) is a valid plan from START to
model GOAL; else a string. Second value: its (COST . LENGTH)."
  (let ((state start) (cost 0))
    (loop for name in ops
          for op = (model-find-op model name)
          for position from 1
          do (cond ((null op) (return-from check-timed-plan (format nil "op ~D (~A) is not an op of the model" position name)))
                   ((not (member op (model-plan-operators model)))
                    (return-from check-timed-plan (format nil "op ~D (~A) is must-ask" position name)))
                   ((not (model-op-applicable-p op state))
                    (return-from check-timed-plan
                      (format nil "op ~D (~A): its precondition does not hold in ~A" position name
                              (state-text model state)))))
             (incf cost (reference-op-duration model op durations))
             (setf state (model-apply-effects op state)))
    (if (model-eval goal state)
        (values nil (cons cost (length ops)))
        (values (format nil "the goal does not hold after ~S, in ~A" ops (state-text model state))
                (cons cost (length ops))))))

(defun cost-text (cost)
  "(EIGHTHS . OPS) as text: seconds and ops."
  (format nil "~F s in ~D op~:P" (/ (car cost) 8) (cdr cost)))

(defun check-timed-random-spec (seed &key generator-options (max-problems 3))
  "Plan (APPLY #'RANDOM-SPEC SEED GENERATOR-OPTIONS) with random durations and
(:optimize :duration); for each event goal and every state, the first plan
whose condition holds must be valid and as cheap as REFERENCE-COSTS says (or
absent when it says unreachable). Returns (VALUES PROBLEMS STATISTICS)."
  (multiple-value-bind (forms model) (apply #'random-spec seed generator-options)
    (let* ((durations (random-durations seed model))
           (name (model-name model))
           (problems '()) (checked 0) (unreachable 0) (longest 0) (not-fewest 0))
      (flet ((note (control &rest arguments)
               (when (< (length problems) max-problems)
                 (push (format nil "seed ~D~@[ ~S~]: ~?" seed generator-options control arguments) problems))))
        (unwind-protect
             (let* ((machine (plan-spec (define-spec name (timed-spec-forms forms durations :duration)
                                                     :package (find-package '#:player-user))))
                    (layout (player.planner::machine-layout machine))
                    (predecessors (reference-timed-predecessors model durations))
                    (untimed-predecessors (reference-predecessors model)))
               (dolist (event (model-events model))
                 (let ((goal (event-goal model event))
                       (player-goal (player-goal-of-event machine (mevent-name event))))
                   (when goal
                     (let ((costs (reference-costs model goal predecessors))
                           (fewest-ops (reference-distances model goal :predecessors untimed-predecessors)))
                       (dotimes (index (model-state-count model))
                         (let* ((start (model-index-state model index))
                                (expected (svref costs index))
                                (plan (first-plan-for player-goal (player.planner::dense-to-state index layout)))
                                (ops (and plan (mapcar #'player::op-name (player.planner::plan-ops plan)))))
                           (incf checked)
                           (cond ((null expected)
                                  (incf unreachable)
                                  (when plan
                                    (note "~A from ~A: Player plans ~S; the reference finds none"
                                          (mevent-name event) (state-text model start) ops)))
                                 ((null plan)
                                  (note "~A from ~A: Player has no plan; the reference's cheapest takes ~A"
                                        (mevent-name event) (state-text model start) (cost-text expected)))
                                 (t (multiple-value-bind (problem cost)
                                        (check-timed-plan model durations goal start ops)
                                      (setf longest (max longest (length ops)))
                                      (when (and (svref fewest-ops index) (> (length ops) (svref fewest-ops index)))
                                        (incf not-fewest))
                                      (cond (problem (note "~A from ~A: ~A" (mevent-name event)
                                                           (state-text model start) problem))
                                            ((not (equal cost expected))
                                             (note "~A from ~A: Player's plan ~S takes ~A; the reference's cheapest ~A"
                                                   (mevent-name event) (state-text model start) ops
                                                   (cost-text cost) (cost-text expected))))))))))))))
          (remove-spec name)))
      (values (nreverse problems)
              (list :checked checked :unreachable unreachable :longest longest :not-fewest not-fewest)))))

;;; The tests

(in-suite planner)

(defparameter *timed-property-cases*
  (flet ((family (seeds &rest options)
           (loop for seed from 1 to seeds collect (cons seed options))))
    (append (family 200)
            (family 60 :enum-probability 0.8 :precondition-probability 0.95 :macro-count 3 :goal-count 6)
            ;; A small :max-depth, where a dearer plan with fewer ops can be needed.
            (family 100 :max-depth 3)
            (family 60 :max-depth 2 :enum-probability 0.8 :precondition-probability 0.95
                       :macro-count 3 :goal-count 6)))
  "(SEED . RANDOM-SPEC-OPTIONS) of the random specs planned with random durations.")

(test reference-ucs-on-a-hand-made-model
  "The reference Dijkstra itself, on a model small enough to work out by hand."
  (let* ((model (make-spec-model
                 :name 'hand-made :max-depth 30
                 :variables (vector (make-model-variable :name 'x :kind :enumerated
                                                         :domain (vector 'a 'b 'c 'd)))
                 :ops (list (make-model-op :name 'slow :precond '(:is 0 0) :effects '((0 . 3)))
                            (make-model-op :name 'ab :precond '(:is 0 0) :effects '((0 . 1)))
                            (make-model-op :name 'bc :precond '(:is 0 1) :effects '((0 . 2)))
                            (make-model-op :name 'cd :precond '(:is 0 2) :effects '((0 . 3)))
                            (make-model-op :name 'free :precond '(:is 0 1) :effects '((0 . 2))))))
         (durations (make-hash-table))
         (goal '(:is 0 3)))
    (loop for (name eighths) in '((slow 800) (ab 1) (bc 1) (cd 1) (free 1))
          do (setf (gethash name durations) eighths))
    (let ((predecessors (reference-timed-predecessors model durations)))
      (flet ((costs (&rest keys) (coerce (apply #'reference-costs model goal predecessors keys) 'list)))
        ;; a: three ops of 1/8 s beat one of 100 s; b: two ops (bc or free, then cd).
        (is (equal '((3 . 3) (2 . 2) (1 . 1) (0 . 0)) (costs)))
        ;; With at most two ops, a must take the slow op; with none, only d is solved.
        (is (equal '((800 . 1) (2 . 2) (1 . 1) (0 . 0)) (costs :max-depth 2)))
        (is (equal '(nil nil nil (0 . 0)) (costs :max-depth 0)))
        (is (equal (costs :max-depth 2)
                   (coerce (exhaustive-costs model goal predecessors :max-depth 2) 'list)))))))

(test optimize-duration-prefers-two-quick-ops
  "The issue's example: one 100 s op against two 0.1 s ops. Fewest operators
(the default, or (:optimize :steps)) picks the single op; (:optimize :duration)
the two quick ones, and the controller runs them."
  (flet ((machine (criterion)
           (let ((spec (define-spec 'quick-or-slow
                           `(,@(when criterion `((:optimize ,criterion)))
                             (player-user::state-variable x player-user::string a (a b c))
                             (player-user::op slow :precond x.a :add x.c :duration 100)
                             (player-user::op step1 :precond x.a :add x.b :duration 0.1d0)
                             (player-user::op step2 :precond x.b :add x.c :duration 0.1d0)
                             (player-user::event go :state x.c))
                         :package (find-package '#:player-tests))))
             (compile-spec spec))))
    (unwind-protect
         (progn
           (is (equal '(slow) (cdr (second (plans (machine nil) 'x.c)))))
           (is (equal '(slow) (cdr (second (plans (machine :steps) 'x.c)))))
           (let ((m (machine :duration)))
             (is (equal '((x.c) (x.b step2) (x.a step1 step2)) (plans m 'x.c)))
             (let ((c (make-controller m)))
               (is (eq t (send-event c 'go)))
               (is (equal '("(:op step1 :script step1 :start 0 :end 0.1)"
                            "(:op step2 :script step2 :start 0.1 :end 0.2)")
                          (remove-if-not (lambda (l) (search "(:op" l)) (trace-of c)))))))
      (remove-spec 'quick-or-slow))))

(test optimize-duration-costs-a-macro-its-seq
  "A macro-op costs the sum of its :seq ops' durations: a macro of two 1 s ops
loses to one 1.5 s op, and wins against a 3 s one."
  (flet ((first-plan (direct-duration)
           (let ((spec (define-spec 'macro-cost
                           `((:optimize :duration)
                             (player-user::state-variable done boolean false)
                             (player-user::op half :duration 1)
                             (player-user::macro-op both :precond (not done) :add done
                                                    :seq (:op half :op half))
                             (player-user::op direct :precond (not done) :add done
                                                     :duration ,direct-duration)
                             (player-user::event go :state done))
                         :package (find-package '#:player-tests))))
             (cdr (second (plans (compile-spec spec) 'done))))))
    (unwind-protect
         (progn (is (equal '(direct) (first-plan 1.5)))
                (is (equal '(both) (first-plan 3))))
      (remove-spec 'macro-cost))))

(test optimize-option-is-checked
  "(:optimize CRITERION) takes :steps or :duration; anything else names the form."
  (let ((e (handler-case (progn (define-spec 'bad-optimize '((:optimize :speed)
                                                             (player-user::state-variable x player-user::boolean player-user::false))
                                             :package (find-package '#:player-tests))
                                nil)
             (spec-error (e) e))))
    (is (typep e 'spec-syntax-error))
    (is (equal '(:optimize :speed) (spec-error-form e)))
    (is (search "unknown :optimize criterion :speed (allowed: :steps or :duration)" (princ-to-string e))))
  (dolist (criterion '(:steps :duration player-user::duration))
    (is (player.spec::spec-p (define-spec 'good-optimize `((:optimize ,criterion)) :package (find-package '#:player-tests)))))
  (remove-spec 'good-optimize)
  (remove-spec 'bad-optimize))

(test optimize-duration-respects-max-depth
  "Within :max-depth, a dearer plan with fewer ops is kept where the cheapest
one has no op to spare: from b the cheapest plan is b-c c-d (2 s, 2 ops), but
with :max-depth 2 only b-d (10 s, 1 op) leaves room for a-b before it."
  (flet ((table (max-depth)
           (let ((spec (define-spec 'max-depth-cost
                           `((:optimize :duration) (:max-depth ,max-depth)
                             (player-user::state-variable x player-user::string a (a b c d))
                             (player-user::op a-b :precond x.a :add x.b)
                             (player-user::op b-c :precond x.b :add x.c)
                             (player-user::op c-d :precond x.c :add x.d)
                             (player-user::op b-d :precond x.b :add x.d :duration 10)
                             (player-user::event go :state x.d))
                         :package (find-package '#:player-tests))))
             (plans (compile-spec spec) 'x.d))))
    (unwind-protect
         (progn
           (is (equal '((x.d) (x.c c-d) (x.b b-c c-d) (x.a a-b b-c c-d)) (table 3)))
           (is (equal '((x.d) (x.c c-d) (x.b b-c c-d) (x.a a-b b-d)) (table 2)))
           (is (equal '((x.d) (x.c c-d) (x.b b-d)) (table 1))))
      (remove-spec 'max-depth-cost))))

(test reference-ucs-agrees-with-exhaustive-search
  "On the random models of the property test, the reference Dijkstra finds the
same costs as trying every plan length (a check of the reference itself)."
  (let ((problems 0))
    (loop for (seed . options) in (sweep-sample *timed-property-cases* 40)
          for model = (nth-value 1 (apply #'random-spec seed options))
          for durations = (random-durations seed model)
          for predecessors = (reference-timed-predecessors model durations)
          do (dolist (event (model-events model))
               (let ((goal (event-goal model event)))
                 (when (and goal (not (equalp (reference-costs model goal predecessors)
                                              (exhaustive-costs model goal predecessors))))
                   (incf problems)))))
    (is (zerop problems) "~D goals where Dijkstra and exhaustive search disagree" problems)))

(test duration-optimal-plans-match-reference-ucs
  "For 420 random specs with random durations and (:optimize :duration), every
event goal and every state: the first plan whose condition holds is valid (each
op's precondition holds in turn, the goal at the end) and costs exactly what
the reference Dijkstra's cheapest plan of at most :max-depth ops costs; a state
the reference cannot solve has no plan."
  (let ((problems '()) (failing 0)
        (totals (list :checked 0 :unreachable 0 :longest 0 :not-fewest 0)))
    (loop for (seed . options) in (sweep-sample *timed-property-cases* 40)
          do (multiple-value-bind (found statistics) (check-timed-random-spec seed :generator-options options)
               (when found
                 (incf failing)
                 (setf problems (subseq (append problems found) 0 (min 3 (+ (length problems) (length found))))))
               (loop for (key value) on statistics by #'cddr
                     do (if (eq key :longest)
                            (setf (getf totals key) (max value (getf totals key)))
                            (incf (getf totals key) value)))))
    (is (>= (length *timed-property-cases*) 200))
    ;; The durations must make the cheapest plans differ from the shortest ones.
    (is (plusp (getf totals :not-fewest)) "no cheapest plan was longer than a shortest one")
    (is (plusp (getf totals :unreachable)) "no state was expected to be unreachable")
    (is (null problems) "~D of ~D random specs disagree with the reference; the first problems:~{~%~%~A~}"
        failing (length *timed-property-cases*) problems)))
