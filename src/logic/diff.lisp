;;;; diff.lisp -- two behaviours compared: did a modification make the
;;;; behaviour inconsistent or incomplete?
;;;;
;;;; Clark & Palmer (§5) ask for a check of "whether or not a modification
;;;; leads to an incomplete or inconsistent behaviour". Comparing the reachable
;;;; graphs of the behaviour before (A) and after (B), states matched by name:
;;;; B is inconsistent where one of its states has no successor though the
;;;; state had one in A (or is new in B): an animation reaching it stops; B is
;;;; incomplete where a move of A between states both still have is gone.
;;;; Moves and states B adds are reported too, but break nothing.

(in-package #:player.logic)

(defstruct (graph-diff (:constructor make-graph-diff (dead-ends removed added removed-states added-states)))
  "What changed from behaviour A to B: DEAD-ENDS, names of B's states with no
successor that had one in A (or are new); REMOVED and ADDED, moves (FROM .
TO) by name; REMOVED-STATES and ADDED-STATES, reachable states by name."
  dead-ends removed added removed-states added-states)

(defun graph-diff-consistent-p (diff)
  "True when DIFF shows no new dead end and no move removed."
  (and (null (graph-diff-dead-ends diff)) (null (graph-diff-removed diff))))

(defun behaviour-moves (behaviour)
  "BEHAVIOUR's moves as a table (FROM-NAME . TO-NAME) -> T, and its state
names -> whether the state has a successor."
  (let ((moves (make-hash-table :test 'equal)) (states (make-hash-table :test 'equal)))
    (loop for i from 0
          for targets across (behaviour-successors behaviour)
          for name = (behaviour-state-name behaviour i)
          do (setf (gethash name states) (and targets t))
             (dolist (j targets)
               (setf (gethash (cons name (behaviour-state-name behaviour j)) moves) t)))
    (values moves states)))

(defun diff-graphs (a b &key starts)
  "Compare behaviour A (before) with B (after), each anything VERIFY takes
(STARTS, a list of nodes, for graphs: all their nodes by default): a
GRAPH-DIFF. States are matched by name."
  (multiple-value-bind (moves-a states-a) (behaviour-moves (behaviour-of a nil nil starts))
    (multiple-value-bind (moves-b states-b) (behaviour-moves (behaviour-of b nil nil starts))
      (flet ((sorted (list) (sort list (lambda (x y) (string< (princ-to-string x) (princ-to-string y))))))
        (make-graph-diff
         (sorted (loop for name being the hash-keys of states-b using (hash-value live)
                       when (and (not live) (multiple-value-bind (live-a found) (gethash name states-a)
                                               (or live-a (not found))))
                         collect name))
         (sorted (loop for move being the hash-keys of moves-a
                       when (and (not (gethash move moves-b))
                                 (nth-value 1 (gethash (car move) states-b))
                                 (nth-value 1 (gethash (cdr move) states-b)))
                         collect move))
         (sorted (loop for move being the hash-keys of moves-b
                       unless (gethash move moves-a) collect move))
         (sorted (loop for name being the hash-keys of states-a
                       unless (nth-value 1 (gethash name states-b)) collect name))
         (sorted (loop for name being the hash-keys of states-b
                       unless (nth-value 1 (gethash name states-a)) collect name)))))))
