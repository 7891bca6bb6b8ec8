;;;; graph-expressions.lisp -- graphs written as data: the small language of
;;;; a defspec's (:graph EXPR) option, interpreted over the algebra, never
;;;; evaluated as Lisp (a spec file stays data).
;;;;
;;;; EXPR is one of
;;;;   NAME                            a graph registered from Lisp (REGISTER-GRAPH, DEFINE-GRAPH)
;;;;   (newton-cradle N)               §4's G^n, N from 1 to *MAX-CRADLE-SPHERES*, or
;;;;                                   to *MAX-LAZY-CRADLE-SPHERES* built on demand
;;;;                                   (then only (reachable ...) of it)
;;;;   (cradle-stage N STAGE)          a named stage of it: :g1 ... :g17, :merged, :paper, :g^n
;;;;   (complete (NODE...))            C(Σ)
;;;;   (graph (NODE...) ((SOURCE . TARGET)...))   nodes and edges written out
;;;;   (sum G G...)  or (+ G G...)     G1 + G2
;;;;   (intersection G G...) or (& G G...)   G1 & G2
;;;;   (product G G...) or (× G G...)  G1 × G2 (left-associative)
;;;;   (merge G G [:leaf atom|sphere]) or (⊗ G G ...)  G1 ⊗ G2; :leaf sphere for cradle graphs
;;;;   (restrict G PRED)               G \ p
;;;;   (reachable G NODE...)           the part of G reachable from the NODEs
;;;;   (spec NAME)                     SPEC->GRAPH of a spec defined before (its
;;;;                                   values are symbols of that spec's package)
;;;;   (let* ((NAME EXPR)...) G)       names for graphs, and for predicates
;;;;                                   written (predicate PRED), used in G
;;;;   (guarded (state P [TEST]) CHEAP FULL)   FULL's states, moving as in CHEAP
;;;;                                   where the guard holds (guards.lisp)
;;;; PRED is a pattern (both ends of an edge must match it, PRED-NODES),
;;;; (=> P1 P2) (the paper's implication, PRED-IMPLIES), (then P1 P2) (PRED-EDGE),
;;;; (& PRED PRED...) (PRED-AND), (edge P1 P2 [TEST]) (a statement about the
;;;; moves from P1 to P2, TEST as in edge-tests.lisp), (not PRED), (or PRED...),
;;;; or a name LET* bound to a predicate. Patterns are the paper's, as in
;;;; patterns.lisp: _, identifiers (any other symbol), constants (numbers,
;;;; strings, keywords, 'SYMBOL), pairs (P1 . P2), and (:eval F X...) with F
;;;; one of + - * only. A NODE is literal data, or (cradle-node (P . V)...).
;;;; Anything else -- an unknown builder, a bad pattern, a graph too large --
;;;; is a GRAPH-EXPRESSION-ERROR (a SPEC-ERROR) naming the form.

(in-package #:player.compose)

(defparameter *max-cradle-spheres* 4
  "The largest N a graph expression's (newton-cradle N) builds whole: n = 5
takes ten seconds and n = 6 minutes on a busy machine (bench/cradle.lisp), too
much for a one-line file to ask of `check'; above it only a reachable part.")

(defparameter *graph-expression-edge-limit* 500000
  "The most edges a graph built by a graph expression may have, at any step.")

(defparameter *graph-expression-node-limit* 500000
  "The most nodes (states) a graph built by a graph expression may have, at any step.")

(defparameter *graph-expression-work-limit* 5000000
  "The most nodes and edges the builders of one graph expression may be handed
in all: each use of a graph counts its size, so reusing a large graph many
times (a LET* name in a long sum) is refused before the work is done.")

(defvar *graph-expression-work* nil
  "While a graph expression is interpreted: the nodes and edges handed out so far.")

(defparameter *pattern-functions* '((+ . +) (- . -) (* . *))
  "The functions a pattern's (:eval F X...) may name in a graph expression.")

(defvar *graph-expression-place* nil
  "While a graph expression is interpreted: the (FILE . POSITION) of its option.")

(defun graph-expression-fail (form control &rest arguments)
  "Signal a GRAPH-EXPRESSION-ERROR about FORM, at *GRAPH-EXPRESSION-PLACE*."
  (error 'graph-expression-error :form form :position (or *graph-expression-place* *source-position*)
                                 :message (format nil "(:graph ...): ~?" control arguments)))

;;; Graphs registered from Lisp

(defvar *graphs* (make-hash-table :test 'equal)
  "Graphs a graph expression may name, by name key.")

(defun register-graph (name graph)
  "Make GRAPH known to graph expressions as NAME (a symbol, compared by
name); returns GRAPH. An ARGUMENT-ERROR when NAME is not a non-keyword
symbol or GRAPH not a graph."
  (check-argument 'register-graph 'name name (lambda (x) (and (symbolp x) x (not (keywordp x)))) "a symbol")
  (check-graph 'register-graph graph)
  (setf (gethash (name-key name) *graphs*) graph))

(defmacro define-graph (name form)
  "Register the graph FORM (Lisp, evaluated now) as NAME for graph expressions."
  `(register-graph ',name ,form))

(defun find-graph (name &optional (errorp t))
  "The graph registered as NAME, or NIL (with ERRORP NIL) or a GRAPH-ERROR."
  (or (and (symbolp name) (gethash (name-key name) *graphs*))
      (and errorp (graph-fail name "no graph named ~A is registered (register-graph)" (lisp-text name)))))

;;; The builders

(defvar *graph-builders* '()
  "(NAMES FUNCTION USAGE): each builder a graph expression may call.")

(defmacro define-graph-builder (names usage lambda-list &body body)
  "Define the builder called by any of NAMES (strings) with the arguments of
the expression bound to LAMBDA-LIST; USAGE shows how it is written."
  (let ((function (intern (format nil "GRAPH-BUILDER-~A" (string-upcase (first names))))))
    `(progn
       (defun ,function (form ,@lambda-list)
         ,(format nil "The graph expression ~A." usage)
         (declare (ignorable form))
         ,@body)
       (setf *graph-builders*
             (cons (list ',names ',function ,usage)
                   (remove ',names *graph-builders* :key #'first :test #'equal))))))

(defun builder-usages ()
  "How each builder is written, for messages."
  (mapcar #'third (reverse *graph-builders*)))

(defun graph-expression (form)
  "The graph the graph expression FORM denotes (see the file header). Signals
a GRAPH-EXPRESSION-ERROR naming the offending part of FORM."
  (let ((*graph-expression-work* 0))
    (interpret-graph form)))

(defun check-graph-size (form graph)
  "Refuse GRAPH, built or named by FORM, when it has more nodes or edges than a
graph expression may build, or when handing it out would take the expression's
work past *GRAPH-EXPRESSION-WORK-LIMIT*; GRAPH otherwise."
  (when (graph-p graph)
    (let ((nodes (graph-node-count graph)) (edges (graph-edge-count graph)))
      (when (> edges *graph-expression-edge-limit*)
        (graph-expression-fail form "~A has ~D edges, more than ~D" (bounded-lisp-text form 80)
                               edges *graph-expression-edge-limit*))
      (when (> nodes *graph-expression-node-limit*)
        (graph-expression-fail form "~A has ~D states, more than ~D" (bounded-lisp-text form 80)
                               nodes *graph-expression-node-limit*))
      (when *graph-expression-work*
        (when (> (incf *graph-expression-work* (+ nodes edges)) *graph-expression-work-limit*)
          (graph-expression-fail form "at ~A, the expression has handled ~D nodes and edges, more than ~D (each use of a graph counts its size)"
                                 (bounded-lisp-text form 80) *graph-expression-work* *graph-expression-work-limit*)))))
  graph)

(defun interpret-graph (form &optional allow-lazy)
  "The graph of the graph expression FORM; a LAZY-GRAPH (a large cradle) only
with ALLOW-LAZY (REACHABLE's argument), else a GRAPH-EXPRESSION-ERROR."
  (let ((graph
          (cond ((and (symbolp form) (bound-name form :graph)))
                ((and (symbolp form) form (not (keywordp form)))
                 (or (find-graph form nil)
                     (graph-expression-fail form "~A is no registered graph (registered: ~:[none~;~:*~{~A~^, ~}~])"
                                            (lisp-text form)
                                            (sort (hash-table-keys *graphs*) #'string<))))
                ((and (consp form) (proper-list-p form) (symbolp (first form)))
                 (let ((entry (find-if (lambda (entry) (apply #'word-p (first form) (first entry)))
                                       *graph-builders*)))
                   (unless entry
                     (graph-expression-fail form "unknown graph builder ~A (known: ~{~A~^, ~})"
                                            (lisp-text (first form)) (builder-usages)))
                   (handler-case (apply (second entry) form (rest form))
                     (program-error ()
                       (graph-expression-fail form "~A is not written ~A" (bounded-lisp-text form 80) (third entry)))
                     ((or graph-error argument-error) (condition)
                       (graph-expression-fail form "~A" condition)))))
                (t (graph-expression-fail form "~A is not a graph expression (a registered graph's name or (BUILDER ARGUMENT...))"
                                          (bounded-lisp-text form 80))))))
    (when (and (lazy-graph-p graph) (not allow-lazy))
      (graph-expression-fail form "~A is built on demand: write (reachable ~A NODE...) to take the part reachable from NODE"
                             (bounded-lisp-text form 80) (bounded-lisp-text form 60)))
    (check-graph-size form graph)))

(defun node-literal (form)
  "The node FORM writes: (cradle-node (P . V)...) builds one, anything else is itself."
  (if (and (consp form) (word-p (first form) "CRADLE-NODE"))
      (let ((spheres (rest form)))
        (unless (and (proper-list-p spheres) spheres (every #'sphere-state-p spheres))
          (graph-expression-fail form "(cradle-node (POSITION . VELOCITY)...) takes sphere states, not ~A"
                                 (bounded-lisp-text spheres 80)))
        (apply #'cradle-node spheres))
      form))

(defun node-list (form list what)
  "LIST, a proper list of node forms of FORM, as nodes."
  (unless (proper-list-p list)
    (graph-expression-fail form "~A must be a list, not ~A" what (bounded-lisp-text list 80)))
  (mapcar #'node-literal list))

(defparameter *max-lazy-cradle-spheres* 10
  "The largest N a graph expression's (newton-cradle N) takes; above
*MAX-CRADLE-SPHERES* it is built on demand, so only (reachable ...) of it may
be taken.")

(define-graph-builder ("newton-cradle") "(newton-cradle N)" (n)
  (unless (typep n `(integer 1 ,*max-lazy-cradle-spheres*))
    (graph-expression-fail form "(newton-cradle N) takes N from 1 to ~D, not ~A" *max-lazy-cradle-spheres* (lisp-text n)))
  (if (<= n *max-cradle-spheres*)
      (newton-cradle n :lazy nil)
      (newton-cradle n :lazy t)))

(define-graph-builder ("cradle-stage") "(cradle-stage N STAGE)" (n stage)
  (unless (typep n `(integer 1 ,*max-cradle-spheres*))
    (graph-expression-fail form "(cradle-stage N STAGE) takes N from 1 to ~D, not ~A" *max-cradle-spheres* (lisp-text n)))
  (let ((key (and (symbolp stage) (find (symbol-name stage) (cradle-stage-names n)
                                        :key #'symbol-name :test #'string-equal))))
    (or (and key (cradle-stage n key))
        (graph-expression-fail form "the ~D-sphere cradle has no stage ~A (stages: ~{~(~A~)~^ ~})"
                               n (lisp-text stage) (cradle-stage-names n)))))

(define-graph-builder ("complete") "(complete (NODE...))" (nodes)
  (let ((nodes (node-list form nodes "(complete (NODE...))'s argument")))
    (when (> (expt (length nodes) 2) *graph-expression-edge-limit*)
      (graph-expression-fail form "(complete ...) of ~D nodes would have more than ~D edges"
                             (length nodes) *graph-expression-edge-limit*))
    (complete-graph nodes)))

(define-graph-builder ("graph") "(graph (NODE...) ((SOURCE . TARGET)...))" (nodes edges)
  (unless (and (proper-list-p edges) (every #'consp edges))
    (graph-expression-fail form "(graph NODES EDGES): EDGES must be a list of (SOURCE . TARGET), not ~A"
                           (bounded-lisp-text edges 80)))
  (make-graph (node-list form nodes "(graph NODES EDGES)'s NODES")
              (mapcar (lambda (edge) (cons (node-literal (car edge)) (node-literal (cdr edge)))) edges)))

(define-graph-builder ("sum" "+") "(sum G G...)" (graph &rest graphs)
  (apply #'graph-sum (interpret-graph graph) (mapcar #'interpret-graph graphs)))

(define-graph-builder ("intersection" "&") "(intersection G G...)" (graph &rest graphs)
  (apply #'graph-intersection (interpret-graph graph) (mapcar #'interpret-graph graphs)))

(define-graph-builder ("product" "×" "*") "(product G G...)" (graph1 graph2 &rest graphs)
  (let ((graphs (mapcar #'interpret-graph (list* graph1 graph2 graphs))))
    (let ((edges (reduce #'* graphs :key #'graph-edge-count))
          (nodes (reduce #'* graphs :key #'graph-node-count)))
      (when (> edges *graph-expression-edge-limit*)
        (graph-expression-fail form "the product would have ~D edges, more than ~D" edges *graph-expression-edge-limit*))
      (when (> nodes *graph-expression-node-limit*)
        (graph-expression-fail form "the product would have ~D states, more than ~D" nodes *graph-expression-node-limit*)))
    (apply #'graph-product graphs)))

(defun merged-edge-count (graph1 graph2 leafp)
  "How many edges (before duplicates merge) GRAPH-MERGE would join from GRAPH1
and GRAPH2: counted first, so a merge too large is refused before it is built."
  (let ((counts (make-node-table)))
    (loop for e2 being the hash-keys of (graph-edge-table graph2)
          do (incf (gethash (cons (tree-left (car e2) :leafp leafp) (tree-left (cdr e2) :leafp leafp)) counts 0)))
    (loop for e1 being the hash-keys of (graph-edge-table graph1)
          sum (gethash (cons (tree-right (car e1) :leafp leafp) (tree-right (cdr e1) :leafp leafp)) counts 0))))

(define-graph-builder ("merge" "⊗") "(merge G G... [:leaf atom|sphere])" (&rest arguments)
  (let* ((tail (member :leaf arguments))
         (graphs (ldiff arguments tail))
         (leaf (second tail)))
    (unless (and (>= (length graphs) 2) (or (null tail) (and (= (length tail) 2) (word-p leaf "ATOM" "SPHERE"))))
      (graph-expression-fail form "write (merge G G... [:leaf atom|sphere]), not ~A" (bounded-lisp-text form 80)))
    (let ((leafp (if (word-p leaf "SPHERE") #'sphere-state-p #'atom)))
      (reduce (lambda (a b)
                (check-merge-nodes a "first" leafp)
                (check-merge-nodes b "second" leafp)
                (let ((edges (merged-edge-count a b leafp)))
                  (when (> edges *graph-expression-edge-limit*)
                    (graph-expression-fail form "the merge would have ~D edges, more than ~D" edges *graph-expression-edge-limit*)))
                (graph-merge a b :leafp leafp))
              (mapcar #'interpret-graph graphs)))))

(define-graph-builder ("restrict") "(restrict G PRED)" (graph predicate)
  (restrict (interpret-graph graph) (interpret-predicate predicate)))

(define-graph-builder ("reachable") "(reachable G NODE...)" (graph &rest nodes)
  ;; A lazy G (a large cradle) is expanded from the NODEs only, within the edge limit.
  (let ((*lazy-node-limit* (min *lazy-node-limit* *graph-expression-edge-limit*)))
    (apply #'graph-reachable (interpret-graph graph t) (node-list form nodes "(reachable G NODE...)'s NODEs"))))

(define-graph-builder ("spec") "(spec NAME)" (name)
  (unless (and (symbolp name) name (find-spec name nil))
    (graph-expression-fail form "(spec NAME): no spec named ~A is defined before this one" (lisp-text name)))
  ;; A spec file may name any spec: keep the graph small enough to load quickly.
  (let ((*spec-graph-state-limit* (min *spec-graph-state-limit* 20000)))
    (values (spec->graph name))))

;;; Names: (let* ((NAME EXPR)...) G)

(defvar *graph-bindings* '()
  "While a graph expression's LET* body is interpreted: (NAME KIND . VALUE)
for each name it binds, KIND :GRAPH or :PREDICATE, innermost first.")

(defun bound-name (symbol kind)
  "The value SYMBOL is bound to as KIND (:GRAPH or :PREDICATE) by an enclosing LET*, or NIL."
  (let ((entry (find-if (lambda (entry) (and (symbolp symbol) (string= (symbol-name (first entry)) (symbol-name symbol))))
                        *graph-bindings*)))
    (and entry (eq (second entry) kind) (cddr entry))))

(define-graph-builder ("let*" "let") "(let* ((NAME G-or-(predicate PRED))...) G)" (bindings body)
  ;; Names bound in order, each seeing those before it, as the paper names
  ;; S1, p1, S2 ... and then writes expressions of them.
  (unless (and (proper-list-p bindings)
               (every (lambda (b) (and (proper-list-p b) (= 2 (length b)) (symbolp (first b)) (first b)
                                       (not (keywordp (first b)))))
                      bindings))
    (graph-expression-fail form "write (let* ((NAME EXPR)...) BODY), not ~A" (bounded-lisp-text bindings 80)))
  (let ((*graph-bindings* *graph-bindings*))
    (loop for (name expression) in bindings
          do (push (if (and (consp expression) (symbolp (first expression)) (word-p (first expression) "PREDICATE"))
                       (progn
                         (unless (= 2 (length expression))
                           (graph-expression-fail expression "write (predicate PRED)"))
                         (list* name :predicate (interpret-predicate (second expression))))
                       (list* name :graph (interpret-graph expression)))
                   *graph-bindings*))
    (interpret-graph body)))

;;; Guards: (guarded GUARD CHEAP FULL)

(defun interpret-guard (form)
  "The node test of a guard (state P [TEST]): the nodes matching the pattern
P for which TEST (edge-tests.lisp) holds over P's identifiers."
  (unless (and (consp form) (proper-list-p form) (symbolp (first form)) (word-p (first form) "STATE")
               (<= 2 (length form) 3))
    (graph-expression-fail form "a guard is written (state PATTERN [TEST]), not ~A" (bounded-lisp-text form 80)))
  (let* ((pattern (interpret-pattern (second form)))
         (test (if (third form) (compile-edge-test (third form) (pattern-identifiers (second form))) (constantly t))))
    (lambda (node)
      (multiple-value-bind (ok bindings) (match-pattern pattern node)
        (and ok (funcall test bindings))))))

(define-graph-builder ("guarded") "(guarded (state P [TEST]) CHEAP FULL)" (guard cheap full)
  ;; FULL's states, moving as in CHEAP where the guard holds (guards.lisp).
  (guard-eager (interpret-guard guard) (interpret-graph cheap) (interpret-graph full)))

;;; Predicates and patterns

(defun interpret-edge-predicate (form)
  "The predicate of (edge P1 P2 [TEST]): moves from a P1 node to a P2 node
for which TEST (edge-tests.lisp) holds over the identifiers they bind."
  (unless (<= 3 (length form) 4)
    (graph-expression-fail form "write (edge P1 P2 [TEST]), not ~A" (bounded-lisp-text form 80)))
  (destructuring-bind (p1 p2 &optional (test nil test-p)) (rest form)
    (let ((identifiers (union (pattern-identifiers p1) (pattern-identifiers p2))))
      (pred-where (interpret-pattern p1) (interpret-pattern p2) (if test-p (compile-edge-test test identifiers) (constantly t))
                  :description (bounded-lisp-text form 80)))))

(defun interpret-predicate (form)
  "The restriction predicate the predicate form FORM denotes."
  (cond ((and (symbolp form) (bound-name form :predicate)))
        ((and (consp form) (proper-list-p form) (word-p (first form) "EDGE"))
         (interpret-edge-predicate form))
        ((and (consp form) (proper-list-p form) (word-p (first form) "NOT"))
         (unless (= 2 (length form)) (graph-expression-fail form "write (not PRED)"))
         (pred-not (interpret-predicate (second form))))
        ((and (consp form) (proper-list-p form) (word-p (first form) "OR"))
         (unless (rest form) (graph-expression-fail form "(or PRED PRED...) needs a predicate"))
         (apply #'pred-or (mapcar #'interpret-predicate (rest form))))
        ((and (consp form) (proper-list-p form) (word-p (first form) "=>" "THEN"))
         (unless (= (length form) 3)
           (graph-expression-fail form "write (~(~A~) P1 P2), not ~A" (first form) (bounded-lisp-text form 80)))
         (funcall (if (word-p (first form) "=>") #'pred-implies #'pred-edge)
                  (interpret-pattern (second form)) (interpret-pattern (third form))))
        ((and (consp form) (proper-list-p form) (word-p (first form) "&"))
         (unless (rest form)
           (graph-expression-fail form "(& PRED PRED...) needs a predicate"))
         (apply #'pred-and (mapcar #'interpret-predicate (rest form))))
        (t (pred-nodes (interpret-pattern form)))))

(defun interpret-pattern (form)
  "The compiled pattern of the pattern form FORM: its (:eval F X...) parts get
the function F names in *PATTERN-FUNCTIONS*; anything else there is an error."
  (labels ((walk (x)
             (cond ((eval-pattern-p x)
                    (let ((entry (and (proper-list-p x) (symbolp (second x))
                                      (assoc (symbol-name (second x)) *pattern-functions*
                                             :key #'symbol-name :test #'string=))))
                      (unless entry
                        (graph-expression-fail form "pattern ~A: (:eval F X...) takes F among ~{~A~^ ~}, not ~A"
                                               (bounded-lisp-text form 80) (mapcar #'car *pattern-functions*)
                                               (bounded-lisp-text (and (consp (cdr x)) (second x)) 40)))
                      (list* :eval (symbol-function (cdr entry)) (cddr x))))
                   ((quoted-constant-p x) x)
                   ((consp x) (cons (walk (car x)) (walk (cdr x))))
                   ((or (functionp x) (not (typep x '(or symbol number string character))))
                    (graph-expression-fail form "pattern ~A: ~A is no identifier, constant or pair"
                                           (bounded-lisp-text form 80) (bounded-lisp-text x 40)))
                   (t x))))
    (handler-case (pattern (walk form))
      (graph-error (condition)
        (graph-expression-fail form "~A" condition)))))
