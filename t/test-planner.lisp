;;;; test-planner.lisp -- plan tables, canonical goals, depth limits, diagnostics.

(in-package #:player-tests)

(def-suite* planner :in player-tests)

(defmacro with-machine ((machine name &rest forms) &body body)
  "Compile a throwaway spec NAME from FORMS into MACHINE around BODY."
  (let ((spec (gensym "SPEC")))
    `(with-spec (,spec ,name ,@forms)
       (let ((,machine (compile-spec ,spec)))
         ,@body))))

(test plans-cover-every-start-state-breadth-first
  (with-machine (m ladder
                 (state-variable rung string r0 (r0 r1 r2 r3))
                 (op up1 :precond rung.r0 :add rung.r1)
                 (op up2 :precond rung.r1 :add rung.r2)
                 (op up3 :precond rung.r2 :add rung.r3)
                 (op jump :precond rung.r0 :add rung.r2)
                 (event top :state rung.r3))
    (let ((table (plans m 'rung.r3)))
      (is (equal '((rung.r3) (rung.r2 up3) (rung.r1 up2 up3) (rung.r0 jump up3))
                 (mapcar (lambda (row) (cons (car row) (cdr row))) table)))
      (is (= 4 (machine-state-count m))))))

(test equivalent-goals-merge
  (with-machine (m merged
                 (state-variable a boolean false)
                 (state-variable b boolean false)
                 (state-class both (a b))
                 (op set-a :add a) (op set-b :add b)
                 (op needs-both :precond both)
                 (event e1 :state (a and b))
                 (event e2 :state (and b a))
                 (event e3 :state both)
                 (event e4 :op needs-both)
                 (event e5 :state (or (and a b) (and a b)))
                 (event e6 :state (not (or (not a) (not b))))
                 (event e7 :state a))
    (is (= 2 (length (machine-goals m))))
    (is (member '(and a b) (machine-goals m) :test #'equal))))

(test disjunctive-and-negative-goals
  (with-machine (m disj
                 (state-variable posture string sit (fly stand sit))
                 (op stand :precond posture.sit :add posture.stand)
                 (op fly :precond posture.stand :add posture.fly)
                 (event e :state (not posture.sit)))
    (let ((c (make-controller m)))
      (is (eq t (send-event c 'e)))
      (is (eq 'stand (state-value c 'posture)))
      (is (equal '(((not posture.sit)) (posture.sit stand)) (plans m '(not posture.sit)))))))

(test shortest-plan-is-chosen-over-declaration-order
  (with-machine (m shortest
                 (state-variable x string a (a b c d))
                 (op ab :precond x.a :add x.b)
                 (op bc :precond x.b :add x.c)
                 (op cd :precond x.c :add x.d)
                 (op ad :precond x.a :add x.d)
                 (event e :state x.d))
    (let ((c (make-controller m)))
      (send-event c 'e)
      (is (equal '("(:op ad :script ad :start 0 :end 1)")
                 (remove-if-not (lambda (l) (search "(:op" l)) (trace-of c)))))))

(test max-depth-truncates-and-is-reported
  (with-machine (m deep (:max-depth 2)
                 (state-variable x string a (a b c d))
                 (op ab :precond x.a :add x.b)
                 (op bc :precond x.b :add x.c)
                 (op cd :precond x.c :add x.d)
                 (event e :state x.d))
    (is (= 3 (length (plans m 'x.d))))
    (let ((c (make-controller m)))
      (multiple-value-bind (ok goal) (send-event c 'e)
        (is (null ok))
        (is (eq 'x.d goal))
        (is (eq 'a (state-value c 'x)))))
    (let ((kinds (mapcar #'diagnostic-kind (check-spec m))))
      (is (member :truncated kinds))
      (is (member :unreachable-goal kinds)))))

(test check-spec-reports-each-kind
  (with-machine (m diagnose
                 (state-variable posture string sit (sit stand fly))
                 (state-variable broken boolean false)
                 (op stand :precond posture.sit :add posture.stand)
                 (op never-used :precond posture.fly :add broken)
                 (op fix :must-ask t :add broken)
                 (event e :state posture.stand)
                 (event e2 :state (posture.fly and posture.sit)))
    (let* ((diagnostics (check-spec m))
           (text (format nil "~{~A~%~}" (mapcar #'diagnostic-message diagnostics))))
      (is (search "goal (posture.fly and posture.sit) is unreachable from every state" text))
      (is (search "goal posture.stand is unreachable from 2 of 6 states" text))
      (is (search "op never-used is used by no plan, event or macro-op" text))
      (is (search "op fix is used by no plan, event or macro-op (it is must-ask)" text))
      (is (search "2 of 6 states cannot be reached from the initial state" text)))))

(test clean-spec-has-no-diagnostics
  (with-machine (m clean
                 (state-variable on boolean false)
                 (op switch-on :precond (not on) :add on)
                 (op switch-off :precond on :sub on)
                 (event e-on :state on)
                 (event e-off :state (not on)))
    (is (null (check-spec m)))))

(test macro-ops-are-single-planner-steps
  (with-machine (m macro-plan
                 (state-variable alert string snore (snore awake))
                 (state-variable posture string sit (sit stand))
                 (op snort) (op exhale)
                 (macro-op hard-wake :precond alert.snore :add alert.awake :seq (:op snort :op exhale))
                 (op standup :precond (alert.awake and posture.sit) :add posture.stand)
                 (event e :state posture.stand))
    (is (equal '(hard-wake standup) (cdr (assoc '(and alert.snore posture.sit) (plans m 'posture.stand)
                                               :test #'equal))))))

(test state-space-limit-is-a-clear-error
  (let ((player.planner::*state-limit* 32))
    (with-spec (spec too-big (state-variable a string x (x y z w))
                             (state-variable b string x (x y z w))
                             (state-variable c string x (x y z w)))
      (let ((e (handler-case (progn (compile-spec spec) nil) (player-error (e) e))))
        (is (typep e 'state-space-too-large))
        (is (search "64 states, over the planner's limit of 32" (princ-to-string e)))))))

(test empty-cubes-are-empty-past-62-bits
  "LAYOUT-CUBE-EMPTY-P answers alike for a fixnum cube and a bignum one: a cube
is empty when any one variable has no value left."
  (with-machine (m wide-empty
                 (state-variable pad integer 0 #.(loop for i below 64 collect i))
                 (state-variable a boolean false)
                 (state-variable b boolean false)
                 (event e :state a))
    (let* ((spec (player::machine-spec m))
           (layout (player.planner::machine-layout m))
           (top (player.spec::top-cube spec))
           (a-field (player.spec::var-field-mask (find "A" (player.spec::spec-variables spec) :key (lambda (v) (symbol-name (player.spec::var-name v))) :test #'string=))))
      (is (not (player.planner::layout-cube-empty-p top layout)))
      (is (player.planner::layout-cube-empty-p (logandc2 top a-field) layout))
      (is (not (typep (logandc2 top a-field) 'fixnum))))))
