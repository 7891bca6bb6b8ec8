;;;; dot.lisp -- a state graph (state-graph.lisp) as Graphviz DOT text, and
;;;; rendered to SVG or PNG by Graphviz's dot program (Debian package graphviz).
;;;;
;;;; The picture: one box per state, labelled with its literals (posture=sit,
;;;; one per line), the initial state with a double border, a goal's states
;;;; shaded; one arrow per op edge labelled with the op, dashed for a must-ask
;;;; op; a large graph's states in clusters, one per value of a variable.  With
;;;; a goal, the plan tree is a second cluster of the same states (node names
;;;; p<N> beside the op graph's s<N>, N the state's dense number) whose arrows
;;;; are the steps of the plans.

(in-package #:player.inspect)

(defparameter *current-state-color* "#d62728"
  "The border colour of the node of the state a running controller is in.")

(defparameter *dot-program* "dot"
  "The Graphviz program that renders .svg and .png files: a name looked up on
PATH, or a path.  Debian's package graphviz installs it.")

(define-condition graphviz-error (player-error-with-message)
  ()
  (:documentation "Rendering a graph failed: *DOT-PROGRAM* is not installed,
or it rejected the graph or could not write the file."))

(defparameter *goal-fill-color* "#bcd9f2" "The fill of a goal's states.")
(defparameter *plan-edge-color* "#1f5fa8" "The colour of a plan tree's arrows.")
(defparameter *no-plan-color* "#c0392b" "The colour of a state no plan leaves.")

;;;# DOT text

(defun dot-escape (text)
  "TEXT with what a quoted DOT string cannot hold as it is escaped: a
backslash doubled, a double quote and a line break backslashed."
  (with-output-to-string (out)
    (loop for char across text
          do (case char
               (#\\ (write-string "\\\\" out))
               (#\" (write-string "\\\"" out))
               (#\Newline (write-string "\\n" out))
               (#\Return)
               (t (write-char char out))))))

(defun dot-string (text)
  "TEXT as a quoted DOT string."
  (format nil "\"~A\"" (dot-escape text)))

(defun dot-lines (lines)
  "The texts LINES as one quoted DOT label, one per line (centred)."
  (format nil "\"~{~A~^\\n~}\"" (mapcar #'dot-escape lines)))

(defun write-dot-attributes (stream attributes)
  "Write ATTRIBUTES, a plist of keywords and texts (already quoted where they
need it), as a DOT attribute list ` [name=value, ...]`; nothing when empty."
  (when attributes
    (format stream " [~{~(~A~)=~A~^, ~}]" attributes)))

(defun node-name (prefix state layout)
  "The DOT name of the one-hot STATE in the part named by PREFIX (s or p)."
  (format nil "~A~D" prefix (state-to-dense state layout)))

;;;# Nodes

(defun node-attributes (graph state &key plan-tree)
  "The DOT attributes of STATE's node in GRAPH (in its PLAN-TREE part when true)."
  (let* ((machine (state-graph-machine graph))
         (goal (state-graph-goal graph))
         (in-goal (and goal (goal-holds-p goal state))))
    (append (list :label (dot-lines (state-literals state (machine-spec machine))))
            (when (= state (machine-initial-state machine))
              (list :peripheries "2"))
            (when in-goal
              (list :style "filled" :fillcolor (dot-string *goal-fill-color*)))
            (when (eql state (state-graph-current graph))
              (list :color (dot-string *current-state-color*) :penwidth "3"
                    :tooltip (dot-string "the controller is here")))
            (when (and plan-tree (not in-goal) (null (state-plan goal state)))
              (list :color (dot-string *no-plan-color*) :fontcolor (dot-string *no-plan-color*)
                    :tooltip (dot-string "no plan reaches the goal from here"))))))

(defun write-node (graph state prefix stream &key plan-tree)
  "Write STATE's node statement, named with PREFIX."
  (format stream "  ~A" (node-name prefix state (machine-layout (state-graph-machine graph))))
  (write-dot-attributes stream (node-attributes graph state :plan-tree plan-tree))
  (format stream ";~%"))

(defun write-nodes (graph prefix stream &key plan-tree)
  "Write a node for each of GRAPH's states, named with PREFIX, in one cluster
per value of GRAPH's cluster variable when it has one."
  (let ((var (state-graph-cluster-variable graph))
        (states (state-graph-states graph)))
    (if (null var)
        (loop for state across states do (write-node graph state prefix stream :plan-tree plan-tree))
        (dotimes (index (var-domain-size var))
          (let ((members (remove-if-not (lambda (s) (= index (value-index-in-state s var))) states)))
            (when (plusp (length members))
              (format stream "  subgraph ~A {~%  label=~A;~%  style=rounded; color=gray60;~%"
                      (dot-string (format nil "cluster_~A_~D" prefix index))
                      (dot-string (format nil "~A=~A" (lisp-text (var-name var)) (state-value-text var index))))
              (loop for state across members do (write-node graph state prefix stream :plan-tree plan-tree))
              (format stream "  }~%")))))))

;;;# Edges

(defun write-edge (graph edge prefix stream attributes)
  "Write EDGE's statement between the nodes named with PREFIX, labelled with
its op, with the extra DOT ATTRIBUTES."
  (let ((layout (machine-layout (state-graph-machine graph))))
    (format stream "  ~A -> ~A" (node-name prefix (op-edge-from edge) layout)
            (node-name prefix (op-edge-to edge) layout))
    (write-dot-attributes stream (list* :label (dot-string (lisp-text (op-name (op-edge-op edge))))
                                        attributes))
    (format stream ";~%")))

(defun write-op-edges (graph stream)
  "Write GRAPH's op edges; a must-ask op's dashed."
  (dolist (edge (state-graph-edges graph))
    (write-edge graph edge "s" stream (and (op-must-ask (op-edge-op edge)) (list :style "dashed")))))

(defun write-plan-tree (graph stream)
  "Write GRAPH's plan tree as the cluster of nodes p<N>."
  (format stream "  subgraph \"cluster_plans\" {~%  label=~A;~%  style=rounded; color=~A;~%"
          (dot-string (format nil "plans to ~A" (lisp-text (state-graph-goal-form graph))))
          (dot-string *plan-edge-color*))
  (write-nodes graph "p" stream :plan-tree t)
  (dolist (edge (state-graph-plan-edges graph))
    (write-edge graph edge "p" stream (list :color (dot-string *plan-edge-color*))))
  (format stream "  }~%"))

;;;# The whole graph

(defun write-dot-graph (graph stream)
  "Write the STATE-GRAPH GRAPH to STREAM as one DOT digraph; return GRAPH."
  (let ((note (state-graph-note graph)))
    (format stream "// ~A~%digraph ~A {~%" (substitute #\Space #\Newline note)
            (dot-string (lisp-text (spec-name (machine-spec (state-graph-machine graph))))))
    (format stream "  graph [label=~A, labelloc=t, fontname=Helvetica, fontsize=12];~%" (dot-string note))
    (format stream "  node [shape=box, fontname=Helvetica, fontsize=10];~%")
    (format stream "  edge [fontname=Helvetica, fontsize=9];~%")
    (when (state-graph-op-graph-p graph)
      (write-nodes graph "s" stream)
      (write-op-edges graph stream))
    (when (state-graph-goal graph)
      (write-plan-tree graph stream))
    (format stream "}~%")
    graph))

(defun write-state-graph (machine stream &key goal current)
  "Write MACHINE's plannable state graph (MACHINE a machine, a spec or a
spec's name) to STREAM as Graphviz DOT text, and return the STATE-GRAPH
drawn.  GOAL, a state expression as written in a spec (posture.sit, a class
name, (and ...)), shades its states and adds its plan tree.  Signals an
ARGUMENT-ERROR for a MACHINE or STREAM of the wrong kind, and a
STATE-GRAPH-ERROR for a GOAL that is not a state expression of the spec and
for a spec with too many states (see BUILD-STATE-GRAPH).  CURRENT, a
one-hot state (a controller's CONTROLLER-BITS), is drawn with a red border."
  (let ((machine (ensure-machine machine 'write-state-graph)))
    (check-argument 'write-state-graph 'stream stream
                    (lambda (s) (and (streamp s) (output-stream-p s))) "an output stream")
    (check-argument 'write-state-graph :current current (lambda (x) (or (null x) (typep x '(integer 0))))
                    "NIL or a one-hot state (a non-negative integer)")
    (let ((graph (build-state-graph machine :goal goal)))
      (setf (state-graph-current graph) current)
      (write-dot-graph graph stream))))

;;;# Files, rendered by Graphviz

(defun graph-file-format (path)
  "What a file PATH names by its type: :DOT (.dot, .gv), :SVG, :PNG, or NIL."
  (let ((type (pathname-type path)))
    (cond ((null type) nil)
          ((member type '("dot" "gv") :test #'string-equal) :dot)
          ((string-equal type "svg") :svg)
          ((string-equal type "png") :png))))

(defun find-dot ()
  "The path of *DOT-PROGRAM*; a GRAPHVIZ-ERROR naming the Debian package when
it is not installed."
  (or (find-executable *dot-program*)
      (error 'graphviz-error
             :message (format nil "drawing an .svg or .png needs Graphviz's ~A program, which is not installed: install the Debian package graphviz (or write a .dot file)"
                              *dot-program*))))

(defun render-dot (text path format)
  "Run *DOT-PROGRAM* on the DOT TEXT to write PATH as FORMAT (:SVG or :PNG);
a GRAPHVIZ-ERROR with its message when it fails."
  (find-dot)
  ;; Run by the name found on PATH, not FIND-DOT's truename: Debian's dot is a
  ;; link to a program that picks its layout engine by the name it is run as.
  ;; dot writes a temporary beside PATH that replaces it only when dot succeeds.
  (with-atomic-output-file (image path :element-type '(unsigned-byte 8) :follow-links t)
   (let* ((errors (make-string-output-stream))
          (process (run-child *dot-program* (list (format nil "-T~(~A~)" format))
                              :input (make-string-input-stream text) :output image
                              :error errors :search t)))
    (unless (eql 0 (sb-ext:process-exit-code process))
      (error 'graphviz-error
             :message (format nil "~A could not draw ~A: ~A" *dot-program* (uiop:native-namestring path)
                              (let ((message (string-trim '(#\Space #\Newline) (get-output-stream-string errors))))
                                (if (string= message "")
                                    (format nil "exit status ~A" (sb-ext:process-exit-code process))
                                    (truncate-text (substitute #\Space #\Newline message) 300))))))))
  path)

(defun write-graph-text (text path)
  "Write TEXT to the file PATH, replacing it; a STATE-GRAPH-ERROR when it cannot be written."
  (handler-case (write-file-string path text :follow-links t)
    (io-error (e)
      (state-graph-fail "cannot write the file ~A: ~A" (uiop:native-namestring path) (io-error-reason e))))
  path)

(defun write-state-graph-file (machine path &key goal current)
  "Write MACHINE's state graph (see WRITE-STATE-GRAPH, for MACHINE and GOAL)
(and CURRENT) to the file PATH (a pathname or native file name), as its type says: DOT text
for .dot or .gv, an image drawn by *DOT-PROGRAM* for .svg or .png.  Returns
the pathname.  Signals an ARGUMENT-ERROR for a MACHINE or PATH of the wrong
kind, a STATE-GRAPH-ERROR for another type or a file that cannot be written
(and as WRITE-STATE-GRAPH does), and a GRAPHVIZ-ERROR when Graphviz is
missing or fails."
  (let* ((machine (ensure-machine machine 'write-state-graph-file))
         (path (check-argument 'write-state-graph-file 'path path
                               (lambda (p) (or (pathnamep p) (and (stringp p) (string/= p ""))))
                               "a pathname or a native file name"))
         (path (if (stringp path) (uiop:parse-native-namestring path) path))
         (format (or (graph-file-format path)
                     (state-graph-fail "cannot tell how to write ~A: give a file ending in .dot, .gv, .svg or .png"
                                       (uiop:native-namestring path)))))
    (unless (eq format :dot) (find-dot))
    (let ((text (with-output-to-string (out) (write-state-graph machine out :goal goal :current current))))
      (if (eq format :dot)
          (write-graph-text text path)
          (render-dot text path format)))))
