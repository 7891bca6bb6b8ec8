;;;; check.lisp -- `player check`: a spec's diagnostics, errors and warnings.

(in-package #:player.cli)

(define-command "check" (file &key spec no-code scripts)
    (:summary "print the spec's diagnostics"
     :description "For a spec made by (:graph ...), as errors: a reachable state with no
successor (deadlock-freedom, (AG (EX t)), fails) and event goals no path from
the initial state reaches. For every spec: goals unreachable from some or all states, ops nothing uses, depth
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
  ;; A scene file: each spec its members play, once, under a ; line naming them.
  (when-let (scene (and (scene-file-p file) (command-cast file spec nil (not no-code))))
    (let ((errors (loop for spec-name in (remove-duplicates (mapcar #'cast-member-spec (cast-members scene))
                                                            :from-end t)
                        do (format t "; ~A (~{~A~^, ~})~%" (lisp-text spec-name)
                                   (loop for member in (cast-members scene)
                                         when (eq (cast-member-spec member) spec-name)
                                           collect (lisp-text (cast-member-name member))))
                        sum (print-spec-diagnostics (find-spec spec-name) scripts))))
      (when (plusp errors)
        (error 'player-error-with-message
               :message (format nil "check found ~D error~:P in scene ~A (see standard output)"
                                errors (lisp-text (cast-name scene))))))
    (return-from command-check))
  (let* ((spec (choose-spec file spec :allow-code (not no-code)))
         (errors (print-spec-diagnostics spec scripts)))
    (when (plusp errors)
      (error 'player-error-with-message
             :message (format nil "check found ~D error~:P in spec ~A (see standard output)"
                              errors (lisp-text (spec-name spec)))))))

(defun print-spec-diagnostics (spec scripts)
  "Print SPEC's diagnostics (with the script library SCRIPTS, else its own),
errors first, or that it has none; return how many errors there were."
  (let* ((behaviour (graph-spec-diagnostics spec)) ; (:graph ...) specs: stuck states, goals no path reaches
         (others (append (code-diagnostics spec) (check-spec spec) (script-diagnostics spec scripts)))
         (diagnostics (append behaviour others))
         (errors (append behaviour (remove-if-not #'diagnostic-error-p others)))
         (warnings (remove-if #'diagnostic-error-p others)))
    (dolist (d errors)
      (format t "error: ~A~%" (diagnostic-message d)))
    (dolist (d warnings)
      (format t "warning: ~A~%" (diagnostic-message d)))
    (unless diagnostics
      (format t "~A: no problems found~%" (lisp-text (spec-name spec))))
    (length errors)))
