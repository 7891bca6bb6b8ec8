;;;; trees.lisp -- binary trees of values and the sequences they flatten to
;;;; (Clark & Palmer, Appendix A).
;;;;
;;;; "Pairs of elements, (x, y), can be nested to produce binary trees
;;;; ((a, b), (x, (y, z))). By traversing the trees from left to right, the tree
;;;; imposes a total ordering on the values at the leaves of the tree."
;;;; A tree is a leaf or a cons (LEFT . RIGHT) of trees. What a leaf is depends
;;;; on the values: every function here takes LEAFP, by default ATOM; Newton's
;;;; cradle, whose leaves are sphere states (POSITION . VELOCITY), passes
;;;; SPHERE-STATE-P. Sequences are lists.

(in-package #:player.compose)

(defun tree-p (x &key (leafp #'atom))
  "Is X a binary tree: a leaf, or a cons of trees (an atom that is not a leaf
is not a tree)?"
  (cond ((funcall leafp x) t)
        ((consp x) (and (tree-p (car x) :leafp leafp) (tree-p (cdr x) :leafp leafp)))
        (t nil)))

(defun tree-left (tree &key (leafp #'atom))
  "left(t): \"The operator left extracts the leftmost leaf value of a binary tree.\""
  (loop until (or (funcall leafp tree) (atom tree))
        do (setf tree (car tree)))
  tree)

(defun tree-right (tree &key (leafp #'atom))
  "right(t): \"The operator right extracts the rightmost leaf value of a binary tree.\""
  (loop until (or (funcall leafp tree) (atom tree))
        do (setf tree (cdr tree)))
  tree)

(defun tree-merge (tree1 tree2 &key (leafp #'atom))
  "merge(t1, t2): \"produces a new binary tree in which either the right most
leaf value of t1 has been replaced by t2 or the leftmost leaf value of t2 has
been replaced by t1. The outcome of merge is non-deterministic since either
outcome will do\". This one always replaces the rightmost leaf of TREE1 by
TREE2, so merging (a . b) with (b . c) gives (a . (b . c)), and repeated merges
build right-nested trees, (a . (b . (c . d)))."
  (if (or (funcall leafp tree1) (atom tree1))
      tree2
      (cons (car tree1) (tree-merge (cdr tree1) tree2 :leafp leafp))))

(defun tree-product (tree1 tree2 &key (leafp #'atom))
  "t1 × t2: \"the binary tree which is constructed by pairing the leaves of t1
and t2 which occur at exactly the same position, for example
((a, b), (c, d)) × ((v, w), (x, y)) = (((a, v), (b, w)), ((c, x), (d, y))).
If t1 and t2 do not have the same shape then t1 × t2 is not defined\": a
GRAPH-ERROR naming both trees."
  (labels ((zip (a b)
             (let ((leaf-a (or (funcall leafp a) (atom a)))
                   (leaf-b (or (funcall leafp b) (atom b))))
               (cond ((and leaf-a leaf-b) (cons a b))
                     ((or leaf-a leaf-b)
                      (graph-fail (cons tree1 tree2) "tree-product: ~A and ~A do not have the same shape"
                                  (node-text tree1) (node-text tree2)))
                     (t (cons (zip (car a) (car b)) (zip (cdr a) (cdr b))))))))
    (zip tree1 tree2)))

(defun tree-flatten (tree &key (leafp #'atom))
  "↓t: \"A binary tree is flattened to produce a sequence of the values at its
leaves using the operator ↓, for example ↓((a, b), (c, d)) = abcd.\""
  (let ((leaves '()))
    (labels ((walk (x)
               (if (or (funcall leafp x) (atom x))
                   (push x leaves)
                   (progn (walk (car x)) (walk (cdr x))))))
      (walk tree))
    (nreverse leaves)))

;;; Sequences

(defun seq-rev (sequence)
  "rev(s): \"A sequence s is reversed using the operator rev\"."
  (reverse sequence))

(defun seq-restrict (sequence predicate)
  "s \\ p: the elements of SEQUENCE for which PREDICATE holds, in order."
  (remove-if-not predicate sequence))

(defun seq-count (sequence)
  "#s: \"The length of a sequence is produced by the operator #.\""
  (length sequence))

(defun seq-suffixes (sequence)
  "↑s: \"the sequence whose elements are pairs (x, s') where x is an element of
s and s' is the suffix sequence of x in s, for example
↑(abcd) = (a, bcd)(b, cd)(c, d)(d, ε)\": a list of conses (X . SUFFIX)."
  (loop for tail on sequence collect (cons (car tail) (cdr tail))))

(defun seq-all (predicate)
  "all(p): \"a new predicate which is applied to a sequence s and is true when p
is true for each element of s.\""
  (lambda (sequence) (every predicate sequence)))

(defun seq-exists (predicate)
  "exists(p): \"a predicate which is applied to a sequence s and is true when p
is true for at least one element of s.\""
  (lambda (sequence) (some predicate sequence)))
