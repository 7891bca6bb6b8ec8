;;;; run.lisp -- `player run`: play events and print the trace.

(in-package #:player.cli)

(define-command "run" (file &key spec no-code initial events at when-busy backend cast)
    (:summary "play events in simulated time and print the trace"
     :description "Each event starts when the previous one's last op has ended; an event
given as EV@T arrives at T seconds instead, and if another is still running,
its :when-busy policy decides (queue, preempt, override or interleave).  A
failed goal shows as (:fail EVENT :goal GOAL :time T) and the next event
carries on."
     :arguments ("SPEC-FILE")
     :options ("--spec" "--no-code" "--initial" "--events" "--at" "--when-busy" "--cast"
               ("--backend" (:choice "lisp" "c++") "lisp|c++"
                "run the controller as Lisp closures, or as generated C++ (needs g++)"
                :default "lisp"))
     :output "the trace on standard output, one s-expression per line; without
        --events, the initial state; for a scene (a scene file, or --cast),
        each member's lines in turn, prefixed MEMBER:")
  (when-let (scene (command-cast file spec cast (not no-code)))
    (unless (string= backend "lisp") (usage-fail "--backend c++ plays one controller, not a scene"))
    (run-scene scene :initial initial :events events :at at :when-busy (policy-keyword when-busy))
    (return-from command-run))
  (let* ((spec (choose-spec file spec :allow-code (not no-code)))
         (machine (compile-spec spec))
         (lisp (string= backend "lisp"))
         (timed (or (timed-scenario-p events at) when-busy))
         (controller (make-controller machine :initial-state initial :timed timed
                                              :presenter (make-trace-presenter
                                                          :stream (and lisp *standard-output*)))))
    (dolist (entry events)
      (find-compiled-event controller (event-entry-name entry)))
    (check-scenario-times events at)
    (cond ((not lisp)
           (format t "~{~A~%~}" (run-c++-trace machine :initial-state initial :events events :until at
                                                       :when-busy (policy-keyword when-busy))))
          ((or events at)
           (play-events controller events :until at :when-busy (policy-keyword when-busy))
           (finish-trace (controller-presenter controller)))
          (t (present-state (controller-presenter controller) controller)))))

(defun check-scenario-times (events at)
  "A USAGE-ERROR when --at stops the clock before an event of EVENTS arrives."
  (let ((late (and at (find-if (lambda (entry) (and (consp entry) (> (cdr entry) at))) events))))
    (when late
      (usage-fail "--at ~A stops the clock before ~A@~A arrives" (format-number at)
                  (car late) (format-number (cdr late))))))
