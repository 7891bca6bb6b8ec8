;;;; nodes.lisp -- nodes as Lisp values: EQUAL, a full-depth hash, a total order.
;;;;
;;;; Clark & Palmer (Appendix A): "A graph is a 4-tuple (N, E, s, t) where N is
;;;; a set of nodes, E is a set of edges". Here a node is any Lisp value compared
;;;; with EQUAL: numbers, symbols, strings, and binary trees as conses
;;;; (LEFT . RIGHT), which is what products build. SXHASH stops a few levels
;;;; into a cons, so the deep trees of Newton's cradle would collide; node
;;;; tables use NODE=, a hash table test with a hash of the whole tree. Edges
;;;; are conses (SOURCE . TARGET), so they hash the same way. NODE< orders any
;;;; two nodes, so every list this module returns is sorted and deterministic.

(in-package #:player.compose)

(defun node= (a b)
  "Nodes are the same when they are EQUAL."
  (equal a b))

(declaim (inline hash-mix))
(defun hash-mix (a b)
  "Two non-negative fixnum hashes combined into one."
  (declare (type (and fixnum unsigned-byte) a b))
  (logand most-positive-fixnum
          (logxor (* (logand a #xFFFFFFFFFFFF) 1099511628211)
                  (+ b #x9E3779B97F4A7C15 (ash a -17)))))

(defun node-hash (node)
  "A hash of NODE consistent with EQUAL that looks at the whole tree."
  (if (consp node)
      (hash-mix (node-hash (car node)) (node-hash (cdr node)))
      (sxhash node)))

(sb-ext:define-hash-table-test node= node-hash)

(defun make-node-table ()
  "An empty hash table keyed by nodes (or edges) under EQUAL."
  (make-hash-table :test 'node=))

(defun node-rank (node)
  "The kind of NODE, as its place in the order: reals, characters, strings,
symbols, conses, anything else."
  (typecase node
    (real 0) (character 1) (string 2) (symbol 3) (cons 4) (t 5)))

(defun node-compare (a b)
  "-1, 0 or 1 as A sorts before, with, or after B: by kind, then reals by value
(an integer before an equal float), strings and characters by CHAR<, symbols
by package then name, conses by car then cdr."
  (let ((ra (node-rank a)) (rb (node-rank b)))
    (cond ((< ra rb) -1)
          ((> ra rb) 1)
          (t (case ra
               (0 (cond ((< a b) -1) ((> a b) 1)
                        ((equal a b) 0)
                        (t (let ((ta (real-kind a)) (tb (real-kind b)))
                             (cond ((< ta tb) -1) ((> ta tb) 1) (t 0))))))
               (1 (cond ((char< a b) -1) ((char> a b) 1) (t 0)))
               (2 (cond ((string< a b) -1) ((string> a b) 1) (t 0)))
               (3 (let ((pa (let ((p (symbol-package a))) (if p (package-name p) "")))
                        (pb (let ((p (symbol-package b))) (if p (package-name p) ""))))
                    (cond ((string< pa pb) -1) ((string> pa pb) 1)
                          ((string< (symbol-name a) (symbol-name b)) -1)
                          ((string> (symbol-name a) (symbol-name b)) 1)
                          (t 0))))
               (4 (let ((c (node-compare (car a) (car b))))
                    (if (zerop c) (node-compare (cdr a) (cdr b)) c)))
               (t (node-compare (node-text a) (node-text b))))))))

(defun real-kind (real)
  "A number for REAL's type, to order 1 before 1.0 (equal in value, not EQUAL)."
  (typecase real (integer 0) (ratio 1) (single-float 2) (double-float 3) (t 4)))

(defun node< (a b)
  "True when node A sorts strictly before node B (see NODE-COMPARE)."
  (minusp (node-compare a b)))

(defun sort-nodes (nodes)
  "A fresh list of NODES in NODE< order."
  (sort (copy-list nodes) #'node<))
