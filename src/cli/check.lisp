;;;; check.lisp -- `player check`: a spec's diagnostics, errors and warnings.

(in-package #:player)

(define-command "check" (file &key spec no-code scripts)
    (:summary "print the spec's diagnostics"
     :description "Goals unreachable from some or all states, ops nothing uses, depth
truncation, states unreachable from the initial state; with a script library
(the spec's (:scripts FILE) or --scripts), everything playing the spec would
fail on -- a library that cannot be read, and every item of a script the spec
needs that its body cannot perform (each motor call is set up as a driver on a
body of the spec's skeleton: unknown poses, joints, roles or DOFs, written
angles past a joint's limits; unknown objects) -- as errors, then the scripts
it lacks and the ops whose :duration differs from their script's. Exit status
1 when there is an error, 0 with warnings only."
     :arguments ("SPEC-FILE")
     :options ("--spec" "--no-code" "--scripts")
     :output "one error: or warning: line per problem on standard output (errors
        first); with an error, a last player: error: line on standard error and
        exit status 1")
  (let* ((spec (choose-spec file spec :allow-code (not no-code)))
         (diagnostics (append (check-spec spec) (script-diagnostics spec scripts)))
         (errors (remove-if-not #'diagnostic-error-p diagnostics))
         (warnings (remove-if #'diagnostic-error-p diagnostics)))
    (dolist (d errors)
      (format t "error: ~A~%" (diagnostic-message d)))
    (dolist (d warnings)
      (format t "warning: ~A~%" (diagnostic-message d)))
    (cond (errors
           (error 'player-error-with-message
                  :message (format nil "check found ~D error~:P in spec ~A (see standard output)"
                                   (length errors) (lisp-text (spec-name spec)))))
          ((null diagnostics)
           (format t "~A: no problems found~%" (lisp-text (spec-name spec)))))))
