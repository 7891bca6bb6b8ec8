;;;; run.lisp -- `player run`: play events and print the trace.

(in-package #:player)

(define-command "run" (file &key spec no-code initial events backend)
    (:summary "play events in simulated time and print the trace"
     :description "Each event starts when the previous one's last op has ended.  A failed
goal shows as (:fail EVENT :goal GOAL :time T) and the next event carries on."
     :arguments ("SPEC-FILE")
     :options ("--spec" "--no-code" "--initial" "--events"
               ("--backend" (:choice "lisp" "c++") "lisp|c++"
                "run the controller as Lisp closures, or as generated C++ (needs g++)"
                :default "lisp"))
     :output "the trace on standard output, one s-expression per line; without
        --events, the initial state")
  (let* ((spec (choose-spec file spec :allow-code (not no-code)))
         (machine (compile-spec spec))
         (lisp (string= backend "lisp"))
         (controller (make-controller machine :initial-state initial
                                              :presenter (make-trace-presenter
                                                          :stream (and lisp *standard-output*)))))
    (dolist (event events)
      (find-compiled-event controller event))
    (cond ((not lisp)
           (format t "~{~A~%~}" (run-c++-trace machine :initial-state initial :events events)))
          (events
           (dolist (event events)
             (send-event controller event)))
          (t (present-state (controller-presenter controller) controller)))))
