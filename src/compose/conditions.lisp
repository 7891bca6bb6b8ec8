;;;; conditions.lisp -- the conditions of src/compose/.  Every bad input to
;;;; the transition-system algebra (a node a graph does not have, a pattern that
;;;; can match no node, a merge of graphs whose nodes are not binary trees,
;;;; trees of different shapes) signals GRAPH-ERROR, naming the value; a bad
;;;; (:graph EXPR) option of a defspec signals GRAPH-EXPRESSION-ERROR, a spec
;;;; error at the option's file and line.

(in-package #:player.compose)

(define-condition graph-error (player-error-with-message)
  ((value :initarg :value :initform nil :reader graph-error-value
          :documentation "The offending value (a node, a pattern, a tree...)."))
  (:documentation "A bad input to the transition-system algebra of src/compose/
(Clark & Palmer's graphs). The message names the offending value, which
GRAPH-ERROR-VALUE returns."))

(defun graph-fail (value control &rest arguments)
  "Signal a GRAPH-ERROR about VALUE with the message CONTROL/ARGUMENTS."
  (error 'graph-error :value value :message (apply #'format nil control arguments)))

(defun node-text (node)
  "NODE printed readably for a message, cut to 120 characters."
  (truncate-text (let ((*print-pretty* nil) (*print-circle* nil) (*print-length* 20) (*print-level* 8))
                   (prin1-to-string node))
                 120))

(define-condition graph-expression-error (spec-error)
  ()
  (:documentation "A (:graph EXPR) option of a defspec is not a graph
expression (graph-expressions.lisp), or its graph cannot be built; FORM is the
offending part, the position the option's file and line."))
