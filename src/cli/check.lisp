;;;; check.lisp -- `player check`: a spec's diagnostics.

(in-package #:player)

(define-command "check" (file &key spec no-code scripts)
    (:summary "print the spec's diagnostics"
     :description "Goals unreachable from some or all states, ops nothing uses, depth
truncation, states unreachable from the initial state; with a script library
(the spec's (:scripts FILE) or --scripts), the scripts it lacks and the ops
whose :duration differs from their script's."
     :arguments ("SPEC-FILE")
     :options ("--spec" "--no-code" "--scripts")
     :output "one warning: line per problem on standard output")
  (let* ((spec (choose-spec file spec :allow-code (not no-code)))
         (diagnostics (append (check-spec spec) (script-diagnostics spec scripts))))
    (if diagnostics
        (dolist (d diagnostics)
          (format t "warning: ~A~%" (diagnostic-message d)))
        (format t "~A: no problems found~%" (lisp-text (spec-name spec))))))
