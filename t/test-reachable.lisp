;;;; test-reachable.lisp -- the reachable regime (issue 13): plans from every
;;;; state reachable from the initial state and the :start-states, checked
;;;; against the independent searches of reference-reachable.lisp, on random
;;;; specs in both regimes and on the STRIPS families of strips-families.lisp;
;;;; the controller's refusal of unplanned states and its run-time search.

(in-package #:player-tests)

(def-suite* reachable :in player-tests)

;;; Random specs in both regimes

(defun assignment-events (prng model)
  "RANDOM-SPEC's event generator: sometimes an event SET-0 of one :add/:sub,
so the events' assignments count among the transitions."
  (when (rs-chance prng 0.5)
    (let* ((i (rs-below prng (model-variable-count model)))
           (k (rs-below prng (length (mvar-domain (svref (model-variables model) i))))))
      (list (make-model-event :name (rs-symbol "set-0") :directives `((:assign ,i ,k)))))))

(defun start-expressions (seed model)
  "For one seed in three, a random (:start-states EXPR) expression of MODEL, as a list; else NIL."
  (when (zerop (mod seed 3))
    (list (random-condition (make-rs-prng (+ 104729 seed)) model))))

(defun unit-durations (model)
  "A duration table (as RANDOM-DURATIONS') giving every plain op of MODEL 1 s."
  (let ((durations (make-hash-table)))
    (dolist (op (model-ops model) durations)
      (setf (gethash (mop-name op) durations) 8))))

(defun reachable-spec-forms (forms model starts regime durations)
  "FORMS with (:state-space REGIME), MODEL's STARTS as (:start-states ...),
and with DURATIONS, (:optimize :duration) and each op's duration."
  (append (list (list :state-space regime))
          (when starts
            (list (cons :start-states (mapcar (lambda (e) (render-expression model e)) starts))))
          (if durations (timed-spec-forms forms durations :duration) forms)))

(defun goal-events (model)
  "MODEL's events of one :state or :op directive with something to plan."
  (remove-if-not (lambda (event)
                   (and (member (first (first (mevent-directives event))) '(:state :op))
                        (event-goal model event)))
                 (model-events model)))

(defun check-reachable-random-spec (seed regime &key criterion options)
  "Plan RANDOM-SPEC SEED (with OPTIONS, an assignment event now and then, and
for one seed in three a :start-states expression) under (:state-space
REGIME), by steps or, with CRITERION :duration, by random durations. In the
reachable regime the machine's states must be the reference's reachable
states; from each of those, the first plan whose condition holds must be a
valid plan as short (or cheap) as the reference's, or absent when the
reference has none. Returns a list of problems (strings)."
  (multiple-value-bind (forms model)
      (apply #'random-spec seed :event-generator #'assignment-events options)
    (let* ((starts (start-expressions seed model))
           (durations (and (eq criterion :duration) (random-durations seed model)))
           (name (model-name model))
           (reachable (reference-reachable-indices model starts))
           (problems '()))
      (flet ((note (control &rest arguments)
               (when (< (length problems) 3)
                 (push (format nil "seed ~D ~(~A~)~@[ ~(~A~)~]: ~?" seed regime criterion control arguments)
                       problems))))
        (unwind-protect
             (let* ((machine (plan-spec (define-spec name (reachable-spec-forms forms model starts regime durations)
                                                     :package (find-package '#:player-user))))
                    (layout (player.planner::machine-layout machine))
                    (one-hot (let ((table (make-hash-table)))
                               (loop for index being the hash-keys of reachable
                                     do (setf (gethash index table)
                                              (model-one-hot model machine (model-index-state model index))))
                               table)))
               (when (eq regime :reachable)
                 (let ((mine (make-hash-table)))
                   (dotimes (dense (machine-state-count machine))
                     (setf (gethash (player.planner::dense-to-state dense layout) mine) t))
                   (unless (and (= (hash-table-count mine) (hash-table-count reachable))
                                (loop for state being the hash-values of one-hot
                                      always (gethash state mine)))
                     (note "Player plans for ~D states; the reference reaches ~D"
                           (hash-table-count mine) (hash-table-count reachable)))))
               (dolist (event (goal-events model))
                 (let* ((goal (event-goal model event))
                        (player-goal (player-goal-of-event machine (mevent-name event)))
                        (expected (if durations
                                      (reference-costs model goal (reference-timed-predecessors model durations))
                                      (reference-distances model goal))))
                   (loop for index being the hash-keys of reachable
                         do (let* ((start (model-index-state model index))
                                   (want (svref expected index))
                                   (plan (first-plan-for player-goal (gethash index one-hot)))
                                   (ops (and plan (mapcar #'player::op-name (player.planner::plan-ops plan)))))
                              (cond ((and (null want) plan)
                                     (note "~A from ~A: Player plans ~S; the reference finds none"
                                           (mevent-name event) (state-text model start) ops))
                                    ((and want (null plan))
                                     (note "~A from ~A: no plan; the reference's takes ~A"
                                           (mevent-name event) (state-text model start) want))
                                    (plan
                                     (multiple-value-bind (problem cost)
                                         (check-timed-plan model (or durations (unit-durations model))
                                                           goal start ops)
                                       (cond (problem (note "~A from ~A: ~A" (mevent-name event)
                                                            (state-text model start) problem))
                                             ((not (if durations (equal cost want) (= (length ops) want)))
                                              (note "~A from ~A: Player's plan ~S; the reference's best is ~A"
                                                    (mevent-name event) (state-text model start) ops want)))))))))))
          (remove-spec name)))
      (nreverse problems))))

(defparameter *reachable-property-cases*
  (append (loop for seed from 1 to 200 collect (list seed))
          (loop for seed from 201 to 260
                collect (list seed :enum-probability 0.8 :precondition-probability 0.95
                                   :macro-count 3 :goal-count 6))
          (loop for seed from 261 to 300 collect (list seed :max-depth 2)))
  "(SEED . RANDOM-SPEC-OPTIONS) of the random specs planned in both regimes.")

(test reachable-regime-matches-the-reference-bfs
  "300 random specs, each planned in both regimes (and 60 of them by duration
in the reachable one): from every reachable state, shortest (cheapest) plans,
as an independent forward BFS and backward search over the model say; in the
reachable regime, exactly the reachable states are planned."
  (let ((problems '()) (specs 0))
    (loop for (seed . options) in (sweep-sample *reachable-property-cases* 30)
          do (dolist (regime '(:full :reachable))
               (incf specs)
               (setf problems (append problems (check-reachable-random-spec seed regime :options options))))
             (when (<= seed 60)
               (setf problems (append problems (check-reachable-random-spec seed :reachable :criterion :duration
                                                                                              :options options)))))
    (is (>= (length *reachable-property-cases*) 300))
    (is (null problems) "~D problems, the first:~{~%  ~A~}" (length problems)
        (subseq problems 0 (min 5 (length problems))))))

(test reachable-regime-controllers-run-shortest-plans
  "Controllers of 12 random specs in the reachable regime run, from every
reachable state, the plan the reference BFS says (run through CHECK-RUN)."
  (let ((problems '()))
    (loop for seed from 1 to 12
          do (multiple-value-bind (forms model) (random-spec seed)
               (let ((name (model-name model))
                     (reachable (reference-reachable-indices model)))
                 (unwind-protect
                      (let ((machine (compile-spec (define-spec name (cons '(:state-space :reachable) forms)
                                                                :package (find-package '#:player-user)))))
                        (dolist (event (model-events model))
                          (let ((distances (reference-distances model (event-goal-ast model event))))
                            (loop for index being the hash-keys of reachable
                                  do (let ((problem (let ((*package* (find-package '#:player-user)))
                                                      (check-run model machine event (svref distances index)
                                                                 (model-index-state model index)))))
                                       (when problem
                                         (push (format nil "seed ~D ~A: ~A" seed (mevent-name event) problem)
                                               problems)))))))
                   (remove-spec name)))))
    (is (null problems) "~D problems, the first:~{~%  ~A~}" (length problems)
        (subseq problems 0 (min 3 (length problems))))))

;;; The STRIPS families

(defun strips-one-hot (state facts offsets)
  "The one-hot state of the STRIPS STATE (bit I for fact I of FACTS), given
each fact's boolean field OFFSETS (false at the offset, true one above)."
  (loop for nil in facts
        for i from 0
        for offset in offsets
        sum (ash 1 (+ offset (if (logbitp i state) 1 0)))))

(defun check-strips-problem (problem &key sample)
  "Plan PROBLEM's spec in the reachable regime and check it against
STRIPS-REACHABLE: the same reachable states, and from each (or from every
SAMPLEth), for each goal, the first plan whose condition holds is a valid
plan of the reference's fewest actions. Returns (VALUES PROBLEMS CHECKED)."
  (let* ((name (player-strips:strips-problem-name problem))
         (facts (player-strips:strips-problem-facts problem))
         (problems '()) (checked 0))
    (flet ((note (control &rest arguments)
             (when (< (length problems) 3)
               (push (format nil "~A: ~?" name control arguments) problems))))
      (unwind-protect
           (let* ((machine (plan-spec (define-spec name (player-strips:strips-spec-forms problem)
                                                   :package (find-package '#:player-user))))
                  (spec (machine-spec machine))
                  (offsets (mapcar (lambda (f)
                                     (player.spec::var-bit-offset
                                      (find (symbol-name f) (player.spec::plannable-variables spec)
                                            :key (lambda (var) (symbol-name (player.spec::var-name var)))
                                            :test #'string=)))
                                   facts))
                  (actions (player-strips:strips-problem-actions problem)))
             (multiple-value-bind (states edges) (strips-reachable problem)
               (unless (= (length states) (machine-state-count machine))
                 (note "~D states planned, ~D reachable" (machine-state-count machine) (length states)))
               (let ((mine (make-hash-table)))
                 (dotimes (dense (machine-state-count machine))
                   (setf (gethash (player.planner::dense-to-state dense (player.planner::machine-layout machine)) mine) t))
                 (unless (every (lambda (state) (gethash (strips-one-hot state facts offsets) mine)) states)
                   (note "Player's states are not the reachable ones")))
               (loop for (event-name . goal-facts) in (player-strips:strips-problem-goals problem)
                     for goal = (player-goal-of-event machine event-name)
                     for goal-bits = (strips-fact-bits problem goal-facts)
                     for distances = (strips-distances edges goal-bits)
                     do (loop for state in states
                              for k from 0
                              when (or (null sample) (zerop (mod k sample)))
                                do (incf checked)
                                   (let* ((plan (first-plan-for goal (strips-one-hot state facts offsets)))
                                          (want (gethash state distances))
                                          (end state))
                                     (cond ((not (eq (null plan) (null want)))
                                            (note "~A from state ~D: plan ~A, reference distance ~A"
                                                  event-name k plan want))
                                           (plan
                                            (dolist (op (player.planner::plan-ops plan))
                                              (let ((action (find (symbol-name (player::op-name op)) actions
                                                                  :key (lambda (a) (symbol-name (player-strips:strips-action-name a)))
                                                                  :test #'string=)))
                                                (setf end (and end (strips-apply problem action end)))))
                                            (unless (and end (= goal-bits (logand goal-bits end))
                                                         (= want (length (player.planner::plan-ops plan))))
                                              (note "~A from state ~D: plan ~S (~D ops) is not a shortest plan (~D)"
                                                    event-name k (mapcar #'player::op-name (player.planner::plan-ops plan))
                                                    (length (player.planner::plan-ops plan)) want)))))))))
        (remove-spec name)))
    (values (nreverse problems) checked)))

(test blocks-world-plans-are-shortest
  "Blocks world with 4 and 5 blocks (25 and 36 booleans; 125 and 866
reachable states), planned in the reachable regime: shortest plans from every
reachable state to every goal, by an independent BFS."
  (dolist (n '(4 5))
    (multiple-value-bind (problems checked) (check-strips-problem (player-strips:blocks-world n))
      (is (= (* 3 (if (= n 4) 125 866)) checked))
      (is (null problems) "~{~A~%~}" problems))))

(test gripper-plans-are-shortest
  "The gripper-like domain with 4 to 8 balls: shortest plans from every
reachable state (every 40th of the 11,776 with 7 and 8 balls), by an
independent BFS."
  (loop for balls from 4 to (sweep-count 8 7)
        do (multiple-value-bind (problems checked)
               (check-strips-problem (player-strips:gripper balls)
                                     :sample (and (> balls 6) (sweep-count 40 400)))
             (is (plusp checked))
             (is (null problems) "~{~A~%~}" problems))))

;;; Wide specs

(defun token-ring-forms (count)
  "A spec of COUNT booleans T0... passing one token along (T0 starts with it)
and an enumerated MODE cycling through three values: 3 * COUNT reachable
states of 3 * 2^COUNT."
  (append `((:max-depth ,(+ count 4)))
          (loop for i below count
                collect `(player-user::state-variable ,(rs-symbol "t~D" i) player-user::boolean
                                                      ,(if (zerop i) 'player-user::true 'player-user::false)))
          '((player-user::state-variable player-user::mode player-user::string player-user::lo
             (player-user::lo player-user::mid player-user::hi)))
          (loop for i from 0 below (1- count)
                collect `(player-user::op ,(rs-symbol "pass-~D" i) :precond ,(rs-symbol "t~D" i)
                                          :add ,(rs-symbol "t~D" (1+ i)) :sub ,(rs-symbol "t~D" i)))
          '((player-user::op player-user::up :precond player-user::mode.lo :add player-user::mode.mid)
            (player-user::op player-user::upper :precond player-user::mode.mid :add player-user::mode.hi)
            (player-user::op player-user::down :precond player-user::mode.hi :add player-user::mode.lo))
          `((player-user::event player-user::finish :state (and ,(rs-symbol "t~D" (1- count)) player-user::mode.hi)))))

(test specs-of-130-variables-plan-their-reachable-states
  "130 booleans and an enumerated variable (2^130 * 3 states, 390 reachable)
are planned in the reachable regime without asking: shortest plans from every
reachable state, and a controller runs one."
  (unwind-protect
       (let* ((machine (compile-spec (define-spec 'token-ring (token-ring-forms 130)
                                                  :package (find-package '#:player-user))))
              (goal (aref (player.planner::machine-goal-table machine) 0))
              (layout (player.planner::machine-layout machine)))
         (is (= 390 (machine-state-count machine)))
         (is (= (* 3 (expt 2 130)) (player.planner::layout-space-size layout)))
         (flet ((offset (name)
                  (player.spec::var-bit-offset (find name (player.spec::plannable-variables (machine-spec machine))
                                                :key (lambda (var) (symbol-name (player.spec::var-name var)))
                                                :test #'string=))))
           (is (every (lambda (dense)
                        (let* ((state (player.planner::dense-to-state dense layout))
                               ;; Each state has one token and one mode; ERROR otherwise.
                               (token (or (loop for i below 130
                                                when (logbitp (1+ (offset (format nil "T~D" i))) state)
                                                  return i)
                                          (error "no token in state ~D" dense)))
                               (mode (or (loop for k below 3
                                               when (logbitp (+ k (offset "MODE")) state) return k)
                                         (error "no mode in state ~D" dense)))
                               (plan (first-plan-for goal state)))
                          (= (length (player.planner::plan-ops plan))
                             (+ (- 129 token) (nth mode '(2 1 0))))))
                      (loop for dense below 390 collect dense))))
         (let ((controller (make-controller machine :presenter (make-null-presenter))))
           (is (eq t (send-event controller 'player-user::finish)))
           (is (eq t (state-value controller (rs-symbol "t129"))))))
    (remove-spec 'token-ring)))

;;; Start states, refusal and the run-time search

(defparameter *reachable-door-forms*
  '((:state-space :reachable)
    (player-user::state-variable player-user::door player-user::string player-user::shut
     (player-user::shut player-user::open player-user::locked))
    (player-user::state-variable player-user::inside player-user::boolean player-user::false)
    (player-user::op player-user::open-door :precond player-user::door.shut :add player-user::door.open)
    (player-user::op player-user::shut-door :precond player-user::door.open :add player-user::door.shut)
    (player-user::op player-user::enter :precond (and player-user::door.open (player-user::not player-user::inside))
     :add player-user::inside)
    (player-user::op player-user::unlock :precond player-user::door.locked :add player-user::door.shut)
    (player-user::event player-user::go-in :state player-user::inside))
  "A door that starts shut and is never locked by any op: the locked states are not reachable.")

(defun reachable-door-machine (&rest options)
  "The door spec with OPTIONS before its forms, compiled."
  (compile-spec (define-spec 'door (append options *reachable-door-forms*) :package (find-package '#:player-user))))

(test start-states-widen-the-planned-set
  "Without :start-states the 3 states reachable from a shut door outside are
planned; (:start-states door.locked) adds the locked states and what they reach."
  (unwind-protect
       (progn
         (is (= 4 (machine-state-count (reachable-door-machine))))
         (let ((machine (reachable-door-machine '(:start-states player-user::door.locked))))
           (is (= 6 (machine-state-count machine)))
           (let ((controller (make-controller machine :initial-state '((player-user::door . player-user::locked)))))
             (is (eq t (send-event controller 'player-user::go-in)))
             (is (equal '("(:op unlock :script unlock :start 0 :end 1)" "(:op open-door :script open-door :start 1 :end 2)"
                          "(:op enter :script enter :start 2 :end 3)")
                        (remove-if-not (lambda (line) (search "(:op" line)) (trace-of controller)))))))
    (remove-spec 'door)))

(test unplanned-states-are-refused
  "A controller may not start in a state outside the planned set, nor explain
from one: STATE-OUTSIDE-PLANNED-SET names the spec, the state and the remedies."
  (unwind-protect
       (let ((machine (reachable-door-machine)))
         (flet ((message-of (thunk)
                  (handler-case (progn (funcall thunk) nil)
                    (state-outside-planned-set (e) (princ-to-string e)))))
           (let ((message (message-of (lambda ()
                                        (make-controller machine :initial-state '((player-user::door . player-user::locked)))))))
             (is (search "spec door has no plans from the state door=locked inside=false" message))
             (is (search "(:start-states EXPR)" message))
             (is (search "(:unplanned-states :search)" message)))
           (is (message-of (lambda () (explain-plan machine :initial '((player-user::door . player-user::locked))
                                                            :event 'player-user::go-in))))
           (is (null (message-of (lambda () (make-controller machine)))))))
    (remove-spec 'door)))

(test unplanned-states-searched-at-run-time
  "With (:unplanned-states :search) a controller started outside the planned
set searches a shortest plan, reports it as a :search line, and runs it; a
goal it cannot reach is reported :unreachable and fails as usual."
  (unwind-protect
       (let* ((machine (reachable-door-machine '(:unplanned-states :search)))
              (controller (make-controller machine :initial-state '((player-user::door . player-user::locked)))))
         (is (eq t (send-event controller 'player-user::go-in)))
         (is (equal '("(:event go-in :time 0)"
                      "(:search inside :ops (unlock open-door enter) :time 0)"
                      "(:op unlock :script unlock :start 0 :end 1)"
                      "(:op open-door :script open-door :start 1 :end 2)"
                      "(:op enter :script enter :start 2 :end 3)"
                      "(:state (door . open) (inside . t))")
                    (trace-of controller))))
    (remove-spec 'door))
  (unwind-protect
       (let* ((machine (compile-spec (define-spec 'stuck '((:state-space :reachable) (:unplanned-states :search)
                                                           (player-user::state-variable player-user::a player-user::boolean player-user::false)
                                                           (player-user::state-variable player-user::b player-user::boolean player-user::false)
                                                           (player-user::op player-user::set-a :precond (player-user::not player-user::b) :add player-user::a)
                                                           (player-user::event player-user::want-a :state player-user::a))
                                                  :package (find-package '#:player-user))))
              (controller (make-controller machine :initial-state '((player-user::b . t)))))
         (is (equal '(nil player-user::a) (multiple-value-list (send-event controller 'player-user::want-a))))
         (is (equal '("(:event want-a :time 0)" "(:search a :unreachable t :time 0)" "(:fail want-a :goal a :time 0)")
                    (butlast (trace-of controller)))))
    (remove-spec 'stuck)))

(test state-space-options-are-checked
  "Bad :state-space, :unplanned-states and :start-states options are clear spec errors."
  (flet ((message-of (options)
           (handler-case (progn (define-spec 'bad-options (append options '((player-user::state-variable player-user::x player-user::boolean player-user::false)))
                                             :package (find-package '#:player-user))
                                nil)
             (player-error (e) (list (type-of e) (princ-to-string e))))))
    (is (search "unknown :state-space value :huge (allowed: :auto, :full, :reachable)"
                (second (message-of '((:state-space :huge))))))
    (is (search "unknown :unplanned-states value maybe"
                (second (message-of '((:unplanned-states maybe))))))
    (is (search "expected (:start-states EXPR...)" (second (message-of '((:start-states))))))
    (is (search ":start-states takes state expressions; 42 is not one"
                (second (message-of '((:start-states 42))))))
    (is (search "unknown variable or state class ghost" (second (message-of '((:start-states player-user::ghost))))))
    (is (search "malformed expression" (second (message-of '((:start-states (player-user::x player-user::x)))))))
    (is (eq 'spec-syntax-error (first (message-of '((:start-states "x"))))))))

(test full-state-space-is-refused-past-the-limit
  "(:state-space :full) past *STATE-LIMIT* is STATE-SPACE-TOO-LARGE, as before the
reachable regime; :auto plans the same spec for its reachable states."
  (let ((player.planner::*state-limit* 32) (player.planner::*full-space-threshold* 32))
    (with-spec (spec wide-full (:state-space :full)
                     (state-variable a string x (x y z w)) (state-variable b string x (x y z w))
                     (state-variable c string x (x y z w)))
      (is (typep (handler-case (compile-spec spec) (player-error (e) e)) 'state-space-too-large)))
    (with-spec (spec wide-auto (state-variable a string x (x y z w)) (state-variable b string x (x y z w))
                     (state-variable c string x (x y z w)) (op o :precond a.x :add a.y))
      (is (= 2 (machine-state-count (compile-spec spec)))))))

(test check-and-plans-in-the-reachable-regime
  "CHECK-SPEC counts the planned (reachable) states, and reports those only a
:start-states expression reaches; PLANS lists a goal's table."
  (unwind-protect
       (let ((machine (reachable-door-machine '(:start-states player-user::door.locked))))
         ;; shut-door is of no use on the way in
         (is (equal '(:unused-op :unreachable-states) (mapcar #'diagnostic-kind (check-spec machine))))
         (is (search "2 of 6 states cannot be reached" (player::diagnostic-message (second (check-spec machine)))))
         (is (equal '(player-user::inside) (first (plans machine 'player-user::inside)))))
    (remove-spec 'door)))

;;; The command line

(test cli-in-the-reachable-regime
  "bin/player on a spec planned for its reachable states: `plans` says how many,
`run` from a state outside them is a one-line error with status 1."
  (multiple-value-bind (out err code) (player-command "plans" (fixture "door.lisp"))
    (is (eql 0 code) "stderr ~S" err)
    (is (search "spec door: 1 goals, 4 reachable states" out)))
  (check-cli-error 1 "spec door has no plans from the state door=locked inside=false"
                   "run" (fixture "door.lisp") "--initial" "door=locked" "--events" "go-in")
  (multiple-value-bind (out err code) (player-command "run" (fixture "door.lisp") "--events" "go-in")
    (is (eql 0 code) "stderr ~S" err)
    (is (search "(:op enter :script enter :start 1 :end 2)" out))))

;;; C++

(test c++-of-a-reachable-machine
  "The C++ backend runs a reachable machine whose one-hot state fits 64 bits
(blocks world, 3 blocks: 16 booleans, 22 reachable states) with the Lisp
trace, line for line, and one of 131 variables (five 64-bit words) too."
  (let ((problem (player-strips:blocks-world 3)))
    (unwind-protect
         (let ((machine (compile-spec (define-spec (player-strips:strips-problem-name problem)
                                          (player-strips:strips-spec-forms problem)
                                        :package (find-package '#:player-user)))))
           (is (= 22 (machine-state-count machine)))
           (is (null (compare-backends machine '() (mapcar #'first (player-strips:strips-problem-goals problem))))))
      (remove-spec (player-strips:strips-problem-name problem))))
  ;; 130 booleans and a three-valued variable: 263 one-hot bits, five words
  ;; of generated C++, planned in the reachable regime.
  (unwind-protect
       (let ((machine (compile-spec (define-spec 'token-ring (token-ring-forms 130)
                                                 :package (find-package '#:player-user)))))
         (is (= 390 (machine-state-count machine)))
         (is (search "kStateWords = 5" (player.cpp::c++-sources machine "ring" "ring")))
         ;; Built at -O0 (the same warnings, as errors): its plan function is
         ;; 1.1 MB, 390 entries of plans up to 132 ops, which g++ -O2 took 50-90 s
         ;; to compile on a cold cache, a quarter of `make test`; -O0 takes 7 s.
         ;; The optimised build of wide states is C++-WIDE's (up to three words).
         (let ((player.cpp::*c++-flags* (substitute "-O0" "-O2" player.cpp::*c++-flags* :test #'string=)))
           (is (null (compare-backends machine '() '(player-user::finish player-user::finish))))))
    (remove-spec 'token-ring)))

(test cut-ops-leave-planned-states
  "An op's :if-cut effects count among the transitions: a timed controller that
cuts it lands in a planned state (CRASHED is set by nothing else) and plans on."
  (unwind-protect
       (let* ((machine (compile-spec
                        (define-spec 'glider
                            '((:state-space :reachable)
                              (player-user::state-variable player-user::posture player-user::string player-user::stand
                               (player-user::stand player-user::fly))
                              (player-user::state-variable player-user::crashed player-user::boolean player-user::false)
                              (player-user::op player-user::take-off :precond player-user::posture.stand
                               :add player-user::posture.fly :duration 2 :interrupt :anytime
                               :if-cut (:add player-user::crashed))
                              (player-user::op player-user::land :precond player-user::posture.fly
                               :add player-user::posture.stand)
                              (player-user::op player-user::recover :precond player-user::crashed
                               :sub player-user::crashed)
                              (player-user::event player-user::ev-fly :op player-user::take-off)
                              (player-user::event player-user::ev-calm (:when-busy :preempt)
                               :state (and player-user::posture.stand (player-user::not player-user::crashed))))
                          :package (find-package '#:player-user))))
              (controller (make-controller machine :timed t)))
         ;; (stand, fly) x (crashed or not): crashed only by the cut
         (is (= 4 (machine-state-count machine)))
         (send-event controller 'player-user::ev-fly :at 0)
         (send-event controller 'player-user::ev-calm :at 1)
         (finish-events controller)
         (is (equal '((player-user::posture . player-user::stand) (player-user::crashed))
                    (controller-state controller)))
         (is (find "(:op recover" (trace-of controller) :test (lambda (a b) (search a b)))))
    (remove-spec 'glider)))

(test recompile-keeps-only-planned-states
  "Switching a controller to a redefined spec that has no plans from its state
is a STATE-TRANSFER-ERROR that changes nothing."
  (unwind-protect
       (let ((controller (make-controller (reachable-door-machine '(:start-states player-user::door.locked))
                                          :initial-state '((player-user::door . player-user::locked)))))
         (reachable-door-machine)
         (let ((e (handler-case (progn (recompile controller) nil) (player-error (e) e))))
           (is (typep e 'state-transfer-error))
           (is (search "has no plans from the state door=locked" (princ-to-string e))))
         (is (eq 'player-user::locked (state-value controller 'player-user::door))))
    (remove-spec 'door)))

(defun check-unplanned-searches (seed)
  "Plan RANDOM-SPEC SEED for its reachable states with (:unplanned-states
:search); from every third state outside them, for each goal, the run-time search
must find a valid plan of the reference's fewest ops, or none when the
reference has none. Returns (VALUES PROBLEMS CHECKED)."
  (multiple-value-bind (forms model) (random-spec seed)
    (let ((name (model-name model))
          (reachable (reference-reachable-indices model))
          (predecessors (reference-predecessors model))
          (durations (unit-durations model))
          (problems '()) (checked 0))
      (unwind-protect
           (let ((machine (plan-spec (define-spec name (list* '(:state-space :reachable)
                                                              '(:unplanned-states :search) forms)
                                                  :package (find-package '#:player-user)))))
             (dolist (event (goal-events model))
               (let* ((goal (event-goal model event))
                      (player-goal (player-goal-of-event machine (mevent-name event)))
                      (distances (reference-distances model goal :predecessors predecessors)))
                 (dotimes (index (model-state-count model))
                   ;; every third state outside the planned set
                   (when (and (not (gethash index reachable)) (zerop (mod index 3)))
                     (incf checked)
                     (let* ((start (model-index-state model index))
                            (ops (player.control::search-unplanned-plan (model-one-hot model machine start)
                                                                player-goal machine))
                            (names (and (listp ops) (mapcar #'player::op-name ops)))
                            (want (svref distances index))
                            (problem (cond ((not (eq (null want) (eq ops :none)))
                                            (format nil "searched ~S, reference ~A" ops want))
                                           (want (or (check-timed-plan model durations goal start names)
                                                     (and (/= want (length names))
                                                          (format nil "~S, the reference's has ~D ops" names want)))))))
                       (when problem
                         (push (format nil "seed ~D ~A from ~A: ~A" seed (mevent-name event)
                                       (state-text model start) problem)
                               problems))))))))
        (remove-spec name))
      (values problems checked))))

(test run-time-search-finds-shortest-plans
  "On 25 random specs, the run-time search from states outside the planned set
finds valid plans as short as the reference BFS's (or none when it has none)."
  (let ((problems '()) (checked 0))
    (loop for seed from 1 to (sweep-count 25 5)
          do (multiple-value-bind (found count) (check-unplanned-searches seed)
               (setf problems (append problems found))
               (incf checked count)))
    (is (> checked (sweep-count 500 50)))
    (is (null problems) "~D problems, the first:~{~%  ~A~}" (length problems)
        (subseq problems 0 (min 3 (length problems))))))
