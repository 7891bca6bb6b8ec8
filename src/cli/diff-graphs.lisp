;;;; diff-graphs.lisp -- `player diff-graphs`: did a modification of a
;;;; behaviour make it inconsistent (a state that gets stuck) or incomplete
;;;; (a move removed)?

(in-package #:player.cli)

(define-command "diff-graphs" (before after &key no-code)
    (:summary "compare two specs' behaviours: new dead ends, moves removed or added"
     :description "Compares the reachable state graphs of the spec in BEFORE-FILE and the
spec in AFTER-FILE (each file's only spec), states matched by name. The
modification is inconsistent when a state of AFTER has no successor though it
had one in BEFORE (or is new), incomplete when a move of BEFORE between states
AFTER still has is gone. Moves and states added or removed are listed too."
     :arguments ("BEFORE-FILE" "AFTER-FILE")
     :options ("--no-code")
     :output "one line per difference on standard output (inconsistent:, incomplete:,
        added:, removed:), or \"same behaviour\"; exit status 1, with a player:
        error: line, when AFTER is inconsistent or incomplete")
  (let* ((a (choose-spec before nil :allow-code (not no-code)))
         (b (choose-spec after nil :allow-code (not no-code)))
         (diff (diff-graphs a b)))
    (dolist (name (graph-diff-dead-ends diff))
      (format t "inconsistent: ~A has no successor~%" name))
    (loop for (from . to) in (graph-diff-removed diff)
          do (format t "incomplete: the move ~A -> ~A is gone~%" from to))
    (loop for (from . to) in (graph-diff-added diff)
          do (format t "added: the move ~A -> ~A~%" from to))
    (dolist (name (graph-diff-removed-states diff)) (format t "removed: the state ~A is no longer reached~%" name))
    (dolist (name (graph-diff-added-states diff)) (format t "added: the state ~A~%" name))
    (when (and (graph-diff-consistent-p diff) (null (graph-diff-added diff))
               (null (graph-diff-removed-states diff)) (null (graph-diff-added-states diff)))
      (format t "same behaviour~%"))
    (unless (graph-diff-consistent-p diff)
      (error 'player-error-with-message
             :message (format nil "~A makes the behaviour of ~A ~{~A~^ and ~}" after before
                              (append (and (graph-diff-dead-ends diff) (list "inconsistent (states with no successor)"))
                                      (and (graph-diff-removed diff) (list "incomplete (moves removed)"))))))))
