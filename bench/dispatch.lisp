;;;; dispatch.lisp -- issue 13's "compiled vs planning at run time" where it
;;;; matters: the synthetic family at n = 16 and 20 (2^n states), where a
;;;; search from the current state costs what a compiled event's cube tests
;;;; save.  (Peedy's 144 states make run-time search cheap; its rows in
;;;; section 3 say little about the ratio.)

(in-package #:player-bench)

(defparameter *dispatch-sizes* '(16 20)
  "Synthetic sizes whose events are timed compiled and planned at run time.")

(defun naive-event-rate (runner machine defs names budget)
  "Send DEFS (with NAMES) in order to a fresh controller of MACHINE, planning
each goal at run time with RUNNER, until they are all sent or BUDGET seconds
of planning have passed (at least 3 events).  Beside it, a compiled controller
takes the same events, untimed.  Returns the events per second of run-time
planning, the events sent, and how many of them left both in the same state."
  (let ((planned (player:make-controller machine :presenter (player:make-null-presenter)))
        (compiled (player:make-controller machine :presenter (player:make-null-presenter)))
        (elapsed 0d0) (sent 0) (same 0))
    (loop for def across defs
          for name across names
          while (or (< sent 3) (< elapsed budget))
          do (let ((t0 (now)))
               (naive-send-event runner planned def)
               (incf elapsed (- (now) t0)))
             (player:send-event compiled name)
             (incf sent)
             (when (= (player.control::controller-bits compiled) (player.control::controller-bits planned))
               (incf same)))
    (values (/ sent elapsed) sent same)))

(defun bench-synthetic-dispatch (n &key (events 1000) (budget 3d0))
  "Rows: events per second of the synthetic spec of N variables through its
compiled closures (null presenter) and planned when each event is sent (a
forward BFS from the current state for each goal, bench/naive.lisp), and
their ratio (issue 13's target: at least 1000x)."
  (let* ((spec (define-synthetic-spec (make-synthetic-family n)))
         (machine (player:compile-spec spec))
         (names (random-event-sequence machine events))
         (defs (event-defs machine names))
         (controller (player:make-controller machine :presenter (player:make-null-presenter)))
         (compiled-rate (/ events (seconds-per-call (lambda ()
                                                      (loop for name across names
                                                            do (player:send-event controller name)))
                                                    :batches 9 :batch-seconds 0.1d0))))
    (multiple-value-bind (naive-rate sent same)
        (naive-event-rate (make-naive-runner machine) machine defs names budget)
      (let ((ratio (/ compiled-rate naive-rate)))
        (row (format nil "3. synthetic n=~D (~D states): events/s, compiled closures, null presenter" n (ash 1 n))
             (format-count compiled-rate) "" "")
        (row (format nil "   events/s, planning each goal when sent (BFS from the state~:[, ~D of ~D events~;~*~*~])"
                     (= sent events) sent events)
             (format-count naive-rate) "" "")
        (row (format nil "   ratio compiled / run-time planning, n=~D" n)
             (format-ratio ratio) ">= 1000x (issue 13)" (>= ratio 1000))
        (note "synthetic n=~D dispatch: ~D events drawn (seeded) from its ~D; run-time planning timed on the first ~D, after which the compiled and the run-time-planning controllers were in the same state ~D times"
              n events (length (player:event-names machine)) sent same)))
    (player:remove-spec (player:spec-name spec))))
