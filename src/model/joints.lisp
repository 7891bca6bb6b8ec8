;;;; joints.lisp -- an imported scene's node tree, and the joints taken from it:
;;;; the bones, the animated nodes and their ancestors, each with its rest
;;;; transform and, for a bone, its inverse bind matrix (import.lisp calls these).

(in-package #:player.model)

;;;# The node tree and the joints

(defun scene-nodes (root)
  "The nodes under ROOT in preorder (parents before children), as a vector of
(POINTER NAME PARENT-INDEX); a MODEL-ERROR past *MODEL-NODE-LIMIT*.  Walked
with a stack, not recursion, so a deep tree cannot exhaust Lisp's stack."
  (let ((nodes (make-array 64 :adjustable t :fill-pointer 0))
        (stack (list (cons root nil))))
    (loop while stack
          do (destructuring-bind (pointer . parent) (pop stack)
               (when (>= (fill-pointer nodes) *model-node-limit*)
                 (fail "its scene has more than ~:D nodes" *model-node-limit*))
               (let ((index (vector-push-extend (list pointer (slot-string pointer '%ai-node 'name) parent)
                                                nodes))
                     (count (cffi:foreign-slot-value pointer '(:struct %ai-node) 'num-children))
                     (children (cffi:foreign-slot-value pointer '(:struct %ai-node) 'children)))
                 (foreign-array children count "child nodes")
                 ;; Pushed last to first, so they come off the stack in order.
                 (loop for i from (1- count) downto 0
                       for child = (cffi:mem-aref children :pointer i)
                       do (when (cffi:null-pointer-p child)
                            (fail "a node of its scene has a NULL child"))
                          (push (cons child index) stack)))))
    nodes))

(defun joint-nodes (nodes names)
  "Which of NODES (see SCENE-NODES) are joints: those whose name is in the
hash table NAMES (bones and animated nodes), and their ancestors.  Returns a
vector of each node's joint index or NIL, and the joint count."
  (let ((marked (make-array (length nodes) :initial-element nil)))
    ;; Preorder puts a parent before its children, so one backward pass
    ;; marks every ancestor of a marked node.
    (loop for i from (1- (length nodes)) downto 0
          for (nil name parent) = (aref nodes i)
          when (or (aref marked i) (gethash name names))
            do (setf (aref marked i) t)
               (when parent (setf (aref marked parent) t)))
    (let ((count 0))
      (values (map 'vector (lambda (mark) (when mark (prog1 count (incf count)))) marked)
              count))))

(defun decomposed-transform (node)
  "The rest local transform of NODE as translation, rotation (w x y z) and
scale, three DOUBLE-VECTORs; a MODEL-ERROR when it is not finite."
  (copy-matrix (cffi:foreign-slot-pointer node '(:struct %ai-node) 'transformation)
               "a node's transform")
  (cffi:with-foreign-objects ((scaling :float 3) (rotation :float 4) (position :float 3))
    (with-assimp-traps-masked
      (%ai-decompose-matrix (cffi:foreign-slot-pointer node '(:struct %ai-node) 'transformation)
                            scaling rotation position))
    (flet ((doubles (pointer count)
             (map 'double-vector (lambda (x) (float x 1d0))
                  (copy-floats pointer 1 count count "a node's decomposed transform"))))
      (values (doubles position 3) (doubles rotation 4) (doubles scaling 3)))))

(defun make-joints (nodes joint-of inverse-binds)
  "The joints: each node of NODES that JOINT-OF gives an index, with its
parent's joint index, its rest transform and, from the hash table
INVERSE-BINDS (bone name to matrix), its inverse bind matrix."
  (coerce (loop for (pointer name parent) across nodes
                for joint across joint-of
                when joint
                  collect (multiple-value-bind (translation rotation scale) (decomposed-transform pointer)
                            (make-joint name (and parent (aref joint-of parent))
                                        translation rotation scale (gethash name inverse-binds))))
          'simple-vector))

;;;# World matrices

(defun matrix* (a b)
  "The product A B of two 4x4 matrices, each 16 doubles row-major, as a new DOUBLE-VECTOR."
  (let ((product (make-array 16 :element-type 'double-float :initial-element 0d0)))
    (dotimes (row 4 product)
      (dotimes (column 4)
        (setf (aref product (+ (* 4 row) column))
              (loop for k below 4
                    sum (* (aref a (+ (* 4 row) k)) (aref b (+ (* 4 k) column)))))))))

(defun node-world-matrix (nodes index)
  "The world matrix at rest (16 doubles, row-major) of the node INDEX of NODES
(see SCENE-NODES): its transform times its ancestors', up to the scene's
root; the identity for INDEX NIL (a mesh no node holds)."
  (let ((world (make-array 16 :element-type 'double-float :initial-contents
                           '(1d0 0d0 0d0 0d0 0d0 1d0 0d0 0d0 0d0 0d0 1d0 0d0 0d0 0d0 0d0 1d0))))
    (loop for node = index then (third (aref nodes node))
          while node
          do (setf world (matrix* (copy-matrix (cffi:foreign-slot-pointer (first (aref nodes node))
                                                                          '(:struct %ai-node) 'transformation)
                                               "a node's transform")
                                  world)))
    world))
