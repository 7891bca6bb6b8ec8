;;;; test-cradle-timing.lisp -- timed transitions and the granularity
;;;; function (issue 30, item 5): durations carried by edges become op
;;;; durations; the cradle's swings take a pendulum's quarter period and pass
;;;; through intermediate angles, fastest at the bottom.

(in-package #:player-tests)

(def-suite* cradle-timing :in player-tests)

(test durations-become-op-durations
  (let* ((graph (make-graph '(a b c) '((a . b) (b . c) (c . a))))
         (timed (graph-with-durations graph (list (cons (lambda (s tg) (declare (ignore tg)) (eq s 'a)) 0.25))
                                      :default 2)))
    (is (not (graph-timed-p graph)))
    (is (graph-timed-p timed))
    (is (graph-equal graph timed))
    (is (= 0.25 (graph-edge-duration timed 'a 'b)))
    (is (= 2 (graph-edge-duration timed 'b 'c)))
    (is (= 1 (graph-edge-duration graph 'b 'c)))
    (signals graph-error (graph-edge-duration timed 'a 'c))
    (signals argument-error (graph-with-durations graph (lambda (s tg) (declare (ignore s tg)) 1) :default -1))
    (signals graph-error (graph-with-durations graph (lambda (s tg) (declare (ignore s tg)) "long")))
    ;; graph->spec: each op takes its edge's time; an untimed graph's ops the unit
    (flet ((durations (g) (loop for form in (graph->spec-forms g :start 'a)
                                when (and (consp form) (string= (symbol-name (first form)) "OP"))
                                  collect (getf (cddr form) :duration))))
      (is (equal '(0.25 2 2) (durations timed)))
      (is (equal '(nil nil nil) (durations graph))))))

(test cradle-spec-is-timed
  ;; swings a quarter period of the strings' pendulum, turns and collisions an
  ;; instant, lifts a second; ev-lift-two-left's plan takes their sum.
  (let* ((spec (first (load-spec (checkout-file "specs/newtons-cradle.lisp"))))
         (quarter (* (/ pi 2) (sqrt (/ 0.35d0 9.81d0)))))
    (dolist (op (player.spec::spec-ops spec))
      (let ((name (symbol-name (player.spec::op-name op)))
            (duration (player.spec::op-duration op)))
        (cond ((search "LIFT" name) (is (= 1 duration)))
              (t (let* ((to (search "-TO-" name))
                        (moves (not (equal (decode-cradle-name (subseq name 5 to))
                                           (decode-cradle-name (subseq name (+ 4 to)))))))
                   (is (< (abs (- duration (if moves quarter 0.05d0))) 1d-3) "~A: ~A" name duration))))))))

(test pendulum-refinement
  ;; falling from the left extreme to the bottom, the angle changes slowly at
  ;; first and fastest at the end; rising, the reverse; a sphere that stays, stays.
  (let* ((lifted (cradle-node '(-1 . 1) '(0 . 0)))
         (bottom (cradle-node '(0 . 1) '(0 . 0)))
         (top (cradle-node '(1 . 1) '(0 . 0)))
         (fall (cradle-refinement lifted bottom 8))
         (rise (cradle-refinement bottom top 8)))
    (flet ((angles (samples) (mapcar #'cadr samples))
           (steps (list) (loop for (a b) on list while b collect (abs (- b a)))))
      (is (= 9 (length fall)))
      (is (< (abs (- (first (angles fall)) (player.compose::cradle-angle -1))) 1d-9))
      (is (< (abs (car (last (angles fall)))) 1d-9))
      (let ((fall-steps (steps (angles fall))) (rise-steps (steps (angles rise))))
        (is (apply #'< fall-steps) "falling speeds up: ~S" fall-steps)
        (is (apply #'> rise-steps) "rising slows down: ~S" rise-steps))
      (is (every (lambda (sample) (zerop (third sample))) fall)))
    (signals argument-error (cradle-refinement lifted bottom 0))))
