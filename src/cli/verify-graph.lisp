;;;; verify-graph.lisp -- `player verify-graph`: model-check a CTL formula on
;;;; a spec's behaviour (its reachable state graph), with a counterexample.

(in-package #:player.cli)

(defmethod read-option-value ((type (eql :formula)) text option)
  ;; One s-expression, read as data (READ-CLI-FORM), never evaluated.
  (multiple-value-bind (formula one) (read-cli-form text (option-name option))
    (if one formula (bad-option-value option text "one formula, e.g. \"(AG (EX t))\""))))

(define-command "verify-graph" (file &key spec no-code formula dot)
    (:summary "model-check a CTL formula on the spec's behaviour"
     :description "Checks the CTL --formula on the states the spec's ops reach from its
initial state (for a spec made by (:graph ...), its graph). Formulas are
s-expressions over the spec's state expressions: (AG (EX t)) (never stuck),
(EF cradle.cs-cs-cs-cs-cs), (AG (not EXPR)), (AF EXPR), (EU A B), (AU A B),
(EG EXPR), (AX F), (EX F), with and, or, not, implies. Paths may end at a
state with no successor. When the formula fails in the initial state, a
counterexample is printed: a path of states, or a lasso that loops back for
ever; --dot FILE writes it as Graphviz."
     :arguments ("SPEC-FILE")
     :options ("--spec" "--no-code"
               ("--formula" :formula "F" "the CTL formula to check, e.g. \"(AG (EX t))\"")
               ("--dot" :string "FILE" "write the counterexample as Graphviz (.dot) to FILE"))
     :output "\"holds: F\" and exit status 0; or \"fails: F\", the counterexample's states
        one per line on standard output, a player: error: line and exit status 1")
  (unless formula (usage-fail "verify-graph needs --formula F (e.g. --formula \"(AG (EX t))\")"))
  (let ((spec (choose-spec file spec :allow-code (not no-code)))
        (text (let ((*package* (find-package '#:player-user)) (*print-pretty* nil))
                (string-downcase (prin1-to-string formula)))))
    (multiple-value-bind (holds path behaviour) (verify spec formula)
      (if holds
          (format t "holds: ~A (~D state~:P)~%" text (behaviour-state-count behaviour))
          (progn
            (format t "fails: ~A; counterexample~:[~; (a lasso)~]:~%" text (counterexample-loop path))
            (print-counterexample behaviour path *standard-output*)
            (when dot
              (with-atomic-output-file (out dot :follow-links t)
                (write-counterexample-dot behaviour path out))
              (format t "; wrote ~A~%" dot))
            (error 'player-error-with-message
                   :message (format nil "~A does not hold in the initial state of ~A"
                                    text (lisp-text (spec-name spec)))))))))
