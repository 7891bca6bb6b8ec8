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
;;;; does (LS-CS-CS: sphere codes, leftmost first); one whose nodes are spheres
;;;; on a grid, or tuples of them, as specs/bouncing-spheres does (X2Y1NE-X4Y1NW,
;;;; see GRID-SPHERE-NAME); any other by DEFAULT-NODE-NAME. The spec's :max-depth, unless it gives one, is the
;;;; number of nodes less one.

(in-package #:player.compose)

(defparameter *graph-option-keys* '(:start :variable :go-events)
  "The options a (:graph EXPR ...) option takes after EXPR.")

(defun cradle-sphere-p (x)
  "Is X a cradle sphere's state: position and velocity each -1, 0 or 1?"
  (and (sphere-state-p x) (<= -1 (car x) 1) (<= -1 (cdr x) 1)))

(defun cradle-graph-p (graph)
  "Are all of GRAPH's nodes trees of cradle sphere states (a cradle's nodes)?"
  (loop for node being the hash-keys of (graph-node-table graph)
        always (and (consp node) (tree-p node :leafp #'cradle-sphere-p))))

(defun grid-sphere-p (x)
  "Is X a sphere on a grid, ((X . Y) . (DX . DY)): integer position, and a
diagonal unit velocity?"
  (and (consp x) (consp (car x)) (consp (cdr x))
       (integerp (caar x)) (integerp (cdar x))
       (member (cadr x) '(-1 1)) (member (cddr x) '(-1 1))))

(defun grid-sphere-name (node)
  "The name of a node made of grid spheres, leftmost first, joined by dashes:
X2Y1NE is the sphere at x = 2, y = 1 moving up (north) and right (east)."
  (format nil "~{~A~^-~}"
          (mapcar (lambda (sphere)
                    (destructuring-bind ((x . y) . (dx . dy)) sphere
                      (format nil "X~:[~;M~]~DY~:[~;M~]~D~C~C" (minusp x) (abs x) (minusp y) (abs y)
                              (if (plusp dy) #\N #\S) (if (plusp dx) #\E #\W))))
                  (tree-flatten node :leafp #'grid-sphere-p))))

(defun grid-graph-p (graph)
  "Are all of GRAPH's nodes grid spheres or trees of them?"
  (loop for node being the hash-keys of (graph-node-table graph)
        always (tree-p node :leafp #'grid-sphere-p)))

(defun graph-node-namer (graph)
  "How a (:graph ...) spec names GRAPH's nodes (see the file header)."
  ;; Grid spheres first: a grid whose values are all -1, 0, 1 would pass for a
  ;; cradle, but a cradle has spheres at rest, which no grid sphere is.
  (cond ((grid-graph-p graph) #'grid-sphere-name)
        ((cradle-graph-p graph) #'cradle-node-name)
        (t #'default-node-name)))

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
                                                :node-namer (graph-node-namer graph))
                     (graph-error (condition)
                       (graph-expression-fail option "~A" condition)))))
        ;; GRAPH->SPEC-FORMS starts with (:max-depth N): the spec's, unless it gives one.
        (values (remove-if (lambda (form) (and (consp form) (eq (first form) :max-depth))) forms)
                (second (find :max-depth forms :key (lambda (form) (and (consp form) (first form))))))))))
