;;;; test-cradle-physics.lisp -- the cradle that never gets stuck
;;;; (src/compose/cradle-physics.lisp) and the cradle built on demand
;;;; (lazy.lisp, lazy-cradle.lisp), issue 30 items 2 and 6.

(in-package #:player-tests)

(def-suite* cradle-physics :in player-tests)

(defun lifted-start (n left right)
  "The cradle node of N spheres, LEFT lifted at rest on the left, RIGHT on the right."
  (apply #'cradle-node (append (make-list left :initial-element '(-1 . 0))
                               (make-list (- n left right) :initial-element '(0 . 0))
                               (make-list right :initial-element '(1 . 0)))))

(defun map-cradle-starts (function n)
  "Call FUNCTION on LEFT, RIGHT and the start node of every lifted set of N spheres."
  (loop for left from 0 to n
        do (loop for right from 0 to (- n left)
                 do (funcall function left right (lifted-start n left right)))))

(defun rest-node-p (node)
  "Is every sphere of NODE hanging at rest?"
  (every (lambda (sphere) (equal sphere '(0 . 0))) (cradle-spheres node)))

(test cradle-never-stuck
  ;; Every reachable state of every start of n <= 6 spheres (n = 7 too in the
  ;; full tier) has exactly one successor; each step is physical by the
  ;; independent rules of STEP-PROBLEMS (test-compose.lisp); rest is reached
  ;; only from rest; the spheres that go out on the far side are as many as
  ;; were lifted on the near one (one side lifted), the outermost ones.
  (loop for n from 1 to (sweep-count 7 6)
        do (map-cradle-starts
            (lambda (left right start)
              (let ((graph (lazy-reachable (lazy-cradle n) start)))
                (dolist (node (graph-nodes graph))
                  (let ((next (graph-successors graph node)))
                    (is (= 1 (length next)) "~D spheres, ~D/~D lifted: ~S has ~D successors"
                        n left right (cradle-spheres node) (length next))
                    (when (= n (length (cradle-spheres node)))
                      (is (null (step-problems (cradle-spheres node) (cradle-spheres (first next))))
                          "~S -> ~S" (cradle-spheres node) (cradle-spheres (first next))))
                    (when (and (plusp (+ left right)) (first next))
                      (is (not (rest-node-p (first next))) "~D/~D lifted: came to rest" left right))))
                (when (and (plusp left) (zerop right) (< left n))
                  (let ((out (remove-duplicates
                              (loop for node in (graph-nodes graph)
                                    append (loop for (p) in (cradle-spheres node) for i from 0
                                                 when (= p 1) collect i)))))
                    (is (equal (loop for i from (- n left) below n collect i) (sort out #'<))
                        "~D of ~D lifted: spheres ~S went out" left n out)))))
            n)))

(test cradle-dead-ends-gone
  ;; The issue's cases: the paper's cradle has 4 dead ends with 2 of 5 lifted
  ;; and with one lifted at each end; the cradle has none.
  (flet ((dead-ends (graph) (count-if-not (lambda (node) (graph-successors graph node)) (graph-nodes graph))))
    (is (= 4 (dead-ends (graph-reachable (cradle-paper 5) (lifted-start 5 2 0)))))
    (is (= 4 (dead-ends (graph-reachable (cradle-paper 5) (lifted-start 5 1 1)))))
    (is (= 0 (dead-ends (graph-reachable (newton-cradle 5) (lifted-start 5 2 0)))))
    (is (= 0 (dead-ends (graph-reachable (newton-cradle 5) (lifted-start 5 1 1)))))
    ;; The issue's example dead end now moves on, as a cradle does.
    (is (equal '((0 . -1) (0 . -1) (0 . 0) (0 . 0) (0 . 0))
               (cradle-spheres (first (graph-successors
                                       (newton-cradle 5)
                                       (cradle-node '(0 . 0) '(0 . -1) '(0 . -1) '(0 . 0) '(0 . 0))))))))
  ;; The cradle is the paper's construction plus G18 and RESOLVED: every edge of
  ;; it keeps the paper's collision rule.
  (is (subgraph-p (newton-cradle 3) (cradle-stage 3 :collisions))))

(test lazy-equals-eager
  ;; The graph built on demand is the eager one, state for state, from every
  ;; start (n <= 4), for the cradle, the stage before RESOLVED and the paper's.
  (loop for n from 1 to 4
        do (dolist (stage '(:g^n :collisions :paper))
             (let ((eager (if (= n 1)
                              (cradle-stage 1 (ecase stage (:g^n :g^n) (:collisions :g^1+) (:paper :g^1)))
                              (cradle-stage n stage)))
                   (lazy (lazy-cradle n :stage stage)))
               (map-cradle-starts
                (lambda (left right start)
                  (when (graph-has-node-p eager start)
                    (is (graph-equal (graph-reachable eager start) (lazy-reachable lazy start))
                        "~D spheres, ~S, ~D/~D lifted" n stage left right)))
                n)
               ;; and node by node over the whole eager graph
               (dolist (node (graph-nodes eager))
                 (unless (equal (graph-successors eager node) (lazy-successors lazy node))
                   (fail "~D spheres ~S: ~S differs" n stage node)
                   (return)))))))

(test lazy-graph-errors
  (signals argument-error (lazy-cradle 0))
  (signals argument-error (lazy-cradle 3 :stage :nope))
  (signals argument-error (lazy-reachable 'x))
  (let ((player.compose::*lazy-node-limit* 10))
    (signals graph-error (lazy-reachable (make-lazy-graph (lambda (n) (list (1+ n)))) 0))))

(test newton-cradle-lazy-above-six
  ;; (newton-cradle 8) is built on demand and answers a reachability query;
  ;; graph-reachable and graph-successors take it; a spec takes (reachable ...) of it.
  (let ((cradle (newton-cradle 8)))
    (is (lazy-graph-p cradle))
    (is (= 10 (graph-node-count (graph-reachable cradle (cradle-start 8 :left 2)))))
    (is (= 1 (length (graph-successors cradle (cradle-start 8 :left 2))))))
  (is (graph-p (newton-cradle 3)))
  (is (graph-equal (graph-reachable (newton-cradle 4) (cradle-start 4 :left 1))
                   (graph-reachable (newton-cradle 4 :lazy t) (cradle-start 4 :left 1))))
  (is (= 10 (graph-node-count (graph-expression '(reachable (newton-cradle 8)
                                                  (cradle-node (-1 . 0) (-1 . 0) (0 . 0) (0 . 0) (0 . 0) (0 . 0) (0 . 0) (0 . 0)))))))
  (signals graph-expression-error (graph-expression '(newton-cradle 8)))
  (signals graph-expression-error (graph-expression '(sum (newton-cradle 8) (newton-cradle 8))))
  (signals graph-expression-error (graph-expression '(newton-cradle 11))))
