;;;; counterexamples.lisp -- why a formula fails: a path of states showing it,
;;;; finite, or a lasso (a prefix, then a loop back to one of its states).
;;;;
;;;; A failing A-formula has a path that refutes it: AG F a path to a state
;;;; where F fails, AF F a path along which F never holds (a lasso, or a path
;;;; to a dead end), AX F one step to a state where F fails, A[F U G] a path
;;;; that leaves F before G or never reaches G. Nested failures extend the
;;;; path from where they happen. A failing E-formula has no such path (every
;;;; path fails it): its counterexample is the state alone.

(in-package #:player.logic)

(defstruct (counterexample (:constructor make-counterexample (states &optional loop)))
  "A path of a behaviour: STATES, a list of state indexes; LOOP, when the path
goes on forever, the position in STATES its last state steps back to."
  (states '() :type list)
  (loop nil))

(defun counterexample-names (behaviour counterexample)
  "The names of COUNTEREXAMPLE's states, in order."
  (mapcar (lambda (i) (behaviour-state-name behaviour i)) (counterexample-states counterexample)))

(defun path-extend (path more)
  "PATH followed by MORE, which starts at PATH's last state (unless PATH loops)."
  (if (or (counterexample-loop path) (null more))
      path
      (let ((offset (1- (length (counterexample-states path)))))
        (make-counterexample (append (butlast (counterexample-states path)) (counterexample-states more))
                             (and (counterexample-loop more) (+ offset (counterexample-loop more)))))))

(defun shortest-path (behaviour start through goal)
  "The shortest path (a list of indexes) from START through THROUGH states to
a GOAL state, or NIL."
  (let ((parent (make-hash-table)) (queue (list start)))
    (setf (gethash start parent) start)
    (loop while queue
          do (let ((i (pop queue)))
               (when (= 1 (sbit goal i))
                 (return-from shortest-path
                   (let ((path (list i)))
                     (loop until (= (first path) start) do (push (gethash (first path) parent) path))
                     path)))
               (when (= 1 (sbit through i))
                 (dolist (j (svref (behaviour-successors behaviour) i))
                   (unless (gethash j parent)
                     (setf (gethash j parent) i)
                     (setf queue (nconc queue (list j))))))))))

(defun stay-path (behaviour start set)
  "A maximal path from START inside SET (every state of which is a dead end or
has a successor in SET): a lasso, or a path to a dead end."
  (let ((positions (make-hash-table)) (path '()) (i start))
    (loop
      (setf (gethash i positions) (length path))
      (push i path)
      (let* ((next (remove-if-not (lambda (j) (= 1 (sbit set j))) (svref (behaviour-successors behaviour) i)))
             (fresh (find-if-not (lambda (j) (gethash j positions)) next)))
        (cond ((null next) (return (make-counterexample (nreverse path))))
              (fresh (setf i fresh))
              (t (return (make-counterexample (nreverse path) (gethash (first next) positions)))))))))

(defun witness (behaviour i formula)
  "A path from state I showing that FORMULA holds there (it does)."
  (let ((op (operator formula)))
    (flet ((sat (f) (formula-holds-states behaviour f))
           (state () (make-counterexample (list i))))
      (cond ((null op) (state))
            ((string= op "NOT") (refutation behaviour i (second formula)))
            ((string= op "OR") (let ((f (find-if (lambda (f) (= 1 (sbit (sat f) i))) (rest formula))))
                                 (if f (witness behaviour i f) (state))))
            ((string= op "IMPLIES") (if (= 1 (sbit (sat (second formula)) i))
                                        (witness behaviour i (third formula))
                                        (state)))
            ((string= op "EX") (let ((j (find-if (lambda (j) (= 1 (sbit (sat (second formula)) j)))
                                                 (svref (behaviour-successors behaviour) i))))
                                 (path-extend (make-counterexample (list i j)) (witness behaviour j (second formula)))))
            ((member op '("EF" "EU") :test #'string=)
             (let* ((goal-formula (if (string= op "EF") (second formula) (third formula)))
                    (path (shortest-path behaviour i (if (string= op "EF") (all-states behaviour 1) (sat (second formula)))
                                         (sat goal-formula))))
               (path-extend (make-counterexample path) (witness behaviour (car (last path)) goal-formula))))
            ((string= op "EG") (stay-path behaviour i (sat formula)))
            (t (state))))))

(defun refutation (behaviour i formula)
  "A path from state I showing that FORMULA fails there (it does)."
  (let ((op (operator formula)))
    (flet ((sat (f) (formula-holds-states behaviour f))
           (state () (make-counterexample (list i))))
      (cond ((null op) (state))
            ((string= op "NOT") (witness behaviour i (second formula)))
            ((string= op "AND") (let ((f (find-if (lambda (f) (= 0 (sbit (sat f) i))) (rest formula))))
                                  (if f (refutation behaviour i f) (state))))
            ((string= op "IMPLIES") (refutation behaviour i (third formula)))
            ((string= op "AX") (let ((j (find-if (lambda (j) (= 0 (sbit (sat (second formula)) j)))
                                                 (svref (behaviour-successors behaviour) i))))
                                 (path-extend (make-counterexample (list i j)) (refutation behaviour j (second formula)))))
            ((string= op "AG") (let ((path (shortest-path behaviour i (all-states behaviour 1)
                                                          (bit-not (sat (second formula))))))
                                 (path-extend (make-counterexample path)
                                              (refutation behaviour (car (last path)) (second formula)))))
            ((string= op "AF") (stay-path behaviour i (sat-eg behaviour (bit-not (sat (second formula))))))
            ((string= op "AU")
             (let* ((not-a (bit-not (sat (second formula)))) (not-b (bit-not (sat (third formula))))
                    (eg (sat-eg behaviour not-b)))
               (if (= 1 (sbit eg i))
                   (stay-path behaviour i eg)
                   (make-counterexample (shortest-path behaviour i not-b (bit-and not-a not-b))))))
            (t (state))))))

(defun print-counterexample (behaviour counterexample stream)
  "Print COUNTEREXAMPLE's states, one per line, and where it loops back."
  (loop for name in (counterexample-names behaviour counterexample)
        for k from 0
        do (format stream "  ~D. ~A~%" k name))
  (when-let (loop (counterexample-loop counterexample))
    (format stream "  then back to ~D. (forever)~%" loop)))

(defun write-counterexample-dot (behaviour counterexample stream)
  "COUNTEREXAMPLE as a Graphviz digraph on STREAM: one node per step, the
path's edges, and the edge back when it loops."
  (format stream "digraph counterexample {~%  rankdir=LR;~%  node [shape=box];~%")
  (loop for name in (counterexample-names behaviour counterexample)
        for k from 0
        do (format stream "  s~D [label=~S];~%" k (format nil "~D. ~A" k name)))
  (loop for k from 1 below (length (counterexample-states counterexample))
        do (format stream "  s~D -> s~D;~%" (1- k) k))
  (when-let (loop (counterexample-loop counterexample))
    (format stream "  s~D -> s~D [style=dashed];~%" (1- (length (counterexample-states counterexample))) loop))
  (format stream "}~%"))

(defun behaviour-of (thing start-p start starts)
  "THING as a behaviour: a behaviour itself, a graph's (GRAPH-BEHAVIOUR, with
START or STARTS), or a spec's (SPEC-BEHAVIOUR)."
  (cond ((behaviour-p thing) thing)
        ((or (graph-p thing) (lazy-graph-p thing))
         (if start-p
             (graph-behaviour thing :start start :starts starts)
             (graph-behaviour thing :starts starts)))
        (t (spec-behaviour thing))))

(defun verify (behaviour formula &key (start nil start-p) starts)
  "Model-check the CTL FORMULA (see ctl.lisp) on BEHAVIOUR: a graph of the
algebra (its initial states START, a node, or STARTS, a list of nodes; by
default all; a lazy graph needs one), a spec (its name or a machine: its reachable
states from its initial state; atoms are its state expressions), or a
BEHAVIOUR. Returns T when FORMULA holds in every initial state, else NIL and
a COUNTEREXAMPLE (a path from the first initial state where it fails), and
the behaviour as a third value. A FORMULA-ERROR for a formula that is not
CTL or names a state or variable the behaviour lacks, or a behaviour past
*VERIFY-STATE-LIMIT* states."
  (let* ((behaviour (behaviour-of behaviour start-p start starts))
         (holds (formula-holds-states behaviour formula))
         (failing (find-if (lambda (i) (= 0 (sbit holds i))) (behaviour-initial behaviour))))
    (if failing
        (values nil (refutation behaviour failing formula) behaviour)
        (values t nil behaviour))))
