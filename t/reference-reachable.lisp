;;;; reference-reachable.lisp -- independent references for the reachable
;;;; regime (issue 13): which states are reachable, and the shortest plans
;;;; from them, for random specs (a SPEC-MODEL, random-specs.lisp) and for
;;;; STRIPS problems (strips-families.lisp). Explicit forward breadth-first
;;;; searches over the models' own data; nothing here calls the planner.
;;;;
;;;; The semantics they encode (the issue's, restated): a state is reachable
;;;; when some sequence of transitions leads to it from the initial state or
;;;; a :start-states state; the transitions are every op with effects
;;;; (must-ask ops and macro-ops too, applied where their precondition holds)
;;;; and every event :add/:sub (anywhere in an event, applied unconditionally).

(in-package #:player-tests)

;;; Random specs

(defun model-assignments (model)
  "Every (:assign VAR-INDEX VALUE-INDEX) directive of MODEL's events, inside :if too."
  (let ((found '()))
    (labels ((walk (directives)
               (dolist (directive directives)
                 (case (first directive)
                   (:assign (push directive found))
                   (:if (walk (cddr directive)))))))
      (dolist (event (model-events model))
        (walk (mevent-directives event))))
    found))

(defun model-successors (model state)
  "The state vectors one transition of MODEL leads to from STATE."
  (append (loop for op in (model-ops model)
                when (and (mop-effects op) (model-op-applicable-p op state))
                  collect (model-apply-effects op state))
          (loop for (nil i k) in (model-assignments model)
                collect (let ((next (copy-seq state)))
                          (setf (svref next i) k)
                          next))))

(defun model-initial-state (model)
  "MODEL's declared initial state, as a vector of value indices."
  (map 'simple-vector #'mvar-initial (model-variables model)))

(defun reference-reachable-indices (model &optional start-expressions)
  "The state numbers (MODEL-STATE-INDEX) reachable in MODEL from its initial
state and from every state where one of the model expressions
START-EXPRESSIONS holds, as a hash table whose keys they are."
  (let ((seen (make-hash-table))
        (queue '()))
    (flet ((visit (state)
             (let ((index (model-state-index model state)))
               (unless (gethash index seen)
                 (setf (gethash index seen) t)
                 (push state queue)))))
      (visit (model-initial-state model))
      (when start-expressions
        (dotimes (index (model-state-count model))
          (let ((state (model-index-state model index)))
            (when (some (lambda (e) (model-eval e state)) start-expressions)
              (visit state)))))
      (loop while queue
            do (mapc #'visit (model-successors model (pop queue)))))
    seen))

(defun model-one-hot (model machine state)
  "The one-hot state of MACHINE for model STATE (variables matched by position;
value index K of a variable is bit K of its field)."
  (loop for var in (player.spec::plannable-variables (machine-spec machine))
        for k across state
        for i from 0
        do (assert (string= (symbol-name (player.spec::var-name var))
                            (symbol-name (mvar-name (svref (model-variables model) i)))))
        sum (ash 1 (+ (player.spec::var-bit-offset var) k))))

;;; STRIPS problems: a state is an integer, bit I for the Ith fact.

(defun strips-fact-bits (problem facts)
  "The bits of FACTS among PROBLEM's facts."
  (loop for f in facts
        sum (ash 1 (position f (player-strips:strips-problem-facts problem)))))

(defun strips-apply (problem action state)
  "The state after ACTION in STATE, or NIL when its precondition fails."
  (let ((pre (strips-fact-bits problem (player-strips:strips-action-pre action))))
    (when (= pre (logand pre state))
      (logior (logandc2 state (strips-fact-bits problem (player-strips:strips-action-del action)))
              (strips-fact-bits problem (player-strips:strips-action-add action))))))

(defun strips-reachable (problem)
  "(VALUES STATES EDGES): PROBLEM's states reachable from its initial state,
as a list, and a hash table from each to its (ACTION . NEXT) moves."
  (let ((edges (make-hash-table))
        (queue (make-array 1 :adjustable t :fill-pointer 1
                             :initial-element (strips-fact-bits problem (player-strips:strips-problem-initial problem)))))
    (setf (gethash (aref queue 0) edges) '())
    (loop for next-in-line from 0
          while (< next-in-line (fill-pointer queue))
          do (let ((state (aref queue next-in-line)))
               (dolist (action (player-strips:strips-problem-actions problem))
                 (let ((next (strips-apply problem action state)))
                   (when next
                     (push (cons action next) (gethash state edges))
                     (unless (nth-value 1 (gethash next edges))
                       (setf (gethash next edges) '())
                       (vector-push-extend next queue)))))))
    (values (coerce queue 'list) edges)))

(defun strips-distances (edges goal-bits)
  "For every state of EDGES (STRIPS-REACHABLE's), the fewest actions to a
state holding every fact of GOAL-BITS, or NIL: breadth first backwards."
  (let ((predecessors (make-hash-table))
        (distances (make-hash-table))
        (frontier '()))
    (maphash (lambda (state moves)
               (dolist (move moves)
                 (push state (gethash (cdr move) predecessors)))
               (when (= goal-bits (logand goal-bits state))
                 (setf (gethash state distances) 0)
                 (push state frontier)))
             edges)
    (loop for depth from 1
          while frontier
          do (let ((next '()))
               (dolist (state frontier)
                 (dolist (previous (gethash state predecessors))
                   (unless (gethash previous distances)
                     (setf (gethash previous distances) depth)
                     (push previous next))))
               (setf frontier next)))
    distances))
