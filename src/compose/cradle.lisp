;;;; cradle.lisp -- Newton's cradle built step by step as in Clark & Palmer's §4.
;;;;
;;;; A sphere's state is (POSITION . VELOCITY): position -1 (lifted to the left
;;;; extreme), 0 (at rest hanging), 1 (lifted right); velocity -1 (moving left),
;;;; 0 (at rest), 1 (moving right). The n-sphere graph's nodes are right-nested
;;;; trees of sphere states, leftmost sphere first: (S1 . (S2 . ... (Sn-1 . Sn))).
;;;;
;;;; Where the paper's text does not give the behaviour its own examples show,
;;;; this file says which reading it takes (the [Reading] notes below).

(in-package #:player.compose)

(defparameter *positions* '(-1 0 1)
  "Σ, the positions of a sphere (and its rates of change).")

(defun sphere-state-p (x)
  "Is X a sphere state (POSITION . VELOCITY), a leaf of a cradle tree?"
  (and (consp x) (integerp (car x)) (integerp (cdr x))))

(defun sphere-transition-p (x)
  "Is X a pair of sphere states (BEFORE . AFTER), a leaf of t1 × t2?"
  (and (consp x) (sphere-state-p (car x)) (sphere-state-p (cdr x))))

;;; The single sphere (§4)

(defun cradle-single-sphere-stages ()
  "The alist of the single-sphere graphs G1 ... G15, G^1 and G^1-LITERAL."
  (let* ((g1 (complete-graph *positions*))
         ;; "G2 = G1 \ p where p(-1, 1) = false and p(1, -1) = false and otherwise p is true"
         (g2 (restrict g1 (lambda (a b) (not (or (and (eql a -1) (eql b 1)) (and (eql a 1) (eql b -1)))))))
         ;; "The rate of change graph of a single-sphere system, G3 = C({0, -1, 1})"
         (g3 (complete-graph *positions*))
         ;; "The graph which describes the free movement of a single-sphere system is G4 = G2 × G3"
         (g4 (graph-product g2 g3))
         ;; [Reading] The paper builds G^1 = G5 & G9 & G12 & G15 from implication
         ;; restrictions, G6 = G4 \ (0, 0) => (0, _) and so on, and G5 = G4 \ p1
         ;; with p1((p1, v1), (p2, v2)) = equal(p2, p1 + v1). Read literally
         ;; (:G^1-LITERAL below), that G^1 does not have the paper's own traces:
         ;; (1, 1) -> (1, 0) breaks p1 (1 /= 1 + 1), (0, 1) -> (0, 0) too; and
         ;; since P => Q holds of every edge not leaving a P node, the sums
         ;; G6 + G7 + G8 and G10 + G11 constrain nothing. The text describes
         ;; behaviours ("G6 describes the behaviour ... where the sphere starts
         ;; from position 0 at rest", "G10 forces the sphere to slow down at
         ;; position 1"), merged by sums: the constructive approach of §3. So
         ;; each Gi here is that behaviour alone, G4 \ (P then Q) (PRED-EDGE:
         ;; the edges from a P node to a Q node), G5 is the free swing (moving
         ;; on by the velocity, keeping it; a sphere at rest does not move), and
         ;; G^1 = G5 + G9 + G12 + G15. It has both of the paper's G^1 traces.
         (g5 (restrict g4 (pred-and (pred-edge '(p . v) '((:eval + p v) . v))
                                    (lambda (source target) (declare (ignore target))
                                      (/= 0 (cdr source))))))
         (g6 (restrict g4 (pred-edge '(0 . 0) '(0 . _))))
         (g7 (restrict g4 (pred-edge '(0 . _) '(0 . 0))))
         (g8 (restrict g4 (pred-edge '(0 . x) '(0 :eval - x))))
         (g9 (graph-sum g6 g7 g8))
         (g10 (restrict g4 (pred-edge '(1 . 1) '(1 . 0))))
         (g11 (restrict g4 (pred-edge '(1 . 0) '(1 . -1))))
         (g12 (graph-sum g10 g11))
         (g13 (restrict g4 (pred-edge '(-1 . -1) '(-1 . 0))))
         (g14 (restrict g4 (pred-edge '(-1 . 0) '(-1 . 1))))
         (g15 (graph-sum g13 g14))
         (g^1 (graph-sum g5 g9 g12 g15))
         (literal (graph-intersection
                   (restrict g4 (pred-edge '(p . v) '((:eval + p v) . _)))
                   (graph-sum (restrict g4 (pred-implies '(0 . 0) '(0 . _)))
                              (restrict g4 (pred-implies '(0 . _) '(0 . 0)))
                              (restrict g4 (pred-implies '(0 . x) '(0 :eval - x))))
                   (graph-sum (restrict g4 (pred-implies '(1 . 1) '(1 . 0)))
                              (restrict g4 (pred-implies '(1 . 0) '(1 . -1))))
                   (graph-sum (restrict g4 (pred-implies '(-1 . -1) '(-1 . 0)))
                              (restrict g4 (pred-implies '(-1 . 0) '(-1 . 1)))))))
    (list (cons :g1 g1) (cons :g2 g2) (cons :g3 g3) (cons :g4 g4) (cons :g5 g5)
          (cons :g6 g6) (cons :g7 g7) (cons :g8 g8) (cons :g9 g9) (cons :g10 g10)
          (cons :g11 g11) (cons :g12 g12) (cons :g13 g13) (cons :g14 g14) (cons :g15 g15)
          (cons :g^1 g^1) (cons :g^1-literal literal))))

;;; Collisions (§4), on the pairs (t1, t2) of trees an edge joins

(defun sphere-moves (t1 t2)
  "↓(t1 × t2): each sphere's (BEFORE . AFTER), leftmost sphere first."
  (tree-flatten (tree-product t1 t2 :leafp #'sphere-state-p) :leafp #'sphere-transition-p))

(defun changeleft (move)
  "changeleft((p, v), (p', v')) = equal(p, p') & equal(p, 0) & v' < v"
  (destructuring-bind ((p . v) . (p2 . v2)) move
    (and (eql p p2) (eql p 0) (< v2 v))))

(defun changeright (move)
  "changeright((p, v), (p', v')) = equal(p, p') & equal(p, 0) & v < v'"
  (destructuring-bind ((p . v) . (p2 . v2)) move
    (and (eql p p2) (eql p 0) (< v v2))))

(defun samechanges (t1 t2)
  "samechanges(t1, t2) = equal(#(changesleft(t1, t2)), #(changesright(t1, t2))),
changesleft(t1, t2) = (↓(t1 × t2)) \\ changeleft, and so on."
  (let ((moves (sphere-moves t1 t2)))
    (= (seq-count (seq-restrict moves #'changeleft))
       (seq-count (seq-restrict moves #'changeright)))))

(defun velocities-swap-p (v1 v1* move)
  "(v1, v1') <-> ((p, v2), (p', v2')) = equal(p, p') & equal(p', 0) &
notequal(v2, v2') & (v1, v1') <-> (v2, v2'), where (v1, v1') <-> (v2, v2')
when v1 is v2' and v1' is v2: the two spheres exchange velocities at 0."
  (destructuring-bind ((p . v2) . (p* . v2*)) move
    (and (eql p p*) (eql p* 0) (/= v2 v2*) (eql v1 v2*) (eql v1* v2))))

(defun caused-by-collision (changes)
  "The paper's ((p, v), (p', v')) ↪ l as a predicate on (MOVE . L): if MOVE is
one of CHANGES (CHANGELEFT or CHANGERIGHT), some sphere of L exchanges
velocities with it.
[Reading] The paper's premise is atzero = equal(p, p') & equal(p', 0) &
notequal(v, v'), any change at 0; then causesleftright asks every change to
have its partner to its right and causesrightleft to its left, which no
collision satisfies (the rightmost sphere has nothing to its right). Its
words say which: causesleftright \"holds when every change in velocity at 0
and on the left is caused by an equal and opposite change on the right\". So
a change to the left (CHANGELEFT: the sphere was hit from the right) needs its
partner among the spheres to its right, a change to the right among those to
its left."
  (lambda (move-and-rest)
    (destructuring-bind (move . rest) move-and-rest
      (or (not (funcall changes move))
          (destructuring-bind ((p . v) . (p* . v*)) move
            (declare (ignore p p*))
            (funcall (seq-exists (lambda (other) (velocities-swap-p v v* other))) rest))))))

(defun causesleftright (t1 t2)
  "causesleftright(t1, t2) = all(↪)(↑(↓(t1 × t2))): every change to the left at
0 is caused by an equal and opposite change to its right."
  (funcall (seq-all (caused-by-collision #'changeleft)) (seq-suffixes (sphere-moves t1 t2))))

(defun causesrightleft (t1 t2)
  "causesrightleft(t1, t2) = all(↪)(↑(rev(↓(t1 × t2)))): every change to the
right at 0 is caused by an equal and opposite change to its left."
  (funcall (seq-all (caused-by-collision #'changeright)) (seq-suffixes (seq-rev (sphere-moves t1 t2)))))

(defun collision-predicate ()
  "samechanges & causesleftright & causesrightleft."
  (pred-and #'samechanges #'causesleftright #'causesrightleft))

(defun ordering-predicate ()
  "G17's ((p1, _), (p2, _)) & p1 <= p2: the left sphere is never to the right."
  (pred-nodes '((p1 . _) . (p2 . _))
              :where (lambda (b) (<= (binding 'p1 b) (binding 'p2 b)))))

;;; n spheres

(defparameter *single-stage-names*
  '(:g1 :g2 :g3 :g4 :g5 :g6 :g7 :g8 :g9 :g10 :g11 :g12 :g13 :g14 :g15 :g^1 :g^1-literal :g18 :g^1+)
  "The stages of the single sphere, the paper's and the physical cradle's.")

(defun cradle-stage-names (n)
  "The names of the stages of the N-sphere cradle, in the order they are built."
  (append *single-stage-names*
          (if (= n 1)
              '(:paper :g^n)
              '(:g16 :g17 :merged :paper :g16+ :g17+ :merged+ :collisions :g^n))))

(defun merge-copies (graph n)
  "GRAPH ⊗ ... ⊗ GRAPH, N - 1 copies merged on a common sphere."
  (let ((merged graph))
    (loop repeat (- n 2)
          do (setf merged (graph-merge merged graph :leafp #'sphere-state-p)))
    merged))

(defun compute-cradle-stage (n name)
  "The stage NAME of the N-sphere cradle, built from the stages before it."
  (flet ((stage (name) (cradle-stage n name)))
    (case name
      ((:g18 :g^1+) (cdr (assoc name (physics-single-stages (cradle-single-sphere-stages)))))
      (:paper (if (= n 1) (stage :g^1) (restrict (stage :merged) (collision-predicate))))
      (:g16 (graph-product (stage :g^1) (stage :g^1)))
      (:g17 (restrict (stage :g16) (ordering-predicate)))
      (:merged (merge-copies (stage :g17) n))
      (:g16+ (graph-product (stage :g^1+) (stage :g^1+)))
      (:g17+ (restrict (stage :g16+) (ordering-predicate)))
      (:merged+ (merge-copies (stage :g17+) n))
      (:collisions (restrict (stage :merged+) (collision-predicate)))
      (:g^n (restrict (stage (if (= n 1) :g^1+ :collisions)) (resolved-predicate)))
      (t (cdr (assoc name (cradle-single-sphere-stages)))))))

(defvar *cradle-stages* (make-hash-table :test 'equal)
  "(N . NAME) -> that stage of the N-sphere cradle, computed once (graphs never
change). The single sphere's stages are kept under N = 1.")

(defun cradle-stages (n)
  "The named graphs of Newton's cradle with N spheres (N >= 1), as an alist
(building all of them; CRADLE-STAGE builds one and what it needs):
:G1 ... :G15 and :G^1 (the single sphere, §4), :G^1-LITERAL (the paper's
G5 & G9 & G12 & G15 read literally, for comparison: it lacks the paper's
traces), :G18 and :G^1+ (cradle-physics.lisp), and for N >= 2, :G16 = G^1 ×
G^1, :G17 = G16 \\ ((p1, _), (p2, _)) & p1 <= p2 (each end of each edge),
:MERGED = G17 ⊗ ... ⊗ G17 (N - 1 copies, merged on a common sphere; G17
itself for N = 2), :PAPER, the paper's cradle: :MERGED \\ (samechanges &
causesleftright & causesrightleft), the restrictions applied after the merge
as the paper warns (G^1 for N = 1); then the same built from G^1+ (:G16+,
:G17+, :MERGED+, :COLLISIONS) and :G^N, the cradle: :COLLISIONS \\ resolved
(see cradle-physics.lisp), in which no state is a dead end.
[Reading] The paper's general formula indexes the merge i = 2 ... n-1, n-2
copies; its G^3 = G17 ⊗ G17 and G^4 = G17 ⊗ G17 ⊗ G17 have n-1, which is what
is built. Its G^3 says causesleft & causesright for causesleftright &
causesrightleft."
  (check-argument 'cradle-stages 'n n (lambda (x) (typep x '(integer 1))) "a number of spheres (an integer >= 1)")
  (loop for name in (cradle-stage-names n) collect (cons name (cradle-stage n name))))

(defun cradle-stage (n name)
  "The graph named NAME (a keyword, see CRADLE-STAGES) of the N-sphere cradle."
  (check-argument 'cradle-stage 'n n (lambda (x) (typep x '(integer 1))) "a number of spheres (an integer >= 1)")
  (unless (member name (cradle-stage-names n))
    (graph-fail name "cradle-stage: no stage ~S for ~D sphere~:P (stages: ~{~S~^ ~})"
                name n (cradle-stage-names n)))
  (let ((key (cons (if (member name *single-stage-names*) 1 n) name)))
    (or (gethash key *cradle-stages*)
        (setf (gethash key *cradle-stages*) (compute-cradle-stage n name)))))

(defparameter *eager-cradle-limit* 6
  "The most spheres NEWTON-CRADLE builds eagerly by default: n = 7 needs more
than SBCL's default heap, n = 8 minutes and gigabytes (bench/cradle.lisp).")

(defun newton-cradle (n &key (lazy (> n *eager-cradle-limit*)))
  "G^n, the behaviour of Newton's cradle with N spheres (N >= 1): nodes are
right-nested trees of sphere states (POSITION . VELOCITY), leftmost sphere
first; see CRADLE-STAGES for how it is built and CRADLE-PAPER for the paper's
own. Built eagerly (a GRAPH) for N up to *EAGER-CRADLE-LIMIT*, on demand (a
LAZY-GRAPH, see LAZY-CRADLE) above it or with LAZY: GRAPH-REACHABLE and
GRAPH-SUCCESSORS take either."
  (if lazy
      (progn
        (check-argument 'newton-cradle 'n n (lambda (x) (typep x '(integer 1))) "a number of spheres (an integer >= 1)")
        (lazy-cradle n))
      (cradle-stage n :g^n)))

(defun cradle-paper (n)
  "The paper's G^n for N spheres, which has dead ends (stage :PAPER)."
  (cradle-stage n :paper))

(defun cradle-node (&rest spheres)
  "The cradle node of SPHERES, each a sphere state (POSITION . VELOCITY),
leftmost first: (S1 . (S2 . ... Sn))."
  (check-argument 'cradle-node 'spheres spheres
                  (lambda (x) (and x (every #'sphere-state-p x))) "one or more sphere states (POSITION . VELOCITY)")
  (reduce #'cons spheres :from-end t))

(defun cradle-spheres (node)
  "The sphere states of the cradle node NODE, leftmost first."
  (tree-flatten node :leafp #'sphere-state-p))
