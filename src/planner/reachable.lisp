;;;; reachable.lisp -- the reachable regime: plans for the states that can
;;;; happen, not for every combination of values.
;;;;
;;;; A spec of 30 to 100 facts has far too many combinations for a bit per
;;;; state, yet few of them can ever occur (four blocks on a table: 29
;;;; booleans, 125 states). So a forward breadth-first search from the
;;;; initial state and the :start-states, under every op (must-ask ops and
;;;; macro-ops too), every event's :add/:sub and every op's :if-cut (what a
;;;; timed controller leaves when it cuts the op), finds the reachable set R;
;;;; its states are numbered in the order found, and SolvedStates becomes a
;;;; bit per state of R. For each bit of the one-hot state, the states of R
;;;; that have it are a bitmap over R too, so the states of R in a cube are
;;;; the AND, over the variables the cube constrains, of the OR of the
;;;; bitmaps of the values it allows: asking "does this cube hold a state of
;;;; R not yet solved" is a few word operations per 64 states of R.
;;;;
;;;; R is closed under the planner's operators, so the paper's regression
;;;; (regression.lisp) runs unchanged and still finds shortest plans for
;;;; every state of R: a regressed cube whose states in R are all solved can
;;;; give no state of R a shorter plan. (Its plans may also hold in states
;;;; outside R, where nothing says they are shortest: the controller refuses
;;;; such states, see src/runtime/controller/unplanned-states.lisp.)
;;;; Memory is a bit per state of R per one-hot bit, nothing per 2^bits.

