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
  "Past *MACRO-BRANCH-LIMIT* branches the proof stops: under :exact planning
refuses the spec, under the default CHECK-SPEC warns instead of failing."
  (with-spec (spec exact-wake-limited
              (state-variable alert string sleep (sleep drowsy awake))
              (op stir :precond alert.sleep :add alert.drowsy)
              (op open-eyes :precond alert.drowsy :add alert.awake)
              (macro-op wake :precond (not alert.awake) :add alert.awake
                        :seq (:op stir :op open-eyes)))
    (let ((player.planner::*macro-branch-limit* 0))
      (let ((warnings (remove :inexact-macro (check-spec (compile-spec spec))
                              :key #'player::diagnostic-kind :test-not #'eq)))
        (is (= 1 (length warnings)))
        (is (search "cannot be proved exact" (player::diagnostic-message (first warnings))))))))
