;;;; test-macro-exactness.lisp -- (:macros :exact): the state after a macro-op
;;;; is what its :seq produced, proved at planning time to be the state the
;;;; planner assumed; and the proof against state-by-state simulation.

(in-package #:player-tests)

(def-suite* macro-exactness :in player-tests)

(test exact-macro-passes-and-keeps-its-sub-ops-state
  ;; wake's :seq plans its way to alert.awake and perks the head, both of
  ;; which it declares: exact from every start state.
  (with-spec (spec exact-wake
              (:macros :exact)
              (state-variable alert string sleep (sleep drowsy awake))
              (state-variable head string down (down up))
              (op stir :precond alert.sleep :add alert.drowsy)
              (op open-eyes :precond alert.drowsy :add alert.awake)
              (op perk :add head.up)
              (macro-op wake :precond (not alert.awake) :add (alert.awake head.up)
                        :seq (:op stir :op open-eyes :op perk))
              (event ev-wake :op wake))
    (let* ((machine (compile-spec spec))
           (controller (make-controller machine)))
      (is (null (player.planner::inexact-macros machine)))
      (is (eq t (send-event controller 'ev-wake)))
      (is (eq 'awake (state-value controller 'alert)))
      (is (eq 'up (state-value controller 'head))))))

(defmacro with-inexact-macro-spec ((spec semantics) &body body)
  "SPEC: a macro whose :seq turns the light on without declaring it, under SEMANTICS."
  `(with-spec (,spec leaky
               (:macros ,semantics)
               (state-variable light boolean false)
               (state-variable door string shut (shut open))
               (op switch-on :add light)
               (op push-door :add door.open)
               (macro-op enter :precond door.shut :add door.open
                         :seq (:op switch-on :op push-door))
               (event ev-enter :op enter))
     ,@body))

(test inexact-macro-is-refused-with-a-witness
  (with-inexact-macro-spec (spec :exact)
    (let ((error (handler-case (progn (compile-spec spec) nil)
                   (player-error (e) e))))
      (is (typep error 'player.base::inexact-macro-error))
      (let ((message (princ-to-string error)))
        (is (search "macro-op enter: not exact" message))
        ;; The witness: the light was off, the :seq leaves it on.
        (is (search "(not light)" message))
        (is (search "leaves light" message))))))

(test inexact-macro-under-the-default-is-a-check-warning
  (with-inexact-macro-spec (spec :declared)
    (let* ((machine (compile-spec spec))
           (diagnostics (remove :inexact-macro (check-spec machine)
                                :key #'player::diagnostic-kind :test-not #'eq)))
      (is (= 1 (length diagnostics)))
      (is (search "macro-op enter is not exact" (player::diagnostic-message (first diagnostics))))
      ;; The paper's semantics: the light flips back when the macro ends.
      (let ((controller (make-controller machine)))
        (is (eq t (send-event controller 'ev-enter)))
        (is (null (state-value controller 'light)))))))

(test unknown-macro-semantics-is-an-error
  (signals player::spec-syntax-error
    (player.spec::parse-spec 'bad-macros '((:macros :sloppy) (state-variable a boolean false)))))

(test exactness-error-names-the-file-and-line
  (let ((path (merge-pathnames "leaky-macro.lisp" (uiop:temporary-directory))))
    (with-open-file (out path :direction :output :if-exists :supersede)
      (format out "(defspec leaky-file~%  (:macros :exact)~%  (state-variable light boolean false)~%  (op switch-on :add light)~%  (op flip :sub light)~%  (macro-op twiddle :precond (not light)~%    :seq (:op switch-on)))~%"))
    (unwind-protect
         (let ((message (handler-case (progn (compile-spec (first (load-spec path))) nil)
                          (player-error (e) (princ-to-string e)))))
           (is (search "leaky-macro.lisp:6:" message))
           (is (search "twiddle" message)))
      (delete-file path))))

;;; The proof against simulation, state by state.

(defun form-named-p (form name)
  "Is FORM a list whose head is the symbol named NAME?"
  (and (consp form) (symbolp (first form)) (string= (symbol-name (first form)) name)))

(defun planning-macro-forms (seed)
  "A random spec's forms whose macro-ops' :seq runs 1-3 of its plain ops,
preconditions and all, so the controller plans inside the macro."
  (let* ((forms (random-spec seed :macro-count 2 :max-variables 5 :max-states 300 :max-depth 30))
         (prng (make-rs-prng (+ 7919 seed)))
         (names (loop for form in forms
                      when (and (form-named-p form "OP") (not (member :must-ask form)))
                        collect (second form))))
    (mapcar (lambda (form)
              (if (and names (form-named-p form "MACRO-OP"))
                  (let ((head (subseq form 0 (position :seq form))))
                    (append head (list :seq (loop repeat (rs-between prng 1 3)
                                                  nconc (list :op (rs-pick prng names))))))
                  form))
            forms)))

(defun state-after-sub-op (state op)
  "The one-hot STATE after OP's effects (a macro's declared ones)."
  (logior (logandc2 state (player.spec::op-effect-mask op)) (player.spec::op-effect-bits op)))

(defun simulate-seq (macro machine state)
  "The one-hot state MACRO's :seq leaves from STATE, achieving each sub-op's
precondition by the first plan whose condition holds, or NIL when one fails."
  (dolist (directive (player.spec::op-seq macro) state)
    (when (eq (first directive) :op)
      (let ((sub (second directive)))
        (when (player.spec::op-precond sub)
          (let* ((goal (player.planner::machine-goal-for machine (player.spec::op-precond sub)))
                 (plan (find-if (lambda (plan) (player.spec::state-in-cube-p state (player.planner::plan-condition plan)))
                                (player.planner::goal-plans goal))))
            (unless plan (return nil))
            (dolist (op (player.planner::plan-ops plan))
              (setf state (state-after-sub-op state op)))))
        (setf state (state-after-sub-op state sub))))))

(defun brute-force-exact-p (macro machine)
  "Is MACRO exact, checked on every state of MACHINE's spec where its precondition holds?"
  (let* ((layout (player.planner::machine-layout machine))
         (spec (player::machine-spec machine))
         (pre (player.spec::expression-cubes (player.spec::op-precond macro) spec))
         (declared (player.spec::op-effect-mask macro)))
    (loop for dense below (player.planner::layout-state-count layout)
          for state = (player.planner::dense-to-state dense layout)
          for after = (and (some (lambda (cube) (player.spec::state-in-cube-p state cube)) pre)
                           (simulate-seq macro machine state))
          never (and after (/= (logandc2 after declared) (logandc2 state declared))))))

(test exactness-proof-agrees-with-simulation-on-random-specs
  ;; The cube proof and the state-by-state simulation must agree on every
  ;; macro of 150 random specs whose macros plan inside (so the proof splits
  ;; start states by the plans the controller would run).
  (let ((macros 0) (inexact 0))
    (loop for seed from 1 to 150
          for name = (rs-symbol "exactness-~D" seed)
          for spec = (ignore-errors (define-spec name (planning-macro-forms seed)
                                                 :package (find-package '#:player-tests)))
          for machine = (and spec (ignore-errors (compile-spec spec)))
          when machine
            do (dolist (op (player.spec::spec-ops spec))
                 (when (eq (player::op-kind op) :macro)
                   (incf macros)
                   (let ((proved (null (player.planner::macro-inexactness op machine))))
                     (unless proved (incf inexact))
                     (is (eq (brute-force-exact-p op machine) proved)
                         "seed ~D, macro ~A: the proof says ~:[inexact~;exact~]"
                         seed (player::op-name op) proved))))
          do (when spec (remove-spec name)))
    (is (> macros 100))
    (is (< 0 inexact macros))))

(test a-macro-the-proof-gives-up-on-is-a-check-warning
  "Past *MACRO-PROOF-BUDGET* steps the proof stops: under :exact planning
refuses the spec, under the default CHECK-SPEC warns instead of failing."
  (with-spec (spec exact-wake-limited
              (state-variable alert string sleep (sleep drowsy awake))
              (op stir :precond alert.sleep :add alert.drowsy)
              (op open-eyes :precond alert.drowsy :add alert.awake)
              (macro-op wake :precond (not alert.awake) :add alert.awake
                        :seq (:op stir :op open-eyes)))
    (let ((player.planner::*macro-proof-budget* 0))
      (let ((warnings (remove :inexact-macro (check-spec (compile-spec spec))
                              :key #'player::diagnostic-kind :test-not #'eq)))
        (is (= 1 (length warnings)))
        (is (search "cannot be proved exact" (player::diagnostic-message (first warnings))))))))

;;; The proof's budget: counted as it goes, shared, naming the chain.

(defun splitting-macro-spec (steps values &key (semantics :exact) (name "split") (tail 0) (copies 1) wrappers)
  "A spec whose macro-op M runs STEPS sub-ops USE<i> (then TAIL ticks); each
one's precondition X<i> is achieved by one of VALUES ops VIA<i>-<v>, chosen by
the value of A<i>, so the exactness proof splits M's start states VALUES ways
at every sub-op: VALUES^STEPS cases, over 2 (2 VALUES)^STEPS states.  COPIES
more of M (M2, ...) share the proof's budget; WRAPPERS adds MID running M and
TOP running MID."
  (with-output-to-string (s)
    (format s "(defspec ~A (:macros :~(~A~))~%" name semantics)
    (loop for i from 1 to steps
          do (format s "  (state-variable a~D string v0 (~{v~D~^ ~}))~%" i (loop for v below values collect v))
             (format s "  (state-variable x~D boolean false)~%" i)
             (loop for v below values do (format s "  (op via~D-~D :precond a~D.v~D :add x~D)~%" i v i v i))
             (format s "  (op use~D :precond x~D :sub x~D)~%" i i i))
    (format s "  (state-variable y boolean false)~%  (op tick :add y)~%")
    (loop for copy from 1 to copies
          do (format s "  (macro-op m~@[~D~] :precond (and (not y)~{ (not x~D)~}) :add y~%    :seq (~{:op use~D~^ ~}~{ :op ~A~}))~%"
                     (and (> copy 1) copy) (loop for i from 1 to steps collect i) (loop for i from 1 to steps collect i)
                     (loop repeat tail collect "tick")))
    (when wrappers
      (format s "  (state-variable z boolean false)~%  (state-variable w boolean false)~%")
      (format s "  (macro-op mid :precond (and (not z) (not y)~{ (not x~D)~}) :add (z y) :seq (:op m))~%"
              (loop for i from 1 to steps collect i))
      (format s "  (macro-op top :precond (and (not w) (not z) (not y)~{ (not x~D)~}) :add (w z y) :seq (:op mid))~%"
              (loop for i from 1 to steps collect i)))
    (format s "  (event ev :op m))~%")))

(defun proof-failure (text &key (budget player.planner::*macro-proof-budget*))
  "The message of planning the spec file TEXT under a proof BUDGET, or NIL when it plans."
  (let ((player.planner::*macro-proof-budget* budget))
    (handler-case (progn (compile-spec (first (load-spec (scratch-file text :name "proof")))) nil)
      (player-error (e) (princ-to-string e)))))

(defun proof-steps (text)
  "How many steps the exactness proof of the spec file TEXT takes."
  (let* ((spec (first (load-spec (scratch-file text :name "proof"))))
         (machine (progn (setf (getf (player.spec::spec-options spec) :macros) :declared)
                         (compile-spec spec)))
         (player.planner::*proof-steps-left* most-positive-fixnum))
    (is (null (player.planner::inexact-macros machine)))
    (- most-positive-fixnum player.planner::*proof-steps-left*)))

(test the-proof-budget-names-the-chain
  ;; 8, 64, 512 cases: a budget of 1,000 steps runs out at the third sub-op.
  (let ((message (proof-failure (splitting-macro-spec 3 8 :wrappers t) :budget 1000)))
    (is (search "proof.lisp:" message) "~A" message)
    (is (search "macro-op m: cannot be proved exact within 1,000 steps" message) "~A" message)
    (is (search "run by top -> mid, its :seq splits its start states at use1 (8 cases), use2 (64 cases)" message)
        "~A" message)
    (is (search "and was at sub-op use3; split it into smaller macro-ops" message) "~A" message))
  ;; The same spec within the default budget is exact.
  (is (null (proof-failure (splitting-macro-spec 3 8 :wrappers t)))))

(test macro-proofs-share-one-budget
  ;; One macro fits in a budget of 1.5 times its steps; two identical ones
  ;; do not, and the second is the one named.
  (let* ((steps (proof-steps (splitting-macro-spec 3 6)))
         (budget (floor (* 3 steps) 2)))
    (is (< 100 steps 10000) "~D steps" steps)
    (is (null (proof-failure (splitting-macro-spec 3 6) :budget budget)))
    (let ((message (proof-failure (splitting-macro-spec 3 6 :copies 2) :budget budget)))
      (is (search "macro-op m2: cannot be proved exact" message) "~A" message))))

(test the-proof-stops-when-the-budget-is-spent
  ;; Every step is paid before it is taken: the steps spent never pass the
  ;; budget, whether the cases multiply (3 x 40 values) or a long :seq
  ;; walks many cases (3 x 8 values, then 2,000 ticks).
  (dolist (text (list (splitting-macro-spec 3 40) (splitting-macro-spec 3 8 :tail 2000)))
    (let* ((spec (first (load-spec (scratch-file text :name "proof"))))
           (machine (progn (setf (getf (player.spec::spec-options spec) :macros) :declared)
                           (compile-spec spec)))
           (player.planner::*macro-proof-budget* 20000)
           (left nil))
      (handler-case (handler-bind ((player.base::inexact-macro-error
                                     (lambda (e) (declare (ignore e)) (setf left player.planner::*proof-steps-left*))))
                      (player.planner::inexact-macros machine)
                      (is nil "the proof did not stop"))
        (player.base::inexact-macro-error (e)
          (is (search "within 20,000 steps" (princ-to-string e)))))
      ;; What was spent past the budget is the one payment that passed it.
      (is (<= -3000 left -1) "~A steps left" left))))
