;;;; dot.lisp -- `player dot`: the plannable state graph as Graphviz.

(in-package #:player.cli)

(defmethod read-option-value ((type (eql :state-expression)) text option)
  ;; One datum read as spec files are (READ-CLI-FORM); whether it is a state
  ;; expression of the spec is for the spec to say.
  (multiple-value-bind (form one) (read-cli-form text (option-name option))
    (unless one (bad-option-value option text "one state expression, e.g. posture.sit or (and a b)"))
    (check-form-structure form :what (option-name option))
    form))

(defmethod read-option-value ((type (eql :graph-file)) text option)
  (unless (graph-file-format (uiop:parse-native-namestring text))
    (bad-option-value option text "a file name ending in .dot, .gv, .svg or .png"))
  text)

(define-command "dot" (file &key spec no-code goal out)
    (:summary "write the plannable state graph as Graphviz"
     :description "Nodes are the plannable states (all of them, or for a large spec those
reachable from the initial state), labelled var=value; the initial state has
a double border.  Each op whose precondition holds in a state and whose
effects change it is an arrow, labelled with the op (dashed: must-ask).  With
--goal, the states where G holds are shaded and the goal's plan tree is drawn
beside: from each state, the steps of the plan the machine runs.  An .svg or
.png is drawn by Graphviz's dot (Debian package graphviz)."
     :arguments ("SPEC-FILE")
     :options ("--spec" "--no-code"
               ("--goal" :state-expression "G"
                "shade the states where G holds and draw its plan tree; G is a state expression as written in the spec, e.g. posture.sit, a class name, or \"(and a b)\"")
               ("--out" :graph-file "FILE"
                "write FILE.dot (or .gv) as text, or FILE.svg or FILE.png drawn by Graphviz"))
     :output "the DOT text on standard output, or the --out file (its path on standard output)")
  (let ((machine (plan-spec (choose-spec file spec :allow-code (not no-code)))))
    (if out
        (format t "; wrote ~A~%" (uiop:native-namestring (write-state-graph-file machine out :goal goal)))
        (write-state-graph machine *standard-output* :goal goal))))
