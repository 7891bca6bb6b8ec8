;;;; test-logic.lisp -- CTL over behaviours (src/logic/): the model checker
;;;; against brute-force enumeration of paths on random graphs, counterexamples
;;;; that are real paths, specs' behaviours, diff-graphs, and the CLI.

(in-package #:player-tests)

(def-suite* logic :in player-tests)

;;; The reference: every maximal simple path (a lasso, or ending at a dead end)

(defun reference-paths (graph node)
  "Each maximal path from NODE of GRAPH whose prefix repeats no state: (STATES
. LOOP), STATES a vector, LOOP the position the last state steps back to, or
NIL at a dead end."
  (let ((paths '()))
    (labels ((walk (path)
               (let ((next (graph-successors graph (first path))))
                 (if (null next)
                     (push (cons (coerce (reverse path) 'vector) nil) paths)
                     (dolist (s next)
                       (let ((at (position s (reverse path))))
                         (if at
                             (push (cons (coerce (reverse path) 'vector) at) paths)
                             (walk (cons s path)))))))))
      (walk (list node)))
    paths))

(defun reference-path-holds (graph path op a b weak)
  "Does the path formula (OP A B) hold along PATH (see REFERENCE-PATHS)?
OP is X, F, G or U. With WEAK, X holds on a path that stops at once (AX:
no successor contradicts it)."
  (destructuring-bind (states . loop) path
    (let ((n (length states)))
      (flet ((at (f i) (reference-holds graph (aref states i) f)))
        (ecase op
          (x (cond ((> n 1) (at a 1)) (loop (at a loop)) (t weak)))
          (f (loop for i below n thereis (at a i)))
          (g (loop for i below n always (at a i)))
          (u (loop for i below n
                   when (at b i) return t
                   unless (at a i) return nil)))))))

(defun reference-holds (graph node formula)
  "FORMULA at NODE of GRAPH by enumerating paths (independent of src/logic/):
atoms are functions of a node; E and A quantify over REFERENCE-PATHS."
  (if (functionp formula)
      (funcall formula node)
      (destructuring-bind (op &optional a b) (if (eq formula t) '(true) formula)
        (flet ((sub (f) (reference-holds graph node f))
               (paths (quantifier path-op)
                 (funcall (if (eq quantifier :e) #'some #'every)
                          (lambda (path) (reference-path-holds graph path path-op a b (eq quantifier :a)))
                          (reference-paths graph node))))
          (ecase op
            (true t)
            (not (not (sub a)))
            (and (and (sub a) (sub b)))
            (or (or (sub a) (sub b)))
            (implies (or (not (sub a)) (sub b)))
            (ex (paths :e 'x)) (ax (paths :a 'x))
            (ef (paths :e 'f)) (af (paths :a 'f))
            (eg (paths :e 'g)) (ag (paths :a 'g))
            (eu (paths :e 'u)) (au (paths :a 'u)))))))

(defun random-formula (prng depth)
  "A random CTL formula of at most DEPTH operators over atoms that are sets
of the integers below 7."
  (if (or (zerop depth) (rs-chance prng 0.2))
      (if (rs-chance prng 0.1)
          t
          (let ((set (loop for i below 7 when (rs-chance prng 0.4) collect i)))
            (lambda (node) (member node set))))
      (let ((op (rs-pick prng '(not and or implies ex ax ef af eg ag eu au))))
        (if (member op '(and or implies eu au))
            (list op (random-formula prng (1- depth)) (random-formula prng (1- depth)))
            (list op (random-formula prng (1- depth)))))))

(test ctl-matches-brute-force
  ;; On 300 random graphs of up to 6 nodes (some with dead ends), the labelling
  ;; algorithm and path enumeration agree on 3 random formulas at every node.
  (do-random-graphs (prng 300)
    (let ((graph (random-graph prng)))
      (unless (graph-empty-p graph)
        (let ((behaviour (graph-behaviour graph)))
          (dotimes (k 3)
            (let* ((formula (random-formula prng 3))
                   (sat (formula-holds-states behaviour formula)))
              (loop for node in (graph-nodes graph)
                    for i from 0
                    do (unless (eq (= 1 (sbit sat i)) (and (reference-holds graph node formula) t))
                         (fail "~S at node ~S of ~S" formula node (graph-edges graph))
                         (return))))))))))

(defun path-in-graph-p (graph counterexample behaviour)
  "Are COUNTEREXAMPLE's consecutive states (and its loop back) edges of GRAPH?"
  (let ((nodes (mapcar (lambda (i) (svref (player.logic::behaviour-states behaviour) i))
                       (counterexample-states counterexample))))
    (and (loop for (a b) on nodes while b always (graph-has-edge-p graph a b))
         (or (null (counterexample-loop counterexample))
             (graph-has-edge-p graph (car (last nodes)) (nth (counterexample-loop counterexample) nodes))))))

(test counterexamples-are-paths
  ;; A failing (AG p) ends where p fails; a failing (AF p) never meets p and
  ;; loops back or ends at a dead end; both are paths of the graph from the start.
  (do-random-graphs (prng 200)
    (let ((graph (random-graph prng)))
      (unless (graph-empty-p graph)
        (let* ((start (first (graph-nodes graph)))
               (set (loop for i below 7 when (rs-chance prng 0.6) collect i))
               (p (lambda (node) (member node set))))
          (multiple-value-bind (holds path behaviour) (verify graph `(ag ,p) :start start)
            (unless holds
              (let ((nodes (counterexample-states path)))
                (is (path-in-graph-p graph path behaviour))
                (is (equal start (svref (player.logic::behaviour-states behaviour) (first nodes))))
                (is (not (funcall p (svref (player.logic::behaviour-states behaviour) (car (last nodes)))))))))
          (multiple-value-bind (holds path behaviour) (verify graph `(af ,p) :start start)
            (unless holds
              (let ((states (mapcar (lambda (i) (svref (player.logic::behaviour-states behaviour) i))
                                    (counterexample-states path))))
                (is (path-in-graph-p graph path behaviour))
                (is (notany p states))
                (is (or (counterexample-loop path)
                        (null (graph-successors graph (car (last states))))))))))))))

(test verify-specs
  ;; The cradle spec never gets stuck and swings out; the paper's gets stuck,
  ;; and the counterexample is the path to the stuck state.
  (let ((spec (first (load-spec (checkout-file "specs/newtons-cradle.lisp")))))
    (is (verify spec '(ag (ex t))))
    (is (verify spec '(ef cradle.cs-cs-cs-rs-rs)))
    (is (verify spec '(ag (implies cradle.ls-ls-cs-cs-cs (af cradle.cs-cs-cs-rs-rs)))))
    (is (not (verify spec '(af cradle.cs-cs-cs-rs-rs))))
    (multiple-value-bind (holds path behaviour) (verify spec '(ag (not cradle.cs-cs-cs-rs-rs)))
      (is (not holds))
      (is (equal "cradle.cs-cs-cs-rs-rs" (car (last (counterexample-names behaviour path))))))
    (signals formula-error (verify spec '(ef cradle.nowhere)))
    (signals formula-error (verify spec '(ef nosuch.var)))
    (signals formula-error (verify spec '(eu cradle.cs-cs-cs-cs-cs)))
    (let ((*verify-state-limit* 3))
      (signals formula-error (verify spec '(ag (ex t))))))
  (let ((paper (first (load-spec (fixture "cradle3-paper.lisp")))))
    (multiple-value-bind (holds path behaviour) (verify paper '(ag (ex t)))
      (is (not holds))
      (is (null (player.logic::behaviour-successors-of behaviour (car (last (counterexample-states path)))))))
    (is (graph-spec-diagnostics paper))
    (is (null (graph-spec-diagnostics (first (load-spec (fixture "cradle3.lisp"))))))))

(test diff-graphs-finds-dead-ends
  (let ((paper (first (load-spec (fixture "cradle3-paper.lisp"))))
        (cradle (first (load-spec (fixture "cradle3.lisp")))))
    (let ((diff (diff-graphs cradle paper)))
      (is (not (graph-diff-consistent-p diff)))
      (is (graph-diff-dead-ends diff)))
    (let ((diff (diff-graphs paper cradle)))
      (is (null (graph-diff-dead-ends diff))))
    (is (graph-diff-consistent-p (diff-graphs cradle cradle)))
    ;; a move removed: the cradle with one edge restricted away
    (let* ((graph (spec->graph cradle))
           (edge (first (graph-edges graph)))
           (smaller (make-graph (graph-nodes graph) (remove edge (graph-edges graph) :test #'equal))))
      (is (equal (list (cons (player.logic::node-name (car edge)) (player.logic::node-name (cdr edge))))
                 (mapcar (lambda (m) m) (graph-diff-removed (diff-graphs graph smaller))))))))

(test verify-graph-cli
  (multiple-value-bind (out err code)
      (player-command "verify-graph" "specs/newtons-cradle.lisp" "--formula" "(AG (EX t))")
    (is (= 0 code) "~A" err)
    (is (search "holds: (ag (ex t))" (string-downcase out))))
  (let ((dot (namestring (merge-pathnames "player-verify-test.dot" (uiop:temporary-directory)))))
    (multiple-value-bind (out err code)
        (player-command "verify-graph" "specs/newtons-cradle.lisp" "--formula" "(AF cradle.cs-cs-cs-rs-rs)"
                        "--dot" dot)
      (is (= 1 code))
      (is (search "player: error: " err))
      (is (search "then back to" out))
      (is (search "digraph" (alexandria:read-file-into-string dot)))
      (ignore-errors (delete-file dot))))
  (check-cli-error 1 "cradle.nowhere" "verify-graph" "specs/newtons-cradle.lisp" "--formula" "(EF cradle.nowhere)")
  (check-cli-error 2 "--formula" "verify-graph" "specs/newtons-cradle.lisp" "--formula" "(AG")
  (multiple-value-bind (out err code) (player-command "check" (fixture "cradle3-paper.lisp"))
    (is (= 1 code))
    (is (search "player: error: check found" err))
    (is (search "gets stuck" out) "~A" out))
  (check-cli-error 1 "inconsistent" "diff-graphs" (fixture "cradle3.lisp") (fixture "cradle3-paper.lisp"))
  (multiple-value-bind (out err code) (player-command "diff-graphs" (fixture "cradle3.lisp") (fixture "cradle3.lisp"))
    (declare (ignore err))
    (is (= 0 code))
    (is (search "same behaviour" out))))
