;;;; test-repl.lisp -- what a REPL user sees: Player's objects print on one
;;;; short line, and a controller's default trace stays bounded.

(in-package #:player-tests)

(def-suite* repl :in player-tests)

(defun one-short-line-p (object &optional (limit 200))
  "Does OBJECT print as one line of at most LIMIT characters?"
  (let ((text (prin1-to-string object)))
    (and (not (find #\Newline text)) (<= (length text) limit))))

(test objects-print-on-one-line
  (let* ((spec (first (load-spec (checkout-file "specs/peedy.lisp"))))
         (machine (compile-spec spec))
         (controller (make-controller machine :initial-state '((alert . snore)))))
    (send-event controller 'ev-search)
    (is (string= "#<SPEC peedy 7 vars, 44 ops, 38 events>" (prin1-to-string spec)))
    (is (search "peedy 13 goals, 144 states, 38 events" (prin1-to-string machine)))
    (is (eql 0 (search "#<CONTROLLER peedy t=5.5 holding-note=true posture=stand alert=awake"
                       (prin1-to-string controller)))
        "~A" controller)
    (is (search "#<MACHINE peedy 13 goals, 144 states>" (prin1-to-string (plan-spec spec))))
    (dolist (object (append (list spec machine controller (controller-presenter controller) (plan-spec spec))
                            (coerce (player.planner::machine-goal-table machine) 'list)
                            (coerce (player.planner::goal-plans (aref (player.planner::machine-goal-table machine) 0)) 'list)
                            (player.spec::spec-ops spec) (player.spec::spec-variables spec)
                            (player.spec::spec-events spec) (player.spec::spec-autoscripts spec)
                            (check-spec spec)))
      (is (one-short-line-p object) "~S prints long" (type-of object)))))

(test the-default-trace-is-bounded
  (with-spec (spec toggling
              (state-variable on boolean false)
              (op switch-on :add on) (op switch-off :sub on)
              (event ev-on :state on) (event ev-off :state (not on)))
    (let ((controller (make-controller (compile-spec spec))))
      (dotimes (i (* 3 player.control::*default-trace-limit*))
        (send-event controller (if (evenp i) 'ev-on 'ev-off)))
      (let ((lines (trace-lines (controller-presenter controller))))
        (is (<= player.control::*default-trace-limit* (length lines) (* 2 player.control::*default-trace-limit*)))
        (is (equal "(:state (on . nil))" (trace-line-string (car (last lines))))
            "the newest lines are kept")))
    (let ((presenter (make-trace-presenter :limit 5))
          (unbounded (make-trace-presenter)))
      (let ((a (make-controller (compile-spec spec) :presenter presenter))
            (b (make-controller (compile-spec spec) :presenter unbounded)))
        (dotimes (i 100)
          (send-event a (if (evenp i) 'ev-on 'ev-off))
          (send-event b (if (evenp i) 'ev-on 'ev-off))))
      (is (<= 5 (length (trace-lines presenter)) 10))
      (is (equal (last (trace-lines unbounded) 5) (last (trace-lines presenter) 5)))
      (is (= 300 (length (trace-lines unbounded)))))
    (signals argument-error (make-trace-presenter :limit 0))))
