;;;; test-dot.lisp -- `player dot` and WRITE-STATE-GRAPH: the plannable state
;;;; graph as Graphviz.  Its nodes and edges are counted in the DOT text and
;;;; checked against an enumeration of states and ops done here (every
;;;; assignment of values, each op's effects applied by hand), and, when
;;;; Graphviz is installed, against the node groups of the SVG `dot -Tsvg`
;;;; draws from it.

(in-package #:player-tests)

(def-suite* dot :in player-tests)

;;;# Counting in DOT and SVG text

(defun dot-statements (dot prefix &key edges)
  "The node statements (or with EDGES the edge statements) of the part of the
DOT text named by PREFIX (\"s\": the op graph, \"p\": the plan tree): lines
`  s12 [...]`, or `  s12 -> s13 [...]`."
  (remove-if-not (lambda (line)
                   (let ((text (string-left-trim " " line)))
                     (and (> (length text) 1)
                          (string= prefix (subseq text 0 1))
                          (digit-char-p (char text 1))
                          (if edges (search " -> " text) (not (search " -> " text))))))
                 (lines dot)))

(defun count-dot (dot prefix &key edges)
  "How many node (or edge) statements the DOT part PREFIX has."
  (length (dot-statements dot prefix :edges edges)))

(defun statement-node (statement)
  "The first node name of a DOT STATEMENT line."
  (let ((text (string-left-trim " " statement)))
    (subseq text 0 (position-if (lambda (c) (member c '(#\Space #\;))) text))))

(defun count-occurrences (needle haystack)
  "How many times NEEDLE occurs in HAYSTACK."
  (loop for start = (search needle haystack) then (search needle haystack :start2 (1+ start))
        while start count t))

(defun dot-installed-p ()
  "Is Graphviz's dot program on PATH?"
  (player.base::find-executable "dot"))

(defun render-svg (dot)
  "The SVG `dot -Tsvg` draws from the DOT text, and its exit code."
  (let* ((out (make-string-output-stream))
         (process (sb-ext:run-program "dot" '("-Tsvg") :search t :output out :error nil
                                                       :input (make-string-input-stream dot))))
    (values (get-output-stream-string out) (sb-ext:process-exit-code process))))

;;;# The graph counted here: every assignment, each op applied by hand

(defun enumerate-assignments (spec)
  "Every assignment of values to SPEC's plannable variables, each a list of
value indices in declaration order."
  (let ((assignments (list '())))
    (dolist (var (reverse (player.spec::plannable-variables spec)) assignments)
      (setf assignments (loop for index below (length (player.spec::var-domain var))
                              nconc (mapcar (lambda (rest) (cons index rest)) assignments))))))

(defun assignment-state (spec assignment)
  "ASSIGNMENT as the one-hot state the planner uses."
  (loop for var in (player.spec::plannable-variables spec)
        for index in assignment
        sum (ash 1 (+ (player.spec::var-bit-offset var) index))))

(defun holds-in-p (ast spec assignment)
  "Does the parsed state expression AST (NIL: no condition) hold in ASSIGNMENT?"
  (or (null ast)
      (let ((state (assignment-state spec assignment)))
        (some (lambda (cube) (zerop (logandc2 state cube))) (player.spec::expression-cubes ast spec)))))

(defun apply-op (spec op assignment)
  "ASSIGNMENT with OP's effects set."
  (let ((vars (player.spec::plannable-variables spec)))
    (loop for var in vars
          for index in assignment
          collect (let ((effect (assoc var (player.spec::op-effects op))))
                    (if effect (cdr effect) index)))))

(defun spec-ops-with-effects (spec)
  "SPEC's ops that set some variable."
  (remove nil (player.spec::spec-ops spec) :key #'player.spec::op-effects))

(defun counted-op-edges (spec)
  "(VALUES EDGES MUST-ASK-EDGES): how many (assignment, op) pairs of SPEC have
the op's precondition hold and its effects change the assignment."
  (let ((edges 0) (must-ask 0))
    (dolist (assignment (enumerate-assignments spec))
      (dolist (op (spec-ops-with-effects spec))
        (when (and (holds-in-p (player.spec::op-precond op) spec assignment)
                   (not (equal assignment (apply-op spec op assignment))))
          (incf edges)
          (when (player.spec::op-must-ask op) (incf must-ask)))))
    (values edges must-ask)))

(defun counted-goal-states (spec goal-form)
  "How many assignments of SPEC satisfy GOAL-FORM."
  (let ((ast (let ((player.spec::*spec* spec)) (player.spec::parse-expression goal-form))))
    (count-if (lambda (assignment) (holds-in-p ast spec assignment)) (enumerate-assignments spec))))

(defun goal-distances (spec goal-form)
  "A hash table from each assignment (a list) of SPEC to the fewest plan
operators (ops not must-ask, macro-ops) leading it into GOAL-FORM; absent
when none do.  Breadth first, backwards from the goal's assignments."
  (let* ((ast (let ((player.spec::*spec* spec)) (player.spec::parse-expression goal-form)))
         (assignments (enumerate-assignments spec))
         (ops (remove-if #'player.spec::op-must-ask (spec-ops-with-effects spec)))
         (distance (make-hash-table :test 'equal))
         (frontier (remove-if-not (lambda (a) (holds-in-p ast spec a)) assignments)))
    (dolist (a frontier) (setf (gethash a distance) 0))
    (loop for d from 1
          while frontier
          do (setf frontier
                   (loop for a in assignments
                         unless (gethash a distance)
                           when (some (lambda (op)
                                        (and (holds-in-p (player.spec::op-precond op) spec a)
                                             (eql (gethash (apply-op spec op a) distance) (1- d))))
                                      ops)
                             collect a))
             (dolist (a frontier) (setf (gethash a distance) d)))
    distance))

;;;# Specs

(defun dot-peedy ()
  "specs/peedy.lisp's spec, loaded afresh."
  (first (load-spec (checkout-file "specs/peedy.lisp"))))

(defmacro with-lamp-spec ((var) &body body)
  "Run BODY with VAR bound to a small spec: lamp (off, dim and a value holding
a double quote and a backslash) times door (a boolean), 6 states.  By hand:
dim leads off->dim (2 edges), off leads every lamp but off to off (4), open
shuts->open (3), must-ask slam open->shut (3): 12 edges, 3 dashed."
  `(with-spec (,var dot-lamp
                    (state-variable lamp string off (off dim "a\"b\\c"))
                    (state-variable door boolean false)
                    (op dim :precond lamp.off :add lamp.dim)
                    (op off :add lamp.off)
                    (op open :precond (not door) :add door)
                    (op slam :must-ask true :sub door)
                    (event ev-dim :state lamp.dim))
     ,@body))

(defun graph-text (machine &rest keys)
  "WRITE-STATE-GRAPH's DOT text for MACHINE with KEYS."
  (with-output-to-string (out) (apply #'write-state-graph machine out keys)))

;;;# The small spec, counted by hand

(test lamp-graph-counted-by-hand
  (with-lamp-spec (spec)
    (let ((dot (graph-text spec)))
      (is (= 6 (count-dot dot "s")))
      (is (= 12 (count-dot dot "s" :edges t)))
      (is (= 3 (count-if (lambda (s) (search "style=dashed" s)) (dot-statements dot "s" :edges t))))
      (is (equal '("slam") (remove-duplicates
                            (loop for s in (dot-statements dot "s" :edges t)
                                  when (search "style=dashed" s)
                                    collect (subseq s (+ 7 (search "label=\"" s)) (search "\", style" s)))
                            :test #'string=)))
      (is (= 0 (count-dot dot "p")) "no plan tree without a goal")
      ;; the initial state, lamp=off and door=false, has the double border
      (let ((initial (remove-if-not (lambda (s) (search "peripheries=2" s)) (dot-statements dot "s"))))
        (is (= 1 (length initial)))
        (is (search "label=\"lamp=off\\ndoor=false\"" (first initial))))
      ;; the value with a quote and a backslash, escaped for DOT
      (is (search "lamp=a\\\"b\\\\c\\ndoor=true" dot))
      (is (= (counted-op-edges spec) 12) "the enumeration here agrees with the count by hand"))))

(test lamp-goal-shades-and-plans
  (with-lamp-spec (spec)
    (let ((dot (graph-text spec :goal 'lamp.dim)))
      (is (= 6 (count-dot dot "s")))
      (is (= 6 (count-dot dot "p")) "the plan tree shows every state")
      (is (= 2 (count-if (lambda (s) (search "fillcolor" s)) (dot-statements dot "s"))))
      (is (= 2 (count-if (lambda (s) (search "fillcolor" s)) (dot-statements dot "p"))))
      ;; off->dim from both doors, a"b\c->off from both: the plans are dim, and off then dim
      (is (= 4 (count-dot dot "p" :edges t)))
      (is (equal '("dim" "dim" "off" "off")
                 (sort (loop for s in (dot-statements dot "p" :edges t)
                             collect (let ((start (+ 7 (search "label=\"" s))))
                                       (subseq s start (position #\" s :start start))))
                       #'string<)))
      (is (search "plans to lamp.dim" dot)))))

(test lamp-renders-through-graphviz
  (if (not (dot-installed-p))
      (skip "Graphviz's dot is not installed")
      (with-lamp-spec (spec)
        (multiple-value-bind (svg code) (render-svg (graph-text spec :goal 'lamp.dim))
          (is (= 0 code))
          (is (= 12 (count-occurrences "class=\"node\"" svg)))
          (is (= 16 (count-occurrences "class=\"edge\"" svg)))
          (is (search "lamp=a&quot;b\\c" svg) "the quoted value survives as text")))))

;;;# Peedy, counted by enumeration

(test peedy-graph-counted
  (let* ((spec (dot-peedy))
         (machine (plan-spec spec))
         (dot (graph-text machine)))
    (multiple-value-bind (edges must-ask) (counted-op-edges spec)
      (is (= 144 (length (enumerate-assignments spec))))
      (is (= 144 (count-dot dot "s")))
      (is (= edges (count-dot dot "s" :edges t)))
      (is (plusp must-ask))
      (is (= must-ask (count-if (lambda (s) (search "style=dashed" s)) (dot-statements dot "s" :edges t)))))
    (is (= 1 (count-if (lambda (s) (search "peripheries=2" s)) (dot-statements dot "s"))))
    (is (search "subgraph \"cluster_s_" dot) "144 states are clustered")
    (is (search "all 144 plannable states" dot))))

(test peedy-goal-shades-exactly-its-states
  (let* ((spec (dot-peedy))
         (machine (plan-spec spec)))
    (dolist (goal '(posture.sit stand-noteless (and music-playing (not posture.fly))))
      (let ((dot (graph-text machine :goal goal))
            (expected (counted-goal-states spec goal)))
        (is (plusp expected))
        (is (= expected (count-if (lambda (s) (search "fillcolor" s)) (dot-statements dot "s")))
            "goal ~S" goal)
        (is (= expected (count-if (lambda (s) (search "fillcolor" s)) (dot-statements dot "p")))
            "goal ~S in the plan tree" goal)))))

(defun edge-key (statement)
  "An edge STATEMENT as \"FROM TO OP\": its dense state numbers and label."
  (let* ((text (string-left-trim " " statement))
         (arrow (search " -> " text))
         (end (position #\Space text :start (+ arrow 4)))
         (label (+ 7 (search "label=\"" text))))
    (format nil "~A ~A ~A" (subseq text 1 arrow) (subseq text (+ arrow 5) end)
            (subseq text label (position #\" text :start label)))))

(defun assignment-dense (spec assignment)
  "The dense number of ASSIGNMENT: mixed radix, the first variable lowest."
  (loop with stride = 1
        for var in (player.spec::plannable-variables spec)
        for index in assignment
        sum (* index stride)
        do (setf stride (* stride (length (player.spec::var-domain var))))))

(defun split-sequence-blank (text)
  "TEXT split at its blanks."
  (uiop:split-string text :separator " "))

(test peedy-plan-tree-walks-op-edges-to-the-goal
  ;; Every plan step is an op edge; every state that can reach the goal has a
  ;; step out, the goal's states none; Peedy's plans are fewest-ops, so each
  ;; step brings the goal one op nearer (distances counted here).
  (let* ((spec (dot-peedy))
         (dot (graph-text (plan-spec spec) :goal 'posture.sit))
         (op-edges (mapcar #'edge-key (dot-statements dot "s" :edges t)))
         (steps (dot-statements dot "p" :edges t))
         (distances (goal-distances spec 'posture.sit))
         (distance-of (make-hash-table :test 'equal)))
    (loop for a in (enumerate-assignments spec)
          do (setf (gethash (princ-to-string (assignment-dense spec a)) distance-of)
                   (gethash a distances)))
    (is (plusp (length steps)))
    (dolist (step steps)
      (destructuring-bind (from to op) (split-sequence-blank (edge-key step))
        (is (member (edge-key step) op-edges :test #'string=) "plan step ~A is no op edge" step)
        (is (eql (gethash to distance-of) (1- (gethash from distance-of)))
            "step ~A (~A) does not bring the goal one op nearer" step op)))
    (let ((sources (remove-duplicates (mapcar #'statement-node steps) :test #'string=)))
      (is (= (count-if (lambda (a) (let ((d (gethash a distances))) (and d (plusp d))))
                       (enumerate-assignments spec))
             (length sources))
          "exactly the states outside the goal that can reach it have a step out"))))

;;;# Large specs: reachable states, refusal, the plan tree alone

(defmacro with-switch-spec ((var) &body body)
  "Run BODY with VAR bound to a spec of seven booleans, 128 states: LOCKED,
which no op changes, and six switches A..F that ops turn on and off.  From the
initial state (all false) the 64 states with LOCKED false are reachable."
  `(with-spec (,var dot-switches
                    (state-variable locked boolean false)
                    ,@(loop for name in '(a b c d e f)
                            collect `(state-variable ,name boolean false))
                    ,@(loop for name in '(a b c d e f)
                            collect `(op ,(intern (format nil "ON-~A" name)) :add ,name)
                            collect `(op ,(intern (format nil "OFF-~A" name)) :sub ,name))
                    (event ev-all :state (and a b c d e f)))
     ,@body))

(test large-specs-draw-the-reachable-states
  (with-switch-spec (spec)
    (let ((player.inspect::*graph-all-states-limit* 100)
          (player.inspect::*graph-state-limit* 100))
      (let ((dot (graph-text spec)))
        (is (= 64 (count-dot dot "s")))
        (is (= (* 64 6) (count-dot dot "s" :edges t)) "each state: one switch op per switch")
        (is (search "the 64 states reachable from the initial state (of 128 plannable states)" dot))
        (is (not (search "locked=true" dot)))))))

(test too-large-specs-are-refused
  (with-switch-spec (spec)
    (let ((player.inspect::*graph-all-states-limit* 50)
          (player.inspect::*graph-state-limit* 50)
          (player.inspect::*plan-tree-state-limit* 100))
      (let ((condition (handler-case (progn (graph-text spec) nil)
                         (state-graph-error (c) c))))
        (is (typep condition 'state-graph-error))
        (is (search "more than 50 of them are reachable" (princ-to-string condition)))
        (is (search "--goal" (princ-to-string condition))))
      ;; with a goal, the plan tree alone
      (let ((dot (graph-text spec :goal '(and a b))))
        (is (= 0 (count-dot dot "s")))
        (is (= 64 (count-dot dot "p")))
        (is (= 16 (count-if (lambda (s) (search "fillcolor" s)) (dot-statements dot "p"))))
        (is (search "only the plan tree is drawn" dot)))
      (let ((player.inspect::*plan-tree-state-limit* 60))
        (signals state-graph-error (graph-text spec :goal '(and a b)))))))

;;;# Errors

(test bad-goals-are-clear-errors
  (with-lamp-spec (spec)
    (dolist (case '((lamp.bright "lamp.bright is not a state expression of spec dot-lamp: bright is not a value of lamp")
                    (window "unknown variable or state class window")
                    (lamp "lamp is not boolean")
                    ((and lamp.off) nil)
                    ((or lamp.dim 3) "malformed expression")))
      (destructuring-bind (goal fragment) case
        (if fragment
            (let ((condition (handler-case (progn (graph-text spec :goal goal) nil)
                               (error (c) c))))
              (is (typep condition 'state-graph-error) "goal ~S: ~A" goal condition)
              (is (search fragment (princ-to-string condition)) "goal ~S: ~A" goal condition))
            (finishes (graph-text spec :goal goal)))))
    (signals argument-error (write-state-graph 42 *standard-output*))
    (signals argument-error (write-state-graph spec 42))
    (signals argument-error (write-state-graph-file spec 42))))

(test missing-graphviz-names-the-package
  (with-lamp-spec (spec)
    (uiop:with-temporary-file (:pathname path :type "svg")
      (let ((*dot-program* "no-such-graphviz-dot"))
        (let ((condition (handler-case (progn (write-state-graph-file spec path) nil)
                           (error (c) c))))
          (is (typep condition 'graphviz-error))
          (is (search "install the Debian package graphviz" (princ-to-string condition))))
        ;; the command line says the same, as its one error line
        (let ((condition (handler-case (progn (player.cli::run-command-line
                                               (list "dot" (fixture "mini.lisp") "--out" (namestring path)))
                                              nil)
                           (error (c) c))))
          (is (typep condition 'graphviz-error))
          (is (search "no-such-graphviz-dot program, which is not installed: install the Debian package graphviz"
                      (player.base::condition-line condition))))))))

;;;# The command line

(defun check-dot-error (expected-code fragment &rest options)
  "`player dot` on mini.lisp with OPTIONS must fail with EXPECTED-CODE and one
error line containing FRAGMENT."
  (multiple-value-bind (out err code) (apply #'player-command "dot" (fixture "mini.lisp") options)
    (is (string= "" out))
    (is (= expected-code code) "exit code ~A for ~S" code options)
    (is (eql 0 (search "player: error: " err)) "stderr ~S" err)
    (is (search fragment err) "stderr ~S lacks ~S" err fragment)
    (is (= 1 (length (lines err))))))

(test dot-command-writes-dot-text
  (multiple-value-bind (out err code) (player-command "dot" (fixture "mini.lisp"))
    (is (= 0 code))
    (is (string= "" err))
    (is (eql 0 (search "// spec mini" out)))
    (let ((spec (first (load-spec (fixture "mini.lisp")))))
      (is (= (length (enumerate-assignments spec)) (count-dot out "s")))
      (is (= (counted-op-edges spec) (count-dot out "s" :edges t))))))

(test dot-command-renders-svg-and-dot-files
  (uiop:with-temporary-file (:pathname svg :type "svg")
    (uiop:with-temporary-file (:pathname dot-file :type "dot")
      (multiple-value-bind (out err code)
          (player-command "dot" (fixture "mini.lisp") "--goal" "stand-noteless" "--out" (namestring dot-file))
        (is (= 0 code) "stderr ~S" err)
        (is (search "; wrote " out))
        (let ((dot (alexandria:read-file-into-string dot-file)))
          (is (= 72 (count-dot dot "s")))
          (is (= 72 (count-dot dot "p")))
          (when (dot-installed-p)
            (multiple-value-bind (out err code)
                (player-command "dot" (fixture "mini.lisp") "--goal" "stand-noteless" "--out" (namestring svg))
              (declare (ignore out))
              (is (= 0 code) "stderr ~S" err)
              (let ((text (alexandria:read-file-into-string svg)))
                (is (search "<svg" text))
                (is (= 144 (count-occurrences "class=\"node\"" text)))
                (is (= (+ (count-dot dot "s" :edges t) (count-dot dot "p" :edges t))
                       (count-occurrences "class=\"edge\"" text))))))))))
  (check-dot-error 1 "goal posture.sitt is not a state expression of spec mini"
                   "--goal" "posture.sitt")
  (check-dot-error 2 "--goal takes one state expression" "--goal" "(and a")
  (check-dot-error 2 "--out takes a file name ending in .dot, .gv, .svg or .png" "--out" "graph.pdf"))

(test the-current-state-is-marked
  "WRITE-STATE-GRAPH :CURRENT marks exactly the node of that state."
  (let* ((machine (compile-spec (first (load-spec (checkout-file "specs/peedy.lisp")))))
         (controller (make-controller machine :initial-state '((posture . sit) (alert . sleep))))
         (text (with-output-to-string (out)
                 (write-state-graph machine out :current (player.control::controller-bits controller))))
         (marked (remove-if-not (lambda (line) (search "penwidth=3" line)) (lines text))))
    (is (= 1 (length marked)))
    (is (search "posture=sit" (first marked)))
    (is (search "alert=sleep" (first marked)))
    (signals argument-error (write-state-graph machine (make-broadcast-stream) :current -1))))
