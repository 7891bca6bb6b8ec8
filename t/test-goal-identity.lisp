;;;; test-goal-identity.lisp -- goals that hold in the same states are one goal,
;;;; however they are written; checked against brute-force evaluation of the
;;;; expressions on every state with the reference evaluator (MODEL-EVAL).

(in-package #:player-tests)

(def-suite* goal-identity :in player-tests)

(test the-same-states-written-twice-are-one-goal
  (with-spec (spec either
              (state-variable a boolean false)
              (state-variable b boolean false)
              (op set-a :add a)
              (op set-b :precond a :add b)
              (event ev-one :state (or a b))
              (event ev-two :state (or a (and (not a) b)))
              (event ev-three :state (not (and (not a) (not b)))))
    (let ((machine (compile-spec spec)))
      (is (= 1 (length (machine-goals machine))))
      (is (equal (plans machine '(or a b)) (plans machine '(or a (and (not a) b)))))
      (let ((controller (make-controller machine)))
        (is (eq t (send-event controller 'ev-two)))
        (is (eq t (state-value controller 'a)))))))

(defun rewrite-preserving-meaning (prng model ast)
  "AST rewritten once, at a random place, by a law that keeps the states it holds in."
  (flet ((law (e)
           (case (rs-below prng 6)
             (0 `(:not (:not ,e)))
             (1 (if (member (first e) '(:and :or))
                    `(:not (,(if (eq (first e) :and) :or :and) ,@(mapcar (lambda (x) `(:not ,x)) (rest e))))
                    e))
             (2 (if (and (eq (first e) :or) (rest (rest e)))
                    ;; (or a b ...) = (or a (and (not a) (or b ...)))
                    `(:or ,(second e) (:and (:not ,(second e)) (:or ,@(cddr e))))
                    e))
             (3 (if (member (first e) '(:and :or)) `(,(first e) ,@(reverse (rest e))) e))
             (4 `(:or ,e (:and ,e ,(random-expression prng model :depth 1))))
             (t (let ((x (random-literal-ast prng model)))
                  `(:and ,e (:or ,x (:not ,x))))))))
    (if (and (member (first ast) '(:and :or :not)) (rs-chance prng 0.6))
        (let ((k (rs-below prng (length (rest ast)))))
          `(,(first ast) ,@(loop for child in (rest ast)
                                 for i from 0
                                 collect (if (= i k) (rewrite-preserving-meaning prng model child) child))))
        (law ast))))

(defun model-states-where (model ast)
  "The states (as a bit vector over their numbers) where AST holds, by MODEL-EVAL."
  (let* ((count (model-state-count model))
         (bits (make-array count :element-type 'bit :initial-element 0)))
    (dotimes (index count bits)
      (when (model-eval ast (model-index-state model index))
        (setf (sbit bits index) 1)))))

(defun player-cubes (spec model ast)
  "Player's canonical cubes of model expression AST in SPEC."
  (let ((player.spec::*spec* spec) (player.base::*current-spec-name* (player::spec-name spec)))
    (player.spec::expression-cubes (player.spec::parse-expression (render-expression model ast)) spec)))

(test equivalence-agrees-with-brute-force
  ;; 150 random specs, 4 pairs each: one expression against a rewriting of it
  ;; (same states), or against another random one (usually not).
  (let ((same 0) (different 0))
    (loop for seed from 1 to 150
          for name = (rs-symbol "identity-~D" seed)
          do (multiple-value-bind (forms model) (random-spec seed :max-variables 5 :max-states 200)
               (let ((spec (define-spec name forms :package (find-package '#:player-tests)))
                     (prng (make-rs-prng (+ 104729 seed))))
                 (unwind-protect
                      (dotimes (i 4)
                        (let* ((a (random-expression prng model :depth 3))
                               (b (if (rs-chance prng 0.6)
                                      (loop with e = a repeat (rs-between prng 1 4)
                                            do (setf e (rewrite-preserving-meaning prng model e))
                                            finally (return e))
                                      (random-expression prng model :depth 3)))
                               (expected (equal (model-states-where model a) (model-states-where model b)))
                               (got (player.planner::dnf-equivalent-p (player-cubes spec model a) (player-cubes spec model b) spec)))
                          (if expected (incf same) (incf different))
                          (is (eq expected got) "seed ~D: ~S vs ~S" seed a b)))
                   (remove-spec name)))))
    (is (> same 200))
    (is (> different 100))))

(defun goal-state-set (goal layout)
  "The states GOAL's cubes hold, by enumeration: a bit per dense state number."
  (let ((bits (make-array (player.planner::layout-state-count layout) :element-type 'bit)))
    (dotimes (dense (length bits) bits)
      (let ((state (player.planner::dense-to-state dense layout)))
        (setf (sbit bits dense)
              (if (some (lambda (cube) (player.spec::state-in-cube-p state cube)) (player.planner::goal-cubes goal)) 1 0))))))

(defun planned-event-goal (machine spec name)
  "The goal MACHINE planned for the :state of SPEC's event NAME."
  (let ((event (find name (player.spec::spec-events spec) :key #'player.spec::event-name)))
    (player.planner::machine-goal-for machine (second (first (player.spec::event-directives event))))))

(test a-machine-plans-each-set-of-states-once
  ;; Random specs with extra events asking for rewritten goals: every goal the
  ;; machine plans holds in a set of states no other goal holds in, and each
  ;; goal and its rewriting are one goal.
  (loop for seed from 1 to 60
        for name = (rs-symbol "identity-machine-~D" seed)
        do (multiple-value-bind (forms model) (random-spec seed :max-variables 4 :max-states 100)
             (let* ((prng (make-rs-prng (+ 1299709 seed)))
                    (goals (loop repeat 3 collect (random-expression prng model :depth 2)))
                    (rewritten (mapcar (lambda (g) (rewrite-preserving-meaning prng model g)) goals))
                    (names (loop for i below 6 collect (rs-symbol "same-~D" i)))
                    (events (loop for g in (append goals rewritten)
                                  for event-name in names
                                  collect (list (rs-symbol "event") event-name
                                                :state (render-expression model g))))
                    (spec (define-spec name (append forms events) :package (find-package '#:player-tests))))
               (unwind-protect
                    (let* ((machine (compile-spec spec))
                           (layout (player.planner::machine-layout machine))
                           (sets (map 'list (lambda (goal) (goal-state-set goal layout))
                                      (player.planner::machine-goal-table machine))))
                      (is (= (length sets) (length (remove-duplicates sets :test #'equal)))
                          "seed ~D: two goals of one machine hold in the same states" seed)
                      (loop for i below 3
                            do (is (eq (planned-event-goal machine spec (nth i names))
                                       (planned-event-goal machine spec (nth (+ i 3) names)))
                                   "seed ~D: goal ~S and its rewriting are two goals" seed (nth i goals))))
                 (remove-spec name))))))
