;;;; test-cradle-figures.lisp -- the paper's Figures 10 and 11 through the
;;;; public API (cradle-start, cradle-run, cradle-figure) and the spec's events
;;;; named from their captions (issue 30, item 3).

(in-package #:player-tests)

(def-suite* cradle-figures :in player-tests)

(defun run-positions (run)
  "Each state of RUN (cradle nodes) as its spheres' positions."
  (mapcar (lambda (node) (mapcar #'car (cradle-spheres node))) run))

(test cradle-figures-runs
  ;; Figure 10, "starting with a single displaced ball": the ball falls, the
  ;; one at the far end goes out, and only those two ever move.
  (let ((run (cradle-figure 10)))
    (is (equal '((-1 . 0) (0 . 0) (0 . 0) (0 . 0) (0 . 0)) (cradle-spheres (first run))))
    (is (equal '((0 . 0) (0 . 0) (0 . 0) (0 . 0) (1 . 0)) (cradle-spheres (car (last run)))))
    (is (every (lambda (positions) (equal '(0 0 0) (subseq positions 1 4))) (run-positions run))))
  ;; Figure 11, "one displaced ball at one end and two at the other": after
  ;; the collision two go out on the left and one on the right.
  (let ((run (cradle-figure 11)))
    (is (equal '(-1 0 0 1 1) (first (run-positions run))))
    (is (equal '(-1 -1 0 0 1) (car (last (run-positions run)))))
    (is (every (lambda (node) (every (lambda (s) (zerop (cdr s))) (cradle-spheres node)))
               (list (first run) (car (last run))))))
  (is (equal (cradle-figure 10) (cradle-run 5 :left 1)))
  (is (= 9 (length (cradle-run 5 :left 1 :steps 8))))
  (signals argument-error (cradle-figure 12))
  (signals argument-error (cradle-start 3 :left 2 :right 2)))

(test cradle-figures-events
  ;; The spec plays each figure from its caption's event, along the run.
  (let ((spec (first (load-spec (checkout-file "specs/newtons-cradle.lisp")))))
    (loop for (event figure op) in '((ev-simple-example-animation 10 "LIFT-ONE-LEFT")
                                     (ev-more-complex-example 11 "LIFT-ONE-LEFT-TWO-RIGHT"))
          do (let ((controller (make-controller (compile-spec spec))))
               (is (eq t (send-event controller event)))
               (let ((ops (loop for line in (trace-lines (controller-presenter controller))
                                when (eq (first line) :op) collect (symbol-name (second line))))
                     (run (cradle-figure figure)))
                 (is (string= op (first ops)))
                 (is (equal (loop for (a b) on run while b
                                  collect (format nil "FROM-~A-TO-~A" (player.compose::cradle-node-name a)
                                                  (player.compose::cradle-node-name b)))
                            (rest ops))
                     "~A: ~S" event ops))))))
