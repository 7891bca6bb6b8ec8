;;;; graph-option.lisp -- a defspec's (:graph EXPR ...) option: the spec gets
;;;; the state variable, ops and GO-X events GRAPH->SPEC makes of the graph the
;;;; graph expression EXPR denotes (graph-expressions.lisp), then the forms
;;;; written after the option. Nothing in EXPR is evaluated as Lisp.
;;;;
;;;;   (:graph EXPR [:start NODE] [:variable NAME] [:go-events BOOLEAN])
;;;;
;;;; NODE is the initial node (default: the first in NODE< order), written as
;;;; a graph expression's nodes are; NAME the state variable (default NODE);
;;;; :go-events false leaves out the GO-X events (one planned goal per node).
;;;; A graph whose nodes are all cradle trees names them as specs/newtons-cradle
;;;; does (LS-CS-CS: sphere codes, leftmost first), any other by
;;;; DEFAULT-NODE-NAME. The spec's :max-depth, unless it gives one, is the
;;;; number of nodes less one.

(in-package #:player.compose)

(defparameter *graph-option-keys* '(:start :variable :go-events)
  "The options a (:graph EXPR ...) option takes after EXPR.")

(defun cradle-graph-p (graph)
  "Are all of GRAPH's nodes trees of sphere states (a cradle's nodes)?"
  (loop for node being the hash-keys of (graph-node-table graph)
        always (and (consp node) (tree-p node :leafp #'sphere-state-p))))

(defun graph-option-arguments (option)
  "The plist after EXPR in the (:graph EXPR ...) OPTION, checked."
  (let ((options (cddr option)))
    (unless (and (proper-list-p options) (evenp (length options))
                 (loop for (key) on options by #'cddr always (member key *graph-option-keys*)))
      (graph-expression-fail option "after EXPR, (:graph EXPR ...) takes ~{~(~S~) VALUE~^, ~}, not ~A"
                             *graph-option-keys* (bounded-lisp-text options 80)))
    options))

(defun graph-option-variable (option value)
  "The state variable's name the :variable VALUE of OPTION gives."
  (unless (and (symbolp value) value (not (keywordp value)) (not (boolean-word value))
               (not (find #\. (symbol-name value))))
    (graph-expression-fail option ":variable takes a variable's name, not ~A" (bounded-lisp-text value 40)))
  value)

(defmethod expand-spec-option ((key (eql :graph)) option)
  (let* ((*graph-expression-place* (or (and *form-places* (gethash option *form-places*)) *source-position*))
         (arguments (graph-option-arguments option))
         (graph (graph-expression (second option)))
         (start (and (getf arguments :start) (node-literal (getf arguments :start)))))
    (when (graph-empty-p graph)
      (graph-expression-fail option "~A has no nodes, so the spec would have no states"
                             (bounded-lisp-text (second option) 80)))
    (when (and start (not (graph-has-node-p graph start)))
      (graph-expression-fail option ":start ~A is not a node of the graph" (bounded-lisp-text start 80)))
    (multiple-value-bind (go-events ok) (boolean-word (getf arguments :go-events t))
      (unless ok
        (graph-expression-fail option ":go-events takes true or false, not ~A"
                               (bounded-lisp-text (getf arguments :go-events) 40)))
      (let ((forms (handler-case
                       (graph->spec-forms graph :start start :go-events go-events
                                                :variable (graph-option-variable option (getf arguments :variable 'node))
                                                :node-namer (if (cradle-graph-p graph) #'cradle-node-name #'default-node-name))
                     (graph-error (condition)
                       (graph-expression-fail option "~A" condition)))))
        ;; GRAPH->SPEC-FORMS starts with (:max-depth N): the spec's, unless it gives one.
        (values (remove-if (lambda (form) (and (consp form) (eq (first form) :max-depth))) forms)
                (second (find :max-depth forms :key (lambda (form) (and (consp form) (first form))))))))))
