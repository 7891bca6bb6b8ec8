;;;; test-compose-specs.lisp -- specs and graphs both ways: SPEC->GRAPH,
;;;; GRAPH->SPEC of it, products of specs, and a defspec's (:graph EXPR)
;;;; option (interpreted data, located errors, no code run).

(in-package #:player-tests)

(in-suite compose)

;;; SPEC->GRAPH

(defun goal-form-of-state (state spec)
  "The state expression that holds exactly in the one-hot STATE of SPEC."
  (cons 'and (loop for (var . index) in (player.spec::state-assignments state spec)
                   collect (if (eq (player.spec::var-kind var) :boolean)
                               (if (= index 1) (player.spec::var-name var) (list 'not (player.spec::var-name var)))
                               (intern (format nil "~A.~A" (symbol-name (player.spec::var-name var))
                                               (symbol-name (svref (player.spec::var-domain var) index)))
                                       '#:player-user)))))

(defun plan-length (machine goal-form state)
  "How many ops MACHINE's plan for GOAL-FORM runs from the one-hot STATE, or NIL."
  (let ((plan (player.inspect::state-plan (player.inspect::find-or-plan-goal machine goal-form) state)))
    (and plan (length (player.planner::plan-ops plan)))))

(defun node-state (spec variable node-name)
  "The one-hot state of SPEC (made by GRAPH->SPEC) whose VARIABLE holds NODE-NAME."
  (let ((var (find variable (player.spec::spec-variables spec) :key #'player.spec::var-name :test #'string-equal)))
    (player.spec::var-value-bit var (position node-name (player.spec::var-domain var) :test #'string-equal))))

(defun check-round-trip (spec)
  "GRAPH->SPEC of SPEC->GRAPH of SPEC plans, between every two states reachable
from the initial state, plans as long as SPEC's (none where SPEC has none)."
  (let* ((graph (spec->graph spec))
         (machine (compile-spec spec))
         (layout (player.planner::make-layout spec))
         (states (loop for dense below (player.planner::layout-state-count layout)
                       for state = (player.planner::dense-to-state dense layout)
                       when (graph-has-node-p graph (player.compose::state-node state spec)) collect state))
         (copy (graph->spec graph 'compose-round-trip :start (player.compose::state-node (player.planner::initial-state spec) spec)))
         (copy-machine (compile-spec copy)))
    (unwind-protect
         (progn
           (is (= (graph-node-count graph) (length states)))
           (dolist (to states)
             (let ((goal (goal-form-of-state to spec))
                   (copy-goal (intern (format nil "NODE.~A" (player.compose::default-node-name (player.compose::state-node to spec)))
                                      '#:player-user)))
               (dolist (from states)
                 (is (eql (plan-length machine goal from)
                          (plan-length copy-machine copy-goal
                                       (node-state copy "NODE" (player.compose::default-node-name (player.compose::state-node from spec)))))
                     "~A: from ~S to ~S" (spec-name spec) (player.compose::state-node from spec) (player.compose::state-node to spec))))))
      (remove-spec 'compose-round-trip))))

(defspec compose-lamp
  (state-variable on boolean false)
  (state-variable colour string red (red green blue))
  (op switch-on :precond (not on) :add on)
  (op switch-off :precond on :sub on)
  (op paint-green :precond (not on) :add colour.green)
  (op paint-blue :precond colour.green :add colour.blue)
  (op touch-up :precond colour.blue)           ; no effect: never an edge
  (op hidden :must-ask t :add colour.red)       ; must-ask: not the planner's
  (event ev-blue :state colour.blue))

(defspec compose-door
  (state-variable door string shut (shut open locked broken))
  (op open-door :precond door.shut :add door.open)
  (op close-door :precond door.open :add door.shut)
  (op lock :precond door.shut :add door.locked)
  (op stay :precond door.open :add door.open))

(test spec-graph-nodes-and-labels
  (multiple-value-bind (graph labels) (spec->graph 'compose-lamp)
    ;; from (off, red): on/off, and painting while off
    (is (= 6 (graph-node-count graph)))
    (is (graph-has-node-p graph '(false . red)))
    (is (graph-has-edge-p graph '(false . red) '(true . red)))
    (is (equal '(switch-on) (gethash '((false . red) . (true . red)) labels)))
    (is (graph-has-edge-p graph '(false . blue) '(true . blue))))
  (multiple-value-bind (graph labels) (spec->graph 'compose-door)
    (is (equal '("LOCKED" "OPEN" "SHUT") (sort (mapcar #'symbol-name (graph-nodes graph)) #'string<)))
    ;; an op that changes nothing is a loop
    (is (graph-has-edge-p graph 'open 'open))
    (is (equal '(stay) (gethash '(open . open) labels)))
    (is (= 4 (graph-edge-count graph))))
  ;; nothing breaks the door: only :all has BROKEN
  (is (= 4 (graph-node-count (spec->graph 'compose-door :from :all))))
  (signals argument-error (spec->graph 'compose-door :from :everything))
  (signals player-error (spec->graph 'compose-no-such-spec)))

(test spec-graph-round-trip-plans
  (check-round-trip (find-spec 'compose-lamp))
  (check-round-trip (find-spec 'compose-door))
  (check-round-trip (first (load-spec (checkout-file "specs/peedy.lisp"))))
  (remove-spec 'peedy))

(test spec-graph-products
  (let* ((lamp (spec->graph 'compose-lamp))
         (door (spec->graph 'compose-door))
         (both (graph-product lamp door)))
    (is (= (* (graph-node-count lamp) (graph-node-count door)) (graph-node-count both)))
    (is (= (* (graph-edge-count lamp) (graph-edge-count door)) (graph-edge-count both)))
    ;; the product as a spec: both move at each step, so the door's loop at open lets
    ;; the lamp move alone
    (let ((spec (graph->spec both 'compose-both :start '((false . red) . shut))))
      (unwind-protect
           (let ((controller (make-controller (compile-spec spec))))
             (is (eq t (send-event controller (intern "GO-<<TRUE_BLUE>_OPEN>" '#:player-user))))
             (is (string= "<<TRUE_BLUE>_OPEN>" (symbol-name (state-value controller 'node)))))
        (remove-spec 'compose-both)))))

;;; (:graph EXPR)

(defun graph-spec-text (option &rest forms)
  "A spec file's text: defspec compose-graph with OPTION on its third line, then FORMS."
  (with-output-to-string (out)
    (format out "(in-package :player-user)~%(defspec compose-graph~%  ~S~{~%  ~S~})~%" option forms)))

(defun call-with-graph-spec-file (text function)
  "Call FUNCTION with the path of a temporary spec file holding TEXT."
  (uiop:with-temporary-file (:pathname path :stream out :type "lisp")
    (write-string text out)
    :close-stream
    (funcall function path)))

(defun load-graph-spec-text (text)
  "Load TEXT as a spec file with code refused; the spec."
  (call-with-graph-spec-file text (lambda (path) (first (load-spec path :allow-code nil)))))

(defun graph-option-error (option)
  "The GRAPH-EXPRESSION-ERROR's report loading a spec file with OPTION gives
\(while the file is there, so the report can name its line), or NIL."
  (call-with-graph-spec-file (graph-spec-text option)
                             (lambda (path)
                               (handler-case (progn (load-spec path :allow-code nil) nil)
                                 (graph-expression-error (condition) (princ-to-string condition))))))

(test graph-option-file-plans-and-runs
  (let* ((spec (first (load-spec (checkout-file "t/fixtures/cradle-graph.lisp") :allow-code nil)))
         (controller (make-controller (compile-spec spec))))
    (unwind-protect
         (progn
           (is (eq t (send-event controller 'ev-release)))
           (let ((ops (loop for line in (trace-lines (controller-presenter controller))
                            when (eq (first line) :op) collect (symbol-name (second line)))))
             (is (equal '("FROM-LS-CS-CS-TO-LE-CS-CS" "FROM-LE-CS-CS-TO-CE-CS-CS" "FROM-CE-CS-CS-TO-CS-CS-CE"
                          "FROM-CS-CS-CE-TO-CS-CS-RE" "FROM-CS-CS-RE-TO-CS-CS-RS")
                        ops)))
           (is (string= "CS-CS-RS" (symbol-name (state-value controller 'cradle))))
           ;; the ops are exactly GRAPH->SPEC's: one per edge of G^3
           (is (= (graph-edge-count (newton-cradle 3)) (length (player.spec::spec-ops spec))))
           (is (= (1- (graph-node-count (newton-cradle 3))) (player::spec-max-depth spec))))
      (remove-spec 'cradle-3))))

(test graph-option-expressions
  (flet ((spec-of (option &rest forms)
           (prog1 (load-graph-spec-text (apply #'graph-spec-text option forms))
             (remove-spec 'compose-graph))))
    ;; the paper's product and restriction, patterns with wildcard, pairs and =>
    (let ((spec (spec-of '(:graph (restrict (product (complete (-1 0 1)) (complete (a b)))
                                   (=> (0 . _) (_ . 'a)))
                           :start (0 . a))
                         '(event ev-go :state node.<m1_b>))))
      (is (= 6 (length (player.spec::var-domain (first (player.spec::spec-variables spec))))))
      (is (= 5 (player::spec-max-depth spec))))
    ;; a registered graph, sums and merges, :eval with -
    (register-graph 'compose-line (make-graph '() '(((0 . 1) . (1 . 2)) ((1 . 2) . (2 . 3)))))
    (let ((spec (spec-of '(:graph (merge compose-line compose-line) :go-events false))))
      (is (= 1 (length (player.spec::spec-ops spec)))))
    (let ((spec (spec-of '(:graph (restrict (complete (-1 0 1)) (then x (:eval - x))) :go-events false))))
      (is (= 3 (length (player.spec::spec-ops spec)))))
    (let ((spec (spec-of '(:graph (sum (graph (a) ()) (graph () ((a . b)))) :variable v) '(:max-depth 3))))
      (is (= 3 (player::spec-max-depth spec)))
      (is (string-equal "V" (player.spec::var-name (first (player.spec::spec-variables spec))))))
    ;; specs defined before, combined: the door and the lamp at once
    (let ((spec (spec-of '(:graph (product (spec compose-door) (spec compose-lamp))))))
      (is (= (* (graph-node-count (spec->graph 'compose-door)) (graph-node-count (spec->graph 'compose-lamp)))
             (length (player.spec::var-domain (first (player.spec::spec-variables spec)))))))
    ;; graphs too large are refused before they are built
    (let ((player.compose::*graph-expression-edge-limit* 1000)
          (lefts (loop for i from 1 to 20 collect (cons i 0)))
          (rights (loop for i from 1 to 20 collect (cons 0 i))))
      (signals graph-expression-error (spec-of `(:graph (merge (complete ,lefts) (complete ,rights)))))
      (signals graph-expression-error (spec-of `(:graph (product (complete ,lefts) (complete ,rights)))))
      (signals graph-expression-error (spec-of `(:graph (complete ,(loop for i below 40 collect i))))))))

(test graph-option-errors-are-located
  (flet ((check (option &rest words)
           (let ((message (graph-option-error option)))
             (is-true message "~S loaded" option)
             (when message
               ;; file and line: the option is on line 3
               (is (search ".lisp:3:" message) "~A" message)
               (dolist (word words)
                 (is (search word message :test #'char-equal) "~S not in ~A" word message))))))
    (check '(:graph (explode 3)) "unknown graph builder" "explode")
    (check '(:graph (restrict (complete (1 2)) (then 7 _))) "7" "matches no node")
    (check '(:graph (restrict (complete (1 2)) (then x (:eval run-program x)))) "run-program")
    (check '(:graph (newton-cradle 99)) "newton-cradle")
    (check '(:graph no-such-graph) "no-such-graph")
    (check '(:graph (complete (1 2)) :start 5) ":start")
    (check '(:graph (complete (1 2)) :colour red) ":colour")
    (check '(:graph (product (complete (1 2)))) "product")))

(defvar *graph-option-ran* nil "Set by code a graph expression must never run.")

(test graph-option-runs-no-code
  (setf *graph-option-ran* nil)
  (dolist (option '((:graph (progn (setf player-tests::*graph-option-ran* t))) ; not a builder
                    (:graph (restrict (complete (1 2))
                                      (then x (:eval player-tests::note-ran x))))
                    (:graph (complete ((:eval player-tests::note-ran 1))))))
    (graph-option-error option))
  (is (null *graph-option-ran*))
  ;; a spec file with (:graph ...) loads with code refused
  (is (player.spec::spec-p (first (load-spec (checkout-file "t/fixtures/cradle-graph.lisp") :allow-code nil))))
  (remove-spec 'cradle-3))

(defun note-ran (&rest arguments)
  "Record that a graph expression ran code."
  (declare (ignore arguments))
  (setf *graph-option-ran* t))
