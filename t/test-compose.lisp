;;;; test-compose.lisp -- the transition-system algebra of src/compose/ (Clark
;;;; & Palmer, 1995): algebra laws on random graphs, the paper's examples,
;;;; Newton's cradle, GRAPH->SPEC and specs/newtons-cradle.lisp.

(in-package #:player-tests)

(def-suite* compose :in player-tests)

;;; Random small graphs, from the seeded generator of random-specs.lisp

(defun random-graph (prng &key (max-nodes 6) (density 0.35) (universe 7))
  "A random graph on at most MAX-NODES of the integers below UNIVERSE, each
ordered pair an edge with probability DENSITY; some nodes may be isolated."
  (let* ((nodes (rs-sample prng (loop for i below universe collect i) (rs-between prng 0 max-nodes)))
         (edges (loop for a in nodes
                      append (loop for b in nodes
                                   when (rs-chance prng density) collect (cons a b)))))
    (make-graph nodes edges)))

(defun random-predicate (prng &key (universe 7) (probability 0.6))
  "A random predicate of (SOURCE TARGET) over integers below UNIVERSE."
  (let ((table (make-hash-table :test 'equal)))
    (dotimes (a universe)
      (dotimes (b universe)
        (setf (gethash (cons a b) table) (rs-chance prng probability))))
    (lambda (source target) (gethash (cons source target) table))))

(defmacro do-random-graphs ((prng count) &body body)
  "Run BODY COUNT times with PRNG a fresh generator seeded 1, 2, ..."
  (let ((seed (gensym "SEED")))
    `(loop for ,seed from 1 to ,count
           do (let ((,prng (make-rs-prng (+ 7000 ,seed)))) ,@body))))

(defun edge-ends (graph)
  "The ends of GRAPH's edges, sorted."
  (player.compose::sort-nodes (remove-duplicates (loop for (s . e) in (graph-edges graph) collect s collect e)
                                         :test #'equal)))

;;; Laws

(test sum-and-intersection-laws
  (do-random-graphs (prng 200)
    (let ((a (random-graph prng)) (b (random-graph prng)) (c (random-graph prng)))
      (is (graph-equal (graph-sum a b) (graph-sum b a)))
      (is (graph-equal (graph-sum (graph-sum a b) c) (graph-sum a (graph-sum b c))))
      (is (graph-equal (graph-sum a a) a))
      (is (graph-equal (graph-intersection a b) (graph-intersection b a)))
      (is (graph-equal (graph-intersection (graph-intersection a b) c)
                       (graph-intersection a (graph-intersection b c))))
      (is (graph-equal (graph-intersection a a) a))
      (is (subgraph-p (graph-intersection a b) (graph-sum a b))))))

(defun rebracket (node)
  "((X . Y) . Z) as (X . (Y . Z))."
  (cons (car (car node)) (cons (cdr (car node)) (cdr node))))

(test product-is-associative-up-to-rebracketing
  (do-random-graphs (prng 200)
    (let ((a (random-graph prng :max-nodes 3 :universe 4))
          (b (random-graph prng :max-nodes 3 :universe 4))
          (c (random-graph prng :max-nodes 3 :universe 4)))
      (let ((left (graph-product (graph-product a b) c))
            (right (graph-product a (graph-product b c))))
        (is (graph-equal (graph-map left #'rebracket) right))
        (is (= (graph-node-count left) (* (graph-node-count a) (graph-node-count b) (graph-node-count c))))
        (is (= (graph-edge-count left) (* (graph-edge-count a) (graph-edge-count b) (graph-edge-count c)))))))
  ;; A product with an empty graph is empty.
  (is (graph-empty-p (graph-product (complete-graph '(1 2)) (make-graph '() '()))))
  (is (graph-empty-p (graph-product (make-graph '() '()) (complete-graph '(1 2))))))

(test restriction-laws
  (do-random-graphs (prng 200)
    (let* ((g (random-graph prng))
           (p (random-predicate prng))
           (q (random-predicate prng))
           (g-p (restrict g p))
           (nested (restrict g-p q))
           (both (graph-intersection g-p (restrict g q))))
      ;; never adds an edge (nor a node)
      (is (subgraph-p g-p g))
      ;; N' = ran(s') ∪ ran(t'): the nodes are exactly the ends of the edges kept
      (is (equal (graph-nodes g-p) (edge-ends g-p)))
      ;; G \ p \ p' = (G \ p) & (G \ p'): the same edges; the nodes of the
      ;; left side are those of the right side that are ends of its edges
      (is (equal (graph-edges nested) (graph-edges both)))
      (is (subgraph-p nested both))
      (is (graph-equal nested (restrict both (constantly t))))
      ;; the paper's translation of & in a restriction
      (is (graph-equal (restrict g (pred-and p q)) both))
      ;; traces of G \ p are traces of G
      (let ((start (first (graph-nodes g-p))))
        (when start
          (let ((traces (make-hash-table :test 'equal)))
            (dolist (trace (graph-traces g start 4)) (setf (gethash trace traces) t))
            (is (every (lambda (trace) (gethash trace traces)) (graph-traces g-p start 4))))))))
  ;; Where the node sets differ: a -> b keeps p only, b -> c p' only, a -> c both.
  (let* ((g (make-graph '() '((a . b) (b . c) (a . c))))
         (p (lambda (s e) (not (and (eq s 'b) (eq e 'c)))))
         (q (lambda (s e) (not (and (eq s 'a) (eq e 'b))))))
    (is (equal '(a c) (graph-nodes (restrict (restrict g p) q))))
    (is (equal '(a b c) (graph-nodes (graph-intersection (restrict g p) (restrict g q)))))))

(test merge-is-the-papers-definition
  ;; (merge, I)((G1 × G2) \ p), computed literally, on random graphs of pairs
  (do-random-graphs (prng 60)
    (flet ((pairs-graph ()
             (let ((g (random-graph prng :max-nodes 5 :universe 9)))
               (graph-map g (lambda (n) (cons (floor n 3) (mod n 3)))))))
      (let ((a (pairs-graph)) (b (pairs-graph)))
        (is (graph-equal (graph-merge a b) (player.compose::graph-merge-by-definition a b))))))
  (let ((g17 (cradle-stage 2 :g17)))
    (is (graph-equal (graph-merge g17 g17 :leafp #'sphere-state-p)
                     (player.compose::graph-merge-by-definition g17 g17 :leafp #'sphere-state-p)))))

;;; Patterns, trees, traces: the paper's examples

(test patterns
  ;; "(1, x) => (x, 1) is true when applied to values ((a, b), (c, d)) where either
  ;; a is not the constant 1 or both a and d are 1 and b and c are the same value"
  (let ((p (pred-implies '(1 . x) '(x . 1))))
    (is-true (funcall p '(2 . 5) '(7 . 7)))
    (is-true (funcall p '(1 . 5) '(5 . 1)))
    (is-false (funcall p '(1 . 5) '(4 . 1)))
    (is-false (funcall p '(1 . 5) '(5 . 2))))
  (is (equal '((x . 3)) (nth-value 1 (match-pattern '(_ . (x . 'foo)) '(1 3 . foo)))))
  (is-false (match-pattern '(x . x) '(1 . 2)))
  (is-true (match-pattern '(0 :eval - x) '(0 . -1) '((x . 1))))
  (let ((g (complete-graph '(1 2 3))))
    (is (= 7 (graph-edge-count (restrict g (pred-implies 1 2)))))
    (is (= 1 (graph-edge-count (restrict g (pred-edge 1 2)))))
    (is (= 1 (graph-edge-count (restrict g (pred-and (pred-edge 1 '_) (lambda (s e) (declare (ignore s)) (= e 3)))))))))

(test trees
  (is (equal '(((a . v) . (b . w)) . ((c . x) . (d . y)))
             (tree-product '((a . b) . (c . d)) '((v . w) . (x . y)))))
  (is (equal '(a b c d) (tree-flatten '((a . b) . (c . d)))))
  (is (equal '((a . (b c d)) (b . (c d)) (c . (d)) (d . nil)) (seq-suffixes '(a b c d))))
  (is (eq 'a (tree-left '((a . b) . (x . (y . z))))))
  (is (eq 'z (tree-right '((a . b) . (x . (y . z))))))
  (is (equal '(a . (b . c)) (tree-merge '(a . b) '(b . c))))
  (is (equal '(0 . 0) (tree-right '(((1 . 1) . (0 . 1)) . (0 . 0)) :leafp #'sphere-state-p)))
  (is (equal '(1 . 1) (tree-left '(((1 . 1) . (0 . 1)) . (0 . 0)) :leafp #'sphere-state-p)))
  (is-true (funcall (seq-all #'oddp) '(1 3)))
  (is-false (funcall (seq-exists #'evenp) '(1 3)))
  (is (= 2 (seq-count (seq-restrict (seq-rev '(1 2 3)) #'oddp)))))

(defun has-trace-p (graph trace)
  "Is TRACE (a list of nodes) a trace of GRAPH?"
  (member trace (graph-traces graph (first trace) (1- (length trace))) :test #'equal))

(test single-sphere-traces
  (let ((g2 (cradle-stage 1 :g2)) (g4 (cradle-stage 1 :g4)) (g^1 (cradle-stage 1 :g^1)))
    (is (= 3 (graph-node-count g2)))
    (is (= 7 (graph-edge-count g2)))
    (is-true (has-trace-p g2 '(-1 0 1 0 -1)))
    (is-true (has-trace-p g2 '(0 1 0 1 0 1)))
    (is-false (has-trace-p g2 '(-1 1)))
    (is-true (has-trace-p g4 '((-1 . 1) (0 . 1) (1 . -1) (0 . -1) (-1 . 1))))
    (is-true (has-trace-p g4 '((0 . 1) (1 . -1) (1 . 1) (1 . -1) (0 . 1) (1 . -1))))
    ;; G^1: "a swinging sphere" and "a sphere on the left which swings down to rest ..."
    (let ((swing '((-1 . 0) (-1 . 1) (0 . 1) (1 . 1) (1 . 0) (1 . -1) (0 . -1)))
          (rest '((-1 . 1) (0 . 1) (0 . 0) (0 . 0) (0 . -1) (-1 . -1) (-1 . 0) (-1 . 1))))
      (is-true (has-trace-p g^1 swing))
      (is-true (has-trace-p g^1 rest))
      ;; the paper's G5 & G9 & G12 & G15 read literally has neither
      (is-false (has-trace-p (cradle-stage 1 :g^1-literal) swing))
      (is-false (has-trace-p (cradle-stage 1 :g^1-literal) rest)))
    ;; a swing is forced: one way on from every state but at 0
    (is (equal '((1 . 0)) (graph-successors g^1 '(1 . 1))))
    (is (equal '((1 . -1)) (graph-successors g^1 '(1 . 0))))
    (is (= 9 (graph-node-count g^1)))
    (is (= 15 (graph-edge-count g^1)))
    (is (equal (random-trace g^1 '(-1 . 0) 6 42) (random-trace g^1 '(-1 . 0) 6 42)))
    (is-true (has-trace-p g^1 (random-trace g^1 '(0 . 0) 8 7)))))

;;; Newton's cradle

(defun lifted-node (n k side)
  "The cradle node of N spheres with K lifted at rest on SIDE (:left or :right)."
  (apply #'cradle-node
         (if (eq side :left)
             (append (make-list k :initial-element '(-1 . 0)) (make-list (- n k) :initial-element '(0 . 0)))
             (append (make-list (- n k) :initial-element '(0 . 0)) (make-list k :initial-element '(1 . 0))))))

(defun gravity-p (before after)
  "Is BEFORE -> AFTER a sphere's turn at an extreme: slowing to rest, or falling back?"
  (member (cons before after)
          '(((1 . 1) . (1 . 0)) ((1 . 0) . (1 . -1)) ((-1 . -1) . (-1 . 0)) ((-1 . 0) . (-1 . 1)))
          :test #'equal))

(defun step-problems (from to)
  "What is physically wrong with the cradle step FROM -> TO (lists of sphere
states), as a list of strings; NIL when nothing is."
  (let ((problems '())
        (moves (mapcar #'cons from to)))
    (dolist (state (list from to))
      (loop for (a b) on state while b
            when (> (car a) (car b)) do (push "two spheres passed each other" problems)))
    (loop for ((p . v) . (p2 . v2)) in moves
          for i from 0
          do (cond ((/= p p2)
                    (unless (and (= p2 (+ p v)) (= v v2)) (push "a sphere jumped" problems)))
                   ((= v v2))
                   ((gravity-p (cons p v) (cons p2 v2)))
                   ((/= p 0) (push "a sphere turned at an extreme" problems))
                   ((notany (lambda (other)
                              (destructuring-bind ((q . w) . (q2 . w2)) other
                                (and (= q q2 0) (= w v2) (= w2 v))))
                            (remove (nth i moves) moves :count 1))
                    (push "a sphere started or stopped without a collision" problems))))
    problems))

(test cradle-behaves
  ;; Every trace of up to 12 steps from k spheres lifted on one side (k = 1 ...
  ;; n - 1, n = 2 ... 6): no two spheres pass each other, a sphere only starts,
  ;; stops or turns at 0 in a collision (or at an extreme, by gravity); the
  ;; spheres that go out on the other side are among the k outermost, and, in
  ;; every trace that does not get stuck, exactly those k.
  ;; This is the paper's G^n (stage :paper; newton-cradle adds cradle-physics.lisp).
  ;; The paper's collision rule lets a sphere's partner be any sphere on the
  ;; far side, so momentum may pass to an inner sphere that is then blocked: such
  ;; traces end at a state with no successor (the model's, not the test's).
  ;; With more than half the spheres lifted, every trace gets stuck at the
  ;; first collision: a moving sphere at 0 cannot stay at 0 in G^1.
  (loop for n from 2 to (sweep-count 6 5)  ; the fast tier leaves out the biggest cradle
        for g = (cradle-paper n)
        do (loop for k from 1 below n
                 do (dolist (side '(:left :right))
                      (let ((traces (graph-traces g (lifted-node n k side) 12 :maximal t))
                            (far (if (eq side :left) 1 -1))
                            (expected (if (eq side :left)
                                          (loop for i from (- n k) below n collect i)
                                          (loop for i below k collect i)))
                            (complete 0))
                        (is (plusp (length traces)))
                        (dolist (trace traces)
                          (let ((states (mapcar #'cradle-spheres trace)))
                            (loop for (from to) on states while to
                                  do (let ((problems (step-problems from to)))
                                       (is (null problems) "~{~A~^, ~}: ~S -> ~S" problems from to)))
                            (let ((out (sort (remove-duplicates
                                              (loop for state in states
                                                    append (loop for (p . nil) in state for i from 0
                                                                 when (= p far) collect i)))
                                             #'<)))
                              (is (subsetp out expected) "~D of ~D lifted ~(~A~): spheres ~S went out" k n side out)
                              (when (= 13 (length states))
                                (incf complete)
                                (is (equal expected out)
                                    "~D of ~D lifted ~(~A~): spheres ~S went out" k n side out)))))
                        (if (<= (* 2 k) n)
                            (is (plusp complete) "~D of ~D lifted ~(~A~): every trace gets stuck" k n side)
                            (is (zerop complete) "~D of ~D lifted ~(~A~): a trace does not get stuck" k n side)))))))

(test cradle-sizes
  ;; G^1 has 9 nodes and 15 edges: 4 swings ((-1,1)->(0,1)->(1,1), mirrored), 4
  ;; turns at the extremes, and at 0: rest (0,0)->(0,0), start (0,0)->(0,±1),
  ;; stop (0,±1)->(0,0), reverse (0,±1)->(0,∓1).
  ;; G16 = G^1 × G^1: 81 nodes, 15² = 225 edges. G17 keeps the pairs whose
  ;; positions are ordered at both ends: 6 ordered position pairs × 9 velocity
  ;; pairs = 54 nodes, 141 edges. G^2 keeps the 48 of those edges in which every
  ;; change at 0 pairs with an opposite one (counted again below, without the
  ;; algebra); every one of the 54 nodes is still the end of some edge kept by
  ;; each conjunct, so G^2 has 54 nodes (the paper's reading of &).
  ;; G^3 = (G17 ⊗ G17) \ ...: 262 nodes and 1111 edges after the merge, 256
  ;; nodes and 202 edges after the restriction (202 counted again below).
  (is (= 54 (graph-node-count (cradle-stage 2 :g17))))
  (is (= 141 (graph-edge-count (cradle-stage 2 :g17))))
  (is (= 54 (graph-node-count (cradle-paper 2))))
  (is (= 48 (graph-edge-count (cradle-paper 2))))
  (is (= 262 (graph-node-count (cradle-stage 3 :merged))))
  (is (= 1111 (graph-edge-count (cradle-stage 3 :merged))))
  (is (= 256 (graph-node-count (cradle-paper 3))))
  (is (= 202 (graph-edge-count (cradle-paper 3))))
  ;; The edge counts again, by brute force over tuples of G^1 edges.
  (let ((single (graph-edges (cradle-paper 1))))
    (flet ((count-steps (n)
             (let ((count 0))
               (labels ((choose (i moves)
                          (if (= i n)
                              (let ((moves (reverse moves)))
                                (when (and (null (step-problems (mapcar #'car moves) (mapcar #'cdr moves)))
                                           (legal-collisions-p moves))
                                  (incf count)))
                              (dolist (edge single) (choose (1+ i) (cons edge moves))))))
                 (choose 0 '()))
               count)))
      (is (= 48 (count-steps 2)))
      (is (= 202 (count-steps 3))))))

(defun legal-collisions-p (moves)
  "As many changes to the left at 0 as to the right, each with a partner that
exchanges velocities with it on the side it was hit from."
  (flet ((change (move) (destructuring-bind ((p . v) . (p2 . v2)) move
                          (and (= p p2 0) (signum (- v2 v)))))
         (swaps-p (a b) (and (= (cdar a) (cddr b)) (= (cddr a) (cdar b))
                             (= 0 (caar b) (cadr b)) (/= (cdar b) (cddr b)))))
    (and (= (count -1 moves :key #'change) (count 1 moves :key #'change))
         (loop for (move . right) on moves
               for left = (ldiff moves (member move moves))
               always (case (change move)
                        (-1 (some (lambda (other) (swaps-p move other)) right))
                        (1 (some (lambda (other) (swaps-p move other)) left))
                        (t t))))))

;;; graph->spec

(defun bfs-distances (graph start)
  "Node -> number of edges on a shortest path from START, for the nodes reachable."
  (let ((distances (make-hash-table :test 'equal))
        (queue (list start)))
    (setf (gethash start distances) 0)
    (loop while queue
          do (let ((node (pop queue)))
               (dolist (next (graph-successors graph node))
                 (unless (gethash next distances)
                   (setf (gethash next distances) (1+ (gethash node distances)))
                   (setf queue (append queue (list next)))))))
    distances))

(defun value-symbol (name)
  "The PLAYER-USER symbol NAME."
  (intern name '#:player-user))

(test graph-spec-plans-follow-edges
  (do-random-graphs (prng 25)
    (let* ((g (random-graph prng :max-nodes 6 :density 0.3))
           (symbols (rs-chance prng 0.5))
           (g (if symbols (graph-map g (lambda (n) (value-symbol (format nil "S~D" n)))) g)))
      (unless (graph-empty-p g)
        (let* ((name (player.compose::default-node-name (first (graph-nodes g))))
               (spec (graph->spec g 'compose-random :start (first (graph-nodes g))))
               (machine (compile-spec spec)))
          (declare (ignore name))
          (unwind-protect
               (dolist (from (graph-nodes g))
                 (let ((distances (bfs-distances g from)))
                   (dolist (to (graph-nodes g))
                     (let* ((controller (make-controller machine :initial-state
                                                         (list (cons (value-symbol "NODE")
                                                                     (value-symbol (player.compose::default-node-name from))))))
                            (ok (send-event controller (value-symbol (format nil "GO-~A" (player.compose::default-node-name to)))))
                            (ops (loop for line in (trace-lines (controller-presenter controller))
                                       when (eq (first line) :op) collect (second line))))
                       (if (gethash to distances)
                           (progn
                             (is (eq t ok))
                             (is (= (gethash to distances) (length ops)) "~S -> ~S: ~S" from to ops)
                             ;; each op is an edge from where the last one ended
                             (let ((at from))
                               (dolist (op ops)
                                 (let ((next (find-if (lambda (n)
                                                        (string= (symbol-name op)
                                                                 (format nil "FROM-~A-TO-~A" (player.compose::default-node-name at)
                                                                         (player.compose::default-node-name n))))
                                                      (graph-successors g at))))
                                   (is-true next "~A is not an edge from ~S" op at)
                                   (setf at next))))
                             (is (string= (player.compose::default-node-name to)
                                          (symbol-name (state-value controller (value-symbol "NODE"))))))
                           (is (null ok)))))))
            (remove-spec 'compose-random)))))))

(defun decode-cradle-name (name)
  "The positions of the spheres of the cradle node named NAME (LS-CE-...)."
  (loop for i from 0 below (length name) by 3
        collect (1- (position (char name i) "LCR"))))

(test newtons-cradle-spec-file
  (let* ((spec (first (load-spec (checkout-file "specs/newtons-cradle.lisp"))))
         (machine (compile-spec spec))
         (controller (make-controller machine)))
    ;; the committed file is what the algebra generates
    (is (equal (player.compose::cradle-spec-forms) (player.spec::spec-forms spec)))
    (is (eq t (send-event controller 'ev-lift-two-left)))
    (let* ((ops (loop for line in (trace-lines (controller-presenter controller))
                      when (eq (first line) :op) collect (symbol-name (second line))))
           (states (loop for op in (rest ops)
                         collect (decode-cradle-name (subseq op (+ 4 (search "-TO-" op))))))
           (out (remove-duplicates (loop for state in states
                                         append (loop for p in state for i from 0 when (= p 1) collect i)))))
      (is (string= "LIFT-TWO-LEFT" (first ops)))
      (is (equal '(3 4) (sort out #'<)) "spheres ~S went out" out)
      (is (equal '(0 0 0 1 1) (car (last states))))
      (is (string= "CS-CS-CS-RS-RS" (symbol-name (state-value controller 'cradle))))))
  (remove-spec 'newtons-cradle))

;;; Bad inputs

(test compose-bad-inputs
  (let ((g2 (cradle-stage 1 :g2)))
    (signals graph-error (restrict g2 (pred-implies 5 '_)))
    (handler-case (restrict g2 (pred-implies 5 '_))
      (graph-error (e) (is (search "5" (princ-to-string e))) (is (eql 5 (graph-error-value e)))))
    (signals graph-error (restrict (cradle-stage 1 :g4) (pred-edge '(0 . 7) '_)))
    (signals graph-error (graph-traces g2 2 3))
    (signals graph-error (random-trace g2 '(0 . 0) 3 1))
    (signals graph-error (graph-successors g2 'nowhere))
    (signals player-error (graph-merge g2 g2))
    (handler-case (graph-merge (newton-cradle 1) (newton-cradle 1) :leafp #'sphere-state-p)
      (graph-error (e) (is (search "is not a binary tree" (princ-to-string e)))))
    (signals graph-error (tree-product '(a . b) '((a . b) . c)))
    (signals graph-error (pattern '(:eval)))
    (signals graph-error (graph->spec (make-graph '() '()) 'compose-empty))
    (signals graph-error (graph->spec (make-graph '("a" a) '()) 'compose-clash))
    (signals graph-error (graph->spec g2 'compose-start :start 9))
    (signals graph-error (cradle-stage 2 :g99))
    (signals argument-error (newton-cradle 0))
    (is (null (find-spec 'compose-empty nil)))))
