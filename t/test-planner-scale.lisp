;;;; test-planner-scale.lisp -- the planner at scale. SolvedStates is marked
;;;; and read a word, or a group of 64 words, at a time (solved-states.lisp),
;;;; and asking it whether NewState is subsumed replaced the scan of ResultQ
;;;; for a plan covering NewState, which made planning quadratic in the number
;;;; of plans (issue 13). The planner as it was is kept here, with SolvedStates
;;;; marked state by state, and the new one must make the same plans in the
;;;; same order.

(in-package #:player-tests)

(in-suite planner)

;;; SolvedStates state by state

(defun naive-cube-states (cube layout)
  "The dense numbers of CUBE's states (variable 0 lowest, mixed radix), by
enumerating the values CUBE allows each variable."
  (let ((states (list 0))
        (stride 1))
    (loop for size across (player.planner::layout-sizes layout)
          for offset across (player.planner::layout-offsets layout)
          do (setf states (loop for value below size
                                when (logbitp (+ offset value) cube)
                                  append (mapcar (lambda (state) (+ state (* value stride))) states))
                   stride (* stride size)))
    states))

(defun naive-mark-cube (bitmap cube layout)
  "Set CUBE's states in BITMAP; return how many were clear."
  (loop for dense in (naive-cube-states cube layout)
        count (zerop (sbit bitmap dense))
        do (setf (sbit bitmap dense) 1)))

(defun naive-cube-has-unmarked-p (bitmap cube layout)
  "True when some state of CUBE is clear in BITMAP."
  (loop for dense in (naive-cube-states cube layout)
          thereis (zerop (sbit bitmap dense))))

;;; The planner before issue 13 (regression.lisp's PLAN-GOAL, SUB-PLAN and
;;; COVERED-BY-PLAN-P as they were), on a naive SolvedStates.

(defun scanning-plan-goal (goal-cubes operators layout max-depth)
  "The plans, solved-states bitmap and truncation flag of the old planner."
  (let ((result-q (player.planner::make-queue))
        (working-q (player.planner::make-queue))
        (solved-states (make-array (player.planner::layout-state-count layout) :element-type 'bit
                                                                         :initial-element 0)))
    (dolist (cube goal-cubes)
      (when (plusp (naive-mark-cube solved-states cube layout))
        (let ((empty-plan (player.planner::make-plan cube '())))
          (player.planner::enqueue empty-plan result-q)
          (player.planner::enqueue empty-plan working-q))))
    (let ((truncatedp (scanning-sub-plan result-q working-q solved-states operators layout max-depth)))
      (values (player.planner::queue-items result-q) solved-states truncatedp))))

(defun scanning-sub-plan (result-q working-q solved-states operators layout max-depth)
  "The old SUB-PLAN: a candidate a plan of RESULT-Q covers is skipped by scanning RESULT-Q."
  (let ((truncatedp nil))
    (loop until (player.planner::queue-empty-p working-q)
          do (let* ((root-plan (player.planner::dequeue working-q))
                    (root-state (player.planner::plan-condition root-plan))
                    (root-ops (player.planner::plan-ops root-plan)))
               (if (>= (length root-ops) max-depth)
                   (unless truncatedp
                     (setf truncatedp
                           (loop for operator in operators
                                   thereis (loop for new-state in (player.planner::regress root-state operator layout)
                                                   thereis (naive-cube-has-unmarked-p solved-states new-state layout)))))
                   (dolist (operator operators)
                     (dolist (new-state (player.planner::regress root-state operator layout))
                       (when (and (not (scanning-covered-by-plan-p new-state root-plan result-q))
                                  (plusp (naive-mark-cube solved-states new-state layout)))
                         (let ((new-plan (player.planner::make-plan new-state
                                                            (cons (player.planner::planner-op-op operator) root-ops))))
                           (player.planner::enqueue new-plan result-q)
                           (player.planner::enqueue new-plan working-q))))))))
    truncatedp))

(defun scanning-covered-by-plan-p (cube root-plan result-q)
  "The old quadratic test: some plan's condition (ROOT-PLAN's first) contains CUBE."
  (or (player.spec::cube-subset-p cube (player.planner::plan-condition root-plan))
      (loop for plan in (player.planner::queue-items result-q)
              thereis (player.spec::cube-subset-p cube (player.planner::plan-condition plan)))))

(defun plan-list (plans)
  "PLANS (a sequence of PLANs) as a list of (CONDITION . OP-DEFS)."
  (map 'list (lambda (plan) (cons (player.planner::plan-condition plan) (player.planner::plan-ops plan))) plans))

(defun compare-with-scanning-planner (forms name)
  "Plan FORMS with Player and with the old planner; NIL when every goal has the
same plans in the same order, the same solved states and truncation, else a string."
  (unwind-protect
       (let* ((machine (plan-spec (define-spec name forms :package (find-package '#:player-user))))
              (layout (player.planner::machine-layout machine))
              (max-depth (spec-max-depth (machine-spec machine))))
         (loop for goal across (player.planner::machine-goal-table machine)
               do (multiple-value-bind (plans solved truncatedp)
                      (scanning-plan-goal (player.planner::goal-cubes goal) (player.planner::machine-operators machine)
                                          layout max-depth)
                    (cond ((not (equal (plan-list plans) (plan-list (player.planner::goal-plans goal))))
                           (return (format nil "goal ~S: ~D plans, the old planner's ~D~@[, first differing at ~D~]"
                                           (player.planner::goal-expression goal) (length (player.planner::goal-plans goal))
                                           (length plans)
                                           (mismatch (plan-list plans) (plan-list (player.planner::goal-plans goal))
                                                     :test #'equal))))
                          ((not (equal solved (player.planner::bitmap-bits (player.planner::goal-solved goal) (length solved))))
                           (return (format nil "goal ~S: different solved states" (player.planner::goal-expression goal))))
                          ((not (eq (not truncatedp) (not (player.planner::goal-truncatedp goal))))
                           (return (format nil "goal ~S: truncated ~A, the old planner ~A"
                                           (player.planner::goal-expression goal) (player.planner::goal-truncatedp goal) truncatedp)))))))
    (remove-spec name)))

(defparameter *wide-spec-options*
  '(:max-variables 14 :max-states 16384 :enum-probability 0.05 :goal-count 4)
  "RANDOM-SPEC options of specs wide enough for SolvedStates' word and group paths.")

(defun wide-spec-seeds (count &key (minimum-variables 12))
  "The first COUNT seeds whose spec with *WIDE-SPEC-OPTIONS* has MINIMUM-VARIABLES or more."
  (loop for seed from 1
        when (>= (model-variable-count (nth-value 1 (apply #'random-spec seed *wide-spec-options*)))
                 minimum-variables)
          collect seed into seeds
        until (= (length seeds) count)
        finally (return seeds)))

(defun scale-test-cases ()
  "(SEED . RANDOM-SPEC-OPTIONS) of the specs compared with the old planner:
the property test's two families and 40 wide specs (12 to 14 variables)."
  (append (loop for seed from 1 to 240 collect (list seed))
          (loop for seed from 1 to 60
                collect (list seed :enum-probability 0.8 :precondition-probability 0.95
                                   :macro-count 3 :goal-count 6))
          (mapcar (lambda (seed) (cons seed *wide-spec-options*)) (wide-spec-seeds 40))))

;;; The tests

(test plans-match-the-scanning-planner
  "On 340 random specs (up to 2^14 states), the planner makes exactly the
plans of the planner before issue 13, in the same order, for every goal
(with a bit per full word of SolvedStates wherever the layout allows one)."
  (let ((problems '()) (cases (scale-test-cases)))
    (loop for (seed . options) in (sweep-sample cases 40)
          do (let ((problem (let ((player.planner::*group-threshold* 0)) ; groups however few the states
                              (compare-with-scanning-planner (apply #'random-spec seed options)
                                                             (rs-symbol "scale-~D" seed)))))
               (when problem
                 (push (format nil "seed ~D~@[ ~S~]: ~A" seed options problem) problems))))
    (is (>= (length cases) 300))
    (is (null problems) "~D of ~D specs plan differently:~{~%  ~A~}"
        (length problems) (length cases) (subseq problems 0 (min 5 (length problems))))))

(defun boolean-layout (count &key (enumerated '()))
  "The layout of a throwaway spec of COUNT booleans (and, at the positions in
ENUMERATED, three-valued variables), with groups however few its states."
  (let ((player.planner::*group-threshold* 0)
        (spec (define-spec 'layout-only
                  (loop for i below count
                        collect (if (member i enumerated)
                                    `(player-user::state-variable ,(rs-symbol "v~D" i) player-user::string
                                                                  lo (lo mid hi))
                                    `(player-user::state-variable ,(rs-symbol "v~D" i) player-user::boolean
                                                                  player-user::false)))
                :package (find-package '#:player-user))))
    (prog1 (player.planner::make-layout spec)
      (remove-spec 'layout-only))))

(defun random-cube (prng layout &key (free-probability 0.6))
  "A random non-empty cube of LAYOUT: each variable free, or one value, or (enumerated) two."
  (loop for size across (player.planner::layout-sizes layout)
        for offset across (player.planner::layout-offsets layout)
        sum (ash (cond ((rs-chance prng free-probability) (1- (ash 1 size)))
                       ((and (> size 2) (rs-chance prng 0.3))
                        (logxor (1- (ash 1 size)) (ash 1 (rs-below prng size))))
                       (t (ash 1 (rs-below prng size))))
                 offset)))

(test solved-states-words-and-groups
  "SolvedStates marks and tests cubes as state-by-state marking does, on layouts
with groups (14 booleans), with words only (7 booleans, 6 booleans then an
enumerated variable), and with neither; the full-word bits stay exact."
  (loop for (count enumerated kind) in '((14 () :groups) (13 (12) :groups) (7 () :words)
                                         (9 (6) :words) (8 (2 5) :runs) (16 (0) :runs))
        for layout = (boolean-layout count :enumerated enumerated)
        for prng = (make-rs-prng count)
        do (is (eq kind (cond ((player.planner::layout-group-prefix layout) :groups)
                              ((player.planner::layout-word-prefix layout) :words)
                              (t :runs))))
           (dolist (free-probability '(0.3 0.5 0.7 0.9))
             (let ((solved (player.planner::make-solved-states layout))
                   (naive (make-array (player.planner::layout-state-count layout) :element-type 'bit
                                                                            :initial-element 0))
                   (agree t))
               (loop repeat (sweep-count 400 100)
                     for cube = (random-cube prng layout :free-probability free-probability)
                     do (unless (and (eq (player.planner::cube-has-unmarked-p solved cube layout)
                                         (naive-cube-has-unmarked-p naive cube layout))
                                     (= (player.planner::mark-cube solved cube layout)
                                        (naive-mark-cube naive cube layout))
                                     (equal naive (player.planner::bitmap-bits (player.planner::solved-states-bits solved)
                                                                             (length naive))))
                          (setf agree nil)))
               (is-true agree "~D variables (~S enumerated), cubes free ~A: marking disagrees"
                        count enumerated free-probability)
               (let ((full (player.planner::solved-states-full-words solved)))
                 (when full
                   (is (every (lambda (word)
                                (eq (= 1 (player.planner::bitmap-bit full word))
                                    (every #'plusp (subseq naive (* word 64) (* (1+ word) 64)))))
                              ;; a bit per whole word of the states
                              (loop for word below (floor (length naive) 64) collect word)))))))))

(test full-state-space-plans
  "A spec of 26 booleans, 2^26 states (the limit), plans every state, by steps and by duration."
  (dolist (criterion '(:steps :duration))
    (unwind-protect
         (let* ((spec (define-spec 'wide-26
                          `((:optimize ,criterion)
                            ,@(loop for i below 26
                                    collect `(player-user::state-variable ,(intern (format nil "X~D" i) '#:player-tests)
                                                                          player-user::boolean player-user::false))
                            (player-user::op a :add x0)
                            (player-user::op b :precond x0 :add x25)
                            (player-user::op c :precond (not x12) :sub x0)
                            (player-user::event e :state (and x0 x25)))
                        :package (find-package '#:player-tests)))
                (machine (plan-spec spec)))
           (is (= (expt 2 26) (machine-state-count machine)))
           (is (equal '(((and x0 x25)) (x25 a) (x0 b) (player.spec::true a b)) (plans machine '(and x0 x25))))
           (is (= (expt 2 26) (player.planner::goal-solved-count (aref (player.planner::machine-goal-table machine) 0)))))
      (remove-spec 'wide-26))))

(test equal-durations-plan-breadth-first
  "With every op lasting the same (and no macro-ops, which last their :seq),
(:optimize :duration) makes exactly the plans of the breadth-first planner."
  (let ((problems '()))
    (loop for (seed . options) in (append (loop for seed from 1 to 120 collect (list seed :macro-count 0))
                                          (loop for seed from 1 to 30
                                                collect (list* seed :macro-count 0 *wide-spec-options*)))
          do (let ((forms (apply #'random-spec seed options)))
               (flet ((tables (criterion)
                        (unwind-protect
                             (let ((machine (plan-spec (define-spec 'equal-durations
                                                           (cons (list :optimize criterion) forms)
                                                         :package (find-package '#:player-user)))))
                               (map 'list (lambda (goal)
                                            (list (map 'list (lambda (plan)
                                                               (cons (player.planner::plan-condition plan)
                                                                     (mapcar #'player::op-name (player.planner::plan-ops plan))))
                                                       (player.planner::goal-plans goal))
                                                  (player.planner::goal-solved goal)
                                                  (not (player.planner::goal-truncatedp goal))))
                                    (player.planner::machine-goal-table machine)))
                          (remove-spec 'equal-durations))))
                 (unless (equalp (tables :steps) (tables :duration))
                   (push seed problems)))))
    (is (null problems) "the plans differ for seeds ~S" problems)))

(test wide-domains-match-the-scanning-planner
  "A variable of 70 values (its one-hot field wider than a fixnum) and a
boolean: the same plans as the old planner, with and without :max-depth cutting."
  (flet ((forms (max-depth)
           (let ((values (loop for i below 70 collect (rs-symbol "w~D" i))))
             `((:max-depth ,max-depth)
               (player-user::state-variable x player-user::string w0 ,values)
               (player-user::state-variable y player-user::boolean player-user::false)
               (player-user::op up :precond (not y) :add y)
               (player-user::op jump :precond (and x.w3 y) :add x.w60)
               ,@(loop for (a b) on values while b
                       collect `(player-user::op ,(rs-symbol "~A-~A" a b)
                                                 :precond ,(rs-symbol "x.~A" a) :add ,(rs-symbol "x.~A" b)))
               (player-user::event e :state (and x.w69 y))
               (player-user::event f :state (or x.w1 x.w65))))))
    (is (null (compare-with-scanning-planner (forms 16) 'wide-domain)))
    (is (null (compare-with-scanning-planner (forms 80) 'wide-domain)))))