(in-package #:player)

(defparameter *reachable-state-limit* (expt 2 22)
  "Most reachable states the reachable regime numbers and plans for.")

(defparameter *start-state-limit* (expt 2 16)
  "Most states one (:start-states EXPR...) expression may stand for.")

(defstruct (reachable-index (:constructor %make-reachable-index))
  "The reachable states of a spec, numbered, with a bitmap per one-hot bit."
  ;; one-hot states by number, in the order the search found them
  (states #() :type simple-vector)
  ;; one-hot state -> its number
  (numbers (make-hash-table) :type hash-table)
  ;; for each one-hot bit: a bitmap over the numbers of the states that have it
  (bit-sets #() :type simple-vector)
  ;; how many states each of BIT-SETS holds
  (bit-counts #() :type simple-vector)
  ;; the bitmap of every state
  (all nil :type (or null simple-bit-vector))
  ;; (OFFSET . FIELD) -> (BITMAP . COUNT), for variables a cube allows several values
  (choices (make-hash-table :test 'equal) :type hash-table)
  ;; what decides the states: the roots and the transitions (for plan-memo.lisp)
  (signature nil)
  ;; (CUBE . SETS) of the last CUBE-SETS: regression tests a cube, then marks it
  (last-cube-sets (cons nil nil) :type cons))

(defun reachable-state (index number)
  "The one-hot state numbered NUMBER in INDEX."
  (svref (reachable-index-states index) number))

(defun reachable-number (index state)
  "The number of one-hot STATE in INDEX, or NIL when it is not reachable."
  (values (gethash state (reachable-index-numbers index))))

(defun reachable-state-p (index state)
  "Is one-hot STATE among INDEX's states?"
  (nth-value 1 (gethash state (reachable-index-numbers index))))

;;; The transitions: what moves a controller from state to state.

(defun op-applies-p (planner-op state)
  "Does PLANNER-OP's precondition hold in the one-hot STATE?"
  (some (lambda (cube) (state-in-cube-p state cube)) (planner-op-precondition planner-op)))

(defun transition-ops (spec)
  "SPEC's ops that change a state, must-ask ops and macro-ops included, as PLANNER-OPs."
  (loop for op in (spec-ops spec)
        when (op-effects op) collect (make-planner-op op spec)))

(defun event-assignment-ops (spec)
  "Unconditional pseudo-ops for every :add/:sub of a plannable literal in an event."
  (let ((ops '()))
    (dolist (event (spec-events spec) ops)
      (map-directives (lambda (directive)
                        (when (eq (first directive) :assign)
                          (push (make-planner-op
                                 (make-op-def :name (event-name event)
                                              :effects (list (cons (second directive)
                                                                   (third directive))))
                                 spec)
                                ops)))
                      (event-directives event)))))

(defun cut-ops (spec)
  "Pseudo-ops for the :if-cut effects of SPEC's ops: a timed controller that
cuts such an op leaves the state it started in (where its precondition held)
with those effects applied."
  (loop for op in (spec-ops spec)
        when (op-cut-effects op)
          collect (make-planner-op (make-op-def :name (op-name op) :precond (op-precond op)
                                                :effects (op-cut-effects op))
                                   spec)))

(defun reachability-transitions (spec)
  "Every way SPEC's state can change: its ops with effects, its events'
:add/:sub and its ops' :if-cut effects, as PLANNER-OPs."
  (append (transition-ops spec) (event-assignment-ops spec) (cut-ops spec)))

;;; The roots: the initial state and the :start-states.

(defun cube-states (cube layout limit form)
  "The one-hot states of CUBE; a SPEC-SYNTAX-ERROR naming FORM (the
:start-states expression CUBE comes from) when they are more than LIMIT."
  (let ((count (loop for mask across (layout-masks layout)
                     for offset across (layout-offsets layout)
                     for size across (layout-sizes layout)
                     for field = (ldb (byte size offset) cube)
                     for product = (logcount field) then (* product (logcount field))
                     finally (return (or product 1)))))
    (when (> count limit)
      (let ((*current-spec-name* (spec-name (layout-spec layout))))
        (spec-fail 'spec-syntax-error form ":start-states expression ~A holds in ~:D states, more than the ~:D one expression may name"
                   (bounded-lisp-text form 60) count limit))))
  (let ((states (list 0)))
    (loop for offset across (layout-offsets layout)
          for size across (layout-sizes layout)
          do (setf states (loop for value below size
                                when (logbitp (+ offset value) cube)
                                  nconc (let ((bit (ash 1 (+ offset value))))
                                          (mapcar (lambda (state) (logior state bit)) states)))))
    states))

(defun reachability-roots (layout)
  "The states the search for LAYOUT's reachable states starts from: its
spec's initial state, then the states of each :start-states expression."
  (let ((spec (layout-spec layout)))
    (cons (initial-state spec)
          (loop for ast in (spec-start-state-asts spec)
                for form in (getf (spec-options spec) :start-states)
                nconc (loop for cube in (expression-cubes ast spec)
                            nconc (cube-states cube layout *start-state-limit* form))))))

(defun reached-states (roots transitions limit)
  "The one-hot states reached from ROOTS by TRANSITIONS (applied where their
preconditions hold), breadth first: (VALUES STATES NUMBERS), a vector in the
order found and a table from state to position. REACHABLE-SPACE-TOO-LARGE
past LIMIT states."
  (let ((states (make-array 64 :adjustable t :fill-pointer 0))
        (numbers (make-hash-table)))
    (flet ((add (state)
             (unless (gethash state numbers)
               (when (>= (fill-pointer states) limit)
                 (error 'reachable-space-too-large :limit limit))
               (setf (gethash state numbers) (fill-pointer states))
               (vector-push-extend state states))))
      (mapc #'add roots)
      (loop for next from 0
            while (< next (fill-pointer states))
            do (let ((state (aref states next)))
                 (dolist (op transitions)
                   (when (op-applies-p op state)
                     (add (apply-effects state op)))))))
    (values (coerce states 'simple-vector) numbers)))

;;; The index

(defun bit-sets (states bit-count)
  "For each of BIT-COUNT one-hot bits, the bitmap over the positions of
STATES of those that have it."
  (let ((sets (coerce (loop repeat bit-count
                            collect (make-array (length states) :element-type 'bit :initial-element 0))
                      'simple-vector)))
    (loop for state across states
          for number from 0
          do (loop for bit below (integer-length state)
                   when (logbitp bit state)
                     do (setf (sbit (svref sets bit) number) 1)))
    sets))

(defun add-reachable-index (layout)
  "LAYOUT with its spec's reachable states as its numbered states."
  (let* ((spec (layout-spec layout))
         (roots (reachability-roots layout))
         (transitions (reachability-transitions spec)))
    (multiple-value-bind (states numbers) (reached-states roots transitions *reachable-state-limit*)
      (let ((sets (bit-sets states (spec-bit-count spec))))
        (setf (layout-reachable layout)
              (%make-reachable-index
               :states states :numbers numbers :bit-sets sets
               :bit-counts (map 'simple-vector (lambda (set) (count 1 set)) sets)
               :all (make-array (length states) :element-type 'bit :initial-element 1)
               :signature (list roots (mapcar (lambda (op)
                                                (list (planner-op-precondition op)
                                                      (planner-op-effect-mask op)
                                                      (planner-op-effect-bits op)))
                                              transitions)))
              (layout-state-count layout) (max 1 (length states)))
        layout))))

;;; Cubes over the index

(defun choice-set (index offset size field)
  "(BITMAP . COUNT): the states of INDEX whose variable at OFFSET (SIZE
values) has one of the values of FIELD; made once per field."
  (let ((key (cons offset field)))
    (or (gethash key (reachable-index-choices index))
        (setf (gethash key (reachable-index-choices index))
              (let ((union (make-array (length (reachable-index-states index)) :element-type 'bit
                                                                                :initial-element 0)))
                (loop for value below size
                      when (logbitp value field)
                        do (bit-ior union (svref (reachable-index-bit-sets index) (+ offset value)) union))
                (cons union (count 1 union)))))))

(defun cube-sets (cube layout)
  "The bitmaps whose AND is the set of CUBE's states in LAYOUT's reachable
index, the most selective first (never none: the bitmap of every state then)."
  (let* ((index (layout-reachable layout))
         (last (reachable-index-last-cube-sets index)))
    (if (eql cube (car last))
        (cdr last)
        (let ((sets (compute-cube-sets cube layout index)))
          ;; one fresh cons, so a reader on another thread sees a whole pair
          (setf (reachable-index-last-cube-sets index) (cons cube sets))
          sets))))

(defun compute-cube-sets (cube layout index)
  "CUBE-SETS of CUBE in LAYOUT's reachable INDEX, worked out."
  (let ((sets (loop for offset of-type fixnum across (layout-offsets layout)
                    for size of-type fixnum across (layout-sizes layout)
                    for allowed = (loop for bit from offset below (+ offset size)
                                        count (logbitp bit cube))
                    unless (= allowed size)
                      collect (if (= 1 allowed)
                                  (let ((bit (loop for bit from offset
                                                   when (logbitp bit cube) return bit)))
                                    (cons (svref (reachable-index-bit-sets index) bit)
                                          (svref (reachable-index-bit-counts index) bit)))
                                  (choice-set index offset size (ldb (byte size offset) cube))))))
    (if sets
        ;; the most selective first: the AND of a word mostly stops there
        (let ((first (reduce (lambda (a b) (if (< (cdr b) (cdr a)) b a)) sets)))
          (coerce (cons (car first) (mapcar #'car (remove first sets :test #'eq))) 'simple-vector))
        (vector (reachable-index-all index)))))

(defmacro do-cube-words ((word pattern cube layout &key (within '+full-word+)) &body body)
  "Run BODY with WORD bound to each word index of the reachable bitmaps and
PATTERN to the 64-bit mask of CUBE's states in it that are also in WITHIN (a
form of WORD giving a 64-bit mask), for the words where there are some."
  (with-gensyms (sets count k)
    `(let* ((,sets (cube-sets ,cube ,layout))
            (,count (length ,sets)))
       (declare (type simple-vector ,sets) (type fixnum ,count))
       (dotimes (,word (ceiling (length (the simple-bit-vector (svref ,sets 0))) 64))
         (let ((,pattern (logand (the (unsigned-byte 64) ,within) (raw-word (svref ,sets 0) ,word))))
           (declare (type (unsigned-byte 64) ,pattern))
           (loop for ,k of-type fixnum from 1 below ,count
                 until (zerop ,pattern)
                 do (setf ,pattern (logand ,pattern (raw-word (svref ,sets ,k) ,word))))
           (unless (zerop ,pattern)
             ,@body))))))

(defun mark-reachable-cube (bitmap cube layout)
  "MARK-CUBE over a reachable index: set the bits of CUBE's states in BITMAP;
return how many were clear."
  (declare (type simple-bit-vector bitmap) (optimize speed))
  (let ((new 0))
    (declare (type fixnum new))
    (do-cube-words (word pattern cube layout)
      (let ((old (raw-word bitmap word)))
        (incf new (logcount (logandc1 old pattern)))
        (setf (sb-kernel:%vector-raw-bits bitmap word) (logior old pattern))))
    new))

(defun reachable-cube-has-unmarked-p (bitmap cube layout)
  "CUBE-HAS-UNMARKED-P over a reachable index: does CUBE hold a state whose
bit in BITMAP is clear?"
  (declare (type simple-bit-vector bitmap) (optimize speed))
  ;; Starting from the clear bits, a word that is already full costs one read.
  (do-cube-words (word pattern cube layout :within (logandc2 +full-word+ (raw-word bitmap word)))
    (return-from reachable-cube-has-unmarked-p (plusp pattern)))
  nil)

;;; The planned set

(defun planned-state-p (machine state)
  "Does MACHINE have shortest plans from one-hot STATE: always in the full
space, for its reachable states in the reachable regime?"
  (let ((index (layout-reachable (machine-layout machine))))
    (or (null index) (reachable-state-p index state))))

(defun state-description (state spec)
  "One-hot STATE of SPEC as text, var=value separated by spaces, at most 200 characters."
  (truncate-text (format nil "~{~A~^ ~}"
                         (loop for var in (plannable-variables spec)
                               for field = (ldb (byte (var-domain-size var) (var-bit-offset var)) state)
                               for index = (1- (integer-length field))
                               collect (format nil "~A=~A" (lisp-text (var-name var))
                                               (if (eq (var-kind var) :boolean)
                                                   (if (= index 1) "true" "false")
                                                   (lisp-text (aref (var-domain var) index))))))
                 200))

(defun refuse-unplanned-state (machine state &optional goal)
  "Signal STATE-OUTSIDE-PLANNED-SET for one-hot STATE of MACHINE (while
achieving GOAL, if given)."
  (let ((spec (machine-spec machine)))
    (error 'state-outside-planned-set
           :spec (lisp-text (spec-name spec)) :state (state-description state spec)
           :goal (and goal (goal-description goal)))))
