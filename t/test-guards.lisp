;;;; test-guards.lisp -- transition systems linked by guards
;;;; (src/compose/guards.lisp, issue 30 item 5).

(in-package #:player-tests)

(def-suite* guards :in player-tests)

(test guarded-cradle-is-the-cradle
  ;; Free swing while well behaved, the full cradle at collisions: the same
  ;; graph from every start (n <= 6), and the full system is asked only at
  ;; the states about to collide.
  (loop for n from 1 to 6
        do (loop for left from 0 to n
                 do (loop for right from 0 to (- n left)
                          do (let ((start (cradle-start n :left left :right right)))
                               (is (graph-equal (lazy-reachable (lazy-cradle n) start)
                                                (lazy-reachable (guarded-cradle n) start))
                                   "~D spheres, ~D/~D lifted" n left right)))))
  (let* ((full-calls 0)
         (full (lazy-cradle 5))
         (counting (make-lazy-graph (lambda (node) (incf full-calls) (lazy-successors full node))))
         (graph (guarded-graph #'cradle-well-behaved-p (cradle-free-swing 5) counting))
         (reached (lazy-reachable graph (cradle-start 5 :left 2))))
    (is (= 10 (graph-node-count reached)))
    ;; two collisions a period: ce-ce-cs-cs-cs and cs-cs-cs-cw-cw
    (is (= 2 full-calls))))

(test guards-in-graph-expressions
  ;; (guarded (state P TEST) CHEAP FULL): 0 and 1 step by +1 (cheap), 2 back to 0 (full)
  (let ((graph (graph-expression '(guarded (state x (< x 2))
                                   (restrict (complete (0 1 2)) (edge x y (= y (+ x 1))))
                                   (restrict (complete (0 1 2)) (edge x y (= y 0)))))))
    (is (equal '((0 . 1) (1 . 2) (2 . 0)) (graph-edges graph))))
  (handler-case (progn (graph-expression '(guarded (state x (> x 5)) (complete (0 1)) (complete (0 1))))
                       (fail "a guard that never holds was accepted"))
    (graph-expression-error (c) (is (search "never" (princ-to-string c)))))
  (signals graph-expression-error (graph-expression '(guarded (when x) (complete (0 1)) (complete (0 1))))))

(test guard-and-size-errors-at-the-command-line
  ;; one player: error: line naming the file and line, exit 1
  (check-cli-error 1 "guard-never.lisp:6:" "check" (fixture "guard-never.lisp"))
  (check-cli-error 1 "never" "check" (fixture "guard-never.lisp"))
  (check-cli-error 1 "graph-too-large.lisp:6:" "verify-graph" (fixture "graph-too-large.lisp") "--formula" "(AG (EX t))")
  (check-cli-error 1 "more than 500000" "verify-graph" (fixture "graph-too-large.lisp") "--formula" "(AG (EX t))"))
