;;;; naive.lisp -- the approach the paper rejects: forward breadth-first search
;;;; over explicit states, from each start state to each goal.
;;;;
;;;; Two versions sharing one search: over the synthetic family's N-bit states
;;;; (SYNTH-OPs), and over any spec's one-hot plannable state, numbered densely,
;;;; used to plan every event at run time (NAIVE-SEND-EVENT).

(in-package #:player-bench)

;;; Search over a dense state space

(defstruct (search-space (:constructor %make-search-space))
  "Scratch arrays for BFS over STATE-COUNT states: a generation stamp per
state (so no clearing between searches), the queue, and each state's parent
and the op that reached it."
  (state-count 0 :type fixnum)
  (stamp (make-array 0 :element-type '(unsigned-byte 32)) :type (simple-array (unsigned-byte 32) (*)))
  (generation 0 :type (unsigned-byte 32))
  (queue (make-array 0 :element-type 'fixnum) :type (simple-array fixnum (*)))
  (parent (make-array 0 :element-type 'fixnum) :type (simple-array fixnum (*)))
  (via (make-array 0 :element-type 'fixnum) :type (simple-array fixnum (*)))
  ;; Searches run and states expanded, for reporting.
  (searches 0 :type fixnum)
  (expanded 0 :type fixnum)
  ;; Dense number -> one-hot state, for NAIVE-PLAN.
  (states (make-array 0 :element-type 'fixnum) :type (simple-array fixnum (*))))

(defun make-search-space (state-count)
  (%make-search-space
   :state-count state-count
   :stamp (make-array state-count :element-type '(unsigned-byte 32) :initial-element 0)
   :queue (make-array state-count :element-type 'fixnum :initial-element 0)
   :parent (make-array state-count :element-type 'fixnum :initial-element 0)
   :via (make-array state-count :element-type 'fixnum :initial-element 0)
   :states (make-array state-count :element-type 'fixnum :initial-element 0)))

(defmacro do-bfs ((space start state-var goal-test) &body expand)
  "Breadth-first search from START (a fixnum state, also its dense number when
the state space is dense). GOAL-TEST is a form true when STATE-VAR is a goal.
EXPAND is run for each dequeued STATE-VAR and must call (VISIT NEXT OP-INDEX)
for each successor. Returns the plan (op indices, first first), or :NONE."
  (alexandria:with-gensyms (s stamp gen queue parent via head tail next op found)
    `(let* ((,s ,space)
            (,stamp (search-space-stamp ,s))
            (,gen (incf (search-space-generation ,s)))
            (,queue (search-space-queue ,s))
            (,parent (search-space-parent ,s))
            (,via (search-space-via ,s))
            (,head 0) (,tail 0) (,found -1))
       (declare (type fixnum ,head ,tail ,found)
                (type (unsigned-byte 32) ,gen))
       (setf (aref ,stamp ,start) ,gen (aref ,parent ,start) -1
             (aref ,queue ,tail) ,start)
       (incf ,tail)
       (block search
         (loop while (< ,head ,tail)
               do (let ((,state-var (aref ,queue ,head)))
                    (declare (type fixnum ,state-var))
                    (incf ,head)
                    (when ,goal-test (setf ,found ,state-var) (return-from search))
                    (flet ((visit (,next ,op)
                             (declare (type fixnum ,next ,op))
                             (unless (= (aref ,stamp ,next) ,gen)
                               (setf (aref ,stamp ,next) ,gen
                                     (aref ,parent ,next) ,state-var
                                     (aref ,via ,next) ,op
                                     (aref ,queue ,tail) ,next)
                               (incf ,tail))))
                      (declare (inline visit))
                      ,@expand))))
       (incf (search-space-searches ,s))
       (incf (search-space-expanded ,s) ,head)
       (if (minusp ,found)
           :none
           (loop with plan = '()
                 for at of-type fixnum = ,found then (aref ,parent at)
                 until (= at ,start)
                 do (push (aref ,via at) plan)
                 finally (return plan))))))

;;; The synthetic family: states are N-bit fixnums, numbered by themselves.

(defstruct (naive-synth (:constructor %make-naive-synth))
  "Vectors of the family's ops (precondition and effect masks) and goals."
  (pre-mask #() :type (simple-array fixnum (*)))
  (pre-bits #() :type (simple-array fixnum (*)))
  (eff-mask #() :type (simple-array fixnum (*)))
  (eff-bits #() :type (simple-array fixnum (*)))
  (goals '() :type list)
  space)

(defun make-naive-synth (family)
  (flet ((field (reader)
           (map '(simple-array fixnum (*)) reader (synth-family-ops family))))
    (%make-naive-synth :pre-mask (field #'synth-op-pre-mask) :pre-bits (field #'synth-op-pre-bits)
                       :eff-mask (field #'synth-op-eff-mask) :eff-bits (field #'synth-op-eff-bits)
                       :goals (synth-family-goals family)
                       :space (make-search-space (ash 1 (synth-family-n family))))))

(defun naive-synth-plan (naive start goal)
  "Forward BFS from START to GOAL (a list of (MASK . BITS) cubes): a shortest plan, or :NONE."
  (declare (optimize (speed 3) (safety 0)) (type fixnum start))
  (let ((pre-mask (naive-synth-pre-mask naive)) (pre-bits (naive-synth-pre-bits naive))
        (eff-mask (naive-synth-eff-mask naive)) (eff-bits (naive-synth-eff-bits naive)))
    (do-bfs ((naive-synth-space naive) start state
             (loop for (mask . bits) in goal
                   thereis (= (logand state (the fixnum mask)) (the fixnum bits))))
      (dotimes (i (length pre-mask))
        (when (= (logand state (aref pre-mask i)) (aref pre-bits i))
          (visit (logior (logandc2 state (aref eff-mask i)) (aref eff-bits i)) i))))))

(defun naive-synth-all-goals (naive start)
  "Plan from START to every goal (the per-start-state work of the naive table
builder); returns how many goals were reachable."
  (loop for goal in (naive-synth-goals naive)
        count (listp (naive-synth-plan naive start goal))))

;;; Any spec at run time: the one-hot state, numbered densely for the search.

(defstruct (naive-op (:constructor make-naive-op (def pre-cubes eff-mask eff-bits)))
  "An op as the run-time planner sees it."
  def
  (pre-cubes '() :type list)
  (eff-mask 0 :type fixnum)
  (eff-bits 0 :type fixnum))

(defstruct (naive-runner (:constructor %make-naive-runner))
  "What planning at run time needs: the ops (plannable ones in a vector, for
the search), every op's own entry, the variables' one-hot fields for dense
numbering, and each goal's cubes."
  (ops #() :type simple-vector)
  (op-table (make-hash-table :test 'eq))
  (fields #() :type simple-vector)
  (goal-cubes (make-hash-table :test 'eq))
  (machine nil)
  (conditions (make-hash-table :test 'eq))
  space)

(defun make-naive-runner (machine)
  "A run-time planner for MACHINE's spec, with its own representation of the ops."
  (let* ((spec (player:machine-spec machine))
         (vars (player.spec::plannable-variables spec))
         (count 1)
         (fields (coerce (loop for var in vars
                               collect (prog1 (list (player.spec::var-bit-offset var)
                                                    (player.spec::var-domain-size var) count)
                                         (setf count (* count (player.spec::var-domain-size var)))))
                         'simple-vector))
         (runner (%make-naive-runner :fields fields :machine machine
                                     :space (make-search-space count))))
    (flet ((entry (op)
             (make-naive-op op
                            (if (player.spec::op-precond op)
                                (player.spec::expression-cubes (player.spec::op-precond op) spec)
                                (list (player.spec::top-cube spec)))
                            (loop for (var) in (player.spec::op-effects op)
                                  sum (player.spec::var-field-mask var))
                            (loop for (var . index) in (player.spec::op-effects op)
                                  sum (player.spec::var-value-bit var index)))))
      (dolist (op (player.spec::spec-ops spec))
        (setf (gethash op (naive-runner-op-table runner)) (entry op)))
      ;; The same ops the regression planner may use.
      (setf (naive-runner-ops runner)
            (coerce (loop for op in (player.spec::spec-ops spec)
                          unless (or (player.spec::op-must-ask op) (null (player.spec::op-effects op)))
                            collect (gethash op (naive-runner-op-table runner)))
                    'simple-vector)))
    runner))

(declaim (inline dense-of))
(defun dense-of (bits fields)
  (declare (optimize (speed 3) (safety 0)) (type fixnum bits) (type simple-vector fields))
  (let ((dense 0))
    (declare (type fixnum dense))
    (loop for field across fields
          do (destructuring-bind (offset size stride) field
               (declare (type fixnum offset size stride))
               (incf dense (the fixnum (* stride (1- (integer-length (ldb (byte size offset) bits))))))))
    dense))

(defun naive-plan (runner bits goal-cubes)
  "Forward BFS over one-hot states from BITS to a state in GOAL-CUBES: a list of
NAIVE-OPs, or :NONE."
  (declare (optimize (speed 3) (safety 0)) (type fixnum bits))
  (let* ((ops (naive-runner-ops runner))
         (fields (naive-runner-fields runner))
         (space (naive-runner-space runner))
         ;; dense number -> one-hot state, filled in as states are found
         (states (search-space-states space))
         (plan (progn
                 (setf (aref (the (simple-array fixnum (*)) states) (dense-of bits fields)) bits)
                 (do-bfs (space (dense-of bits fields) dense
                                (let ((state (aref (the (simple-array fixnum (*)) states) dense)))
                                  (loop for cube in goal-cubes
                                        thereis (zerop (logandc2 state (the fixnum cube))))))
                   (let ((state (aref (the (simple-array fixnum (*)) states) dense)))
                     (declare (type fixnum state))
                     (dotimes (i (length ops))
                       (let ((op (svref ops i)))
                         (when (loop for cube in (naive-op-pre-cubes op)
                                     thereis (zerop (logandc2 state (the fixnum cube))))
                           (let* ((next (logior (logandc2 state (naive-op-eff-mask op))
                                                (naive-op-eff-bits op)))
                                  (d (dense-of next fields)))
                             (setf (aref (the (simple-array fixnum (*)) states) d) next)
                             (visit d i))))))))))
    (if (eq plan :none) :none (map 'list (lambda (i) (svref ops i)) plan))))

;;; Running an event with a plan made on the spot for every goal

(defun naive-goal-cubes (runner ast)
  (let ((table (naive-runner-goal-cubes runner)))
    (or (gethash ast table)
        (setf (gethash ast table)
              (player.spec::expression-cubes ast (player:machine-spec (naive-runner-machine runner)))))))

(defun naive-condition (runner ast)
  "The :IF predicate for AST (evaluating a condition is not planning, so the
compiled predicate is reused)."
  (let ((table (naive-runner-conditions runner)))
    (or (gethash ast table)
        (setf (gethash ast table) (player.control::compile-condition ast (naive-runner-machine runner))))))

(defun naive-achieve (runner controller cubes active)
  "Plan from the current state to CUBES and run the plan; NIL if there is none."
  (let ((plan (naive-plan runner (player.control::controller-bits controller) cubes)))
    (and (listp plan)
         (every (lambda (op) (naive-run-op runner controller (naive-op-def op) active)) plan))))

(defun naive-run-op (runner controller def active)
  "Play op DEF (a macro: run its :seq, planning as it goes), then apply its effects."
  (let ((entry (gethash def (naive-runner-op-table runner)))
        (before (player.control::controller-bits controller)))
    (when (eq (player::op-kind def) :macro)
      (when (member def active) (return-from naive-run-op nil))
      (unless (naive-run-directives runner controller (player.spec::op-seq def) (cons def active))
        (return-from naive-run-op nil))
      (player:present-op (player:controller-presenter controller) def 0d0))
    (unless (eq (player::op-kind def) :macro)
      (player:present-op (player:controller-presenter controller) def 0d0))
    (setf (player.control::controller-bits controller)
          (logior (logandc2 before (naive-op-eff-mask entry)) (naive-op-eff-bits entry)))
    t))

(defun naive-run-directives (runner controller directives active)
  "Run parsed DIRECTIVES, planning each goal at run time; NIL at the first failure."
  (dolist (directive directives t)
    (unless
        (ecase (first directive)
          (:achieve (naive-achieve runner controller (naive-goal-cubes runner (second directive)) active))
          (:op (let ((def (second directive)))
                 (and (or (null (player.spec::op-precond def))
                          (naive-achieve runner controller
                                         (naive-goal-cubes runner (player.spec::op-precond def)) active))
                      (naive-run-op runner controller def active))))
          (:assign (let ((var (second directive)))
                     (setf (player.control::controller-bits controller)
                           (logior (logandc2 (player.control::controller-bits controller)
                                             (player.spec::var-field-mask var))
                                   (player.spec::var-value-bit var (third directive))))
                     t))
          (:increment (let ((slot (player.spec::var-slot (second directive))))
                        (incf (svref (player.control::controller-values controller) slot) (third directive))
                        t))
          (:if (if (funcall (naive-condition runner (second directive)) controller)
                   (naive-run-directives runner controller (third directive) active)
                   t))
          ((:label :time :code :c++) t))
      (return nil))))

(defun naive-send-event (runner controller event)
  "Process EVENT-DEF on CONTROLLER's state, planning every goal at run time."
  (let ((player:*controller* controller))
    (naive-run-directives runner controller (player.spec::event-directives event) '())))
