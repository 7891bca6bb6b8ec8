;;;; verify.lisp -- `player verify`: replay a recording made by `player
;;;; record` on a spec file and report the first difference.

(in-package #:player.cli)

(defmethod read-option-value ((type (eql :tolerance)) text option)
  ;; A real from 0: how far a replayed frame's number may be from the recorded one.
  (let ((value (read-cli-value text)))
    (unless (and (realp value) (finite-real-p value) (>= value 0))
      (bad-option-value option text "a number from 0 (e.g. 1e-4)"))
    value))

(define-command "verify" (file trace &key no-code tolerance)
    (:summary "replay a recorded scenario and report the first difference"
     :description "Plays the scenario of TRACE-FILE (written by `player record`) on the
spec of SPEC-FILE named in the recording, and compares: the trace line by line
as text, then the body frames number by number within --tolerance.  The first
difference is the error message, with exit status 1: `t/golden/x.trace:
trace line 7 (file line 22): expected (:op sit ...), got (:op land ...)`,
`the recording has 12 trace lines, the replay 10; ...`, or `frame 3 at 0.75 s
(file line 40): body peedy, joint neck, dof x: expected 22.2, got 22.4
(tolerance 0.0001)`."
     :arguments ("SPEC-FILE" "TRACE-FILE")
     :options ("--no-code"
               ("--tolerance" :tolerance "X" "how far a frame's number may be from the recorded one"
                :default 1d-4 :default-text "0.0001"))
     :output "\"ok: N lines match\" on standard output, or the first difference on
        standard error with exit status 1")
  (let* ((recording (read-recording trace))
         (verification (verify-recording recording :spec-file file :allow-code (not no-code)
                                                   :tolerance tolerance)))
    (if (verification-ok-p verification)
        (format t "~A~%" (verification-message verification))
        (error 'recording-mismatch
               :verification verification
               :message (format nil "~A: ~A" trace (verification-message verification))))))
