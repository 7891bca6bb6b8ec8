;;;; reachable.lisp -- the reachable regime: plans for the states that can
;;;; happen, not for every combination of values.
;;;;
;;;; A spec of 30 to 100 facts has far too many combinations for a bit per
;;;; state, yet few of them can ever occur (four blocks on a table: 29
;;;; booleans, 125 states). So a forward breadth-first search from the
;;;; initial state and the :start-states, under every op (must-ask ops and
;;;; macro-ops too), every event's :add/:sub and every op's :if-cut (what a
;;;; timed controller leaves when it cuts the op), finds the reachable set R;
;;;; its states are numbered in ascending order, and SolvedStates becomes a
;;;; bit per state of R. For each bit of the one-hot state, the states of R
;;;; that have it are a bitmap over R too, so the states of R in a cube are
;;;; the AND, over the variables the cube constrains, of the OR of the
;;;; bitmaps of the values it allows: asking "does this cube hold a state of
;;;; R not yet solved" is a few word operations per 64 states of R. A bit per
;;;; word of each bitmap (the word holds states) and of SolvedStates (the word
;;;; is full) lets most words be skipped 64 at a time: in ascending order, a
;;;; cube's states lie in few words.
;;;;
;;;; R is closed under the planner's operators, so the paper's regression
;;;; (regression.lisp) runs unchanged and still finds shortest plans for
;;;; every state of R: a regressed cube whose states in R are all solved can
;;;; give no state of R a shorter plan. (Its plans may also hold in states
;;;; outside R, where nothing says they are shortest: the controller refuses
;;;; such states, see src/control/controller/unplanned-states.lisp.)
;;;; Memory is a bit per state of R per one-hot bit, nothing per 2^bits.

(in-package #:player.planner)

(defparameter *reachable-state-limit* (expt 2 22)
  "Most reachable states the reachable regime numbers and plans for.")

(defparameter *start-state-limit* (expt 2 16)
  "Most states one (:start-states EXPR...) expression may stand for.")

(defstruct (state-set (:constructor %make-state-set (bits count words)))
  "Some states of a reachable index: BITS, a bit per state number; COUNT, how
many; WORDS, a bit per 64-bit word of BITS, set when the word holds one."
  (bits nil :type bitmap)
  (count 0 :type fixnum)
  (words nil :type bitmap))

(defun make-state-set (bits)
  "The STATE-SET of the states whose bits are set in BITS (a BITMAP)."
  (let ((words (make-bitmap (length bits))))
    (dotimes (word (length bits))
      (unless (zerop (bitmap-word bits word))
        (setf (bitmap-bit words word) 1)))
    (%make-state-set bits (count-marked bits) words)))

(defstruct (reachable-index (:constructor %make-reachable-index))
  "The reachable states of a spec, numbered, with their STATE-SET per one-hot bit."
  ;; one-hot states by number: ascending, so the states a cube fixes the
  ;; high variables of lie in runs of numbers (and of words)
  (states #() :type simple-vector)
  ;; one-hot state -> its number
  (numbers (make-hash-table) :type hash-table)
  ;; for each one-hot bit: the STATE-SET of the states that have it
  (bit-sets #() :type simple-vector)
  ;; the STATE-SET of every state
  (all nil)
  ;; for each one-hot bit: the position of its variable in the layout
  (bit-variables #() :type simple-vector)
  ;; the cube of every state
  (top 0 :type unsigned-byte)
  ;; (OFFSET . FIELD) -> STATE-SET, for variables a cube allows several values of
  ;; (synchronized: PLANS may plan goals of one machine on several threads)
  (choices (make-hash-table :test 'equal :synchronized t) :type hash-table)
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
      (with-spec-context (:spec-name (spec-name (layout-spec layout)))
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

(defun states-reached (roots transitions limit)
  "The one-hot states reached from the states ROOTS by TRANSITIONS (PLANNER-OPs
applied where their preconditions hold), ROOTS included, as a hash table
whose keys they are; NIL as soon as there are more than LIMIT.  (The order of
the search does not matter: only the set is kept.)"
  (let ((seen (make-hash-table)) (queue '())
        (expansion-cost (state-expansion-cost roots transitions)))
    (flet ((add (state)
             (unless (gethash state seen)
               (when (>= (hash-table-count seen) limit)
                 (return-from states-reached nil))
               (setf (gethash state seen) t)
               (push state queue))))
      (mapc #'add roots)
      (setf queue (nreverse queue))
      (loop while queue
            do (let ((state (pop queue)))
                 (spend-planning-units expansion-cost)
                 (dolist (op transitions)
                   (when (op-applies-p op state)
                     (add (apply-effects state op)))))))
    seen))

(defun reached-states (roots transitions limit)
  "The one-hot states reached from ROOTS by TRANSITIONS (STATES-REACHED):
(VALUES STATES NUMBERS), a vector in ascending order and a table from state to
position. REACHABLE-SPACE-TOO-LARGE past LIMIT states."
  (let* ((seen (or (states-reached roots transitions limit)
                   (error 'reachable-space-too-large :limit limit)))
         (sorted (sort (coerce (hash-table-keys seen) 'simple-vector) #'<))
         (numbers (make-hash-table :size (hash-table-count seen))))
    (loop for state across sorted
          for number from 0
          do (setf (gethash state numbers) number))
    (values sorted numbers)))

;;; The index

(defun bit-sets (states bit-count)
  "For each of BIT-COUNT one-hot bits, the STATE-SET of the positions of
STATES of those that have it."
  (let ((sets (coerce (loop repeat bit-count
                            collect (make-bitmap (length states)))
                      'simple-vector)))
    (loop for state across states
          for number from 0
          do (loop for bit below (integer-length state)
                   when (logbitp bit state)
                     do (setf (bitmap-bit (svref sets bit) number) 1)))
    (map 'simple-vector #'make-state-set sets)))

(defun add-reachable-index (layout)
  "LAYOUT with its spec's reachable states as its numbered states."
  (let* ((spec (layout-spec layout))
         (roots (reachability-roots layout))
         (transitions (reachability-transitions spec)))
    (multiple-value-bind (states numbers) (reached-states roots transitions *reachable-state-limit*)
      (setf (layout-reachable layout)
            (%make-reachable-index
             :states states :numbers numbers :bit-sets (bit-sets states (spec-bit-count spec))
             :bit-variables (coerce (loop for size across (layout-sizes layout)
                                          for k from 0
                                          nconc (make-list size :initial-element k))
                                    'simple-vector)
             :top (top-cube spec)
             :all (make-state-set (make-bitmap (length states) :initial-bit 1))
             :signature (list roots (mapcar (lambda (op)
                                              (list (planner-op-precondition op)
                                                    (planner-op-effect-mask op)
                                                    (planner-op-effect-bits op)))
                                            transitions)))
            (layout-state-count layout) (max 1 (length states)))
      layout)))

;;; Cubes over the index

(defun choice-set (index offset size field)
  "The STATE-SET of the states of INDEX whose variable at OFFSET (SIZE values)
has one of the values of FIELD; made once per field."
  (let ((key (cons offset field)))
    (or (gethash key (reachable-index-choices index))
        (setf (gethash key (reachable-index-choices index))
              (let ((union (make-bitmap (length (reachable-index-states index)))))
                (loop for value below size
                      when (logbitp value field)
                        do (bitmap-ior-into union (state-set-bits (svref (reachable-index-bit-sets index)
                                                                         (+ offset value)))))
                (make-state-set union))))))

(defun cube-sets (cube layout)
  "The STATE-SETs whose intersection is CUBE's states in LAYOUT's reachable
index, the most selective first (never none: the set of every state then)."
  (let* ((index (layout-reachable layout))
         (last (reachable-index-last-cube-sets index)))
    (if (eql cube (car last))
        (cdr last)
        (let ((sets (compute-cube-sets cube layout index)))
          ;; one fresh cons, so a reader on another thread sees a whole pair
          (setf (reachable-index-last-cube-sets index) (cons cube sets))
          sets))))

(defun map-set-bits (function integer)
  "Call FUNCTION on the position of each bit set in the non-negative INTEGER,
ascending, a 64-bit digit at a time (LOGBITP on a bignum costs a call per bit)."
  (declare (type function function) (type unsigned-byte integer) (optimize speed))
  (flet ((digit (bits base)
           (declare (type (unsigned-byte 64) bits) (type fixnum base))
           (loop until (zerop bits)
                 do (let ((low (logand bits (ldb (byte 64 0) (- bits)))))
                      (declare (type (unsigned-byte 64) low))
                      (funcall function (+ base (1- (integer-length low))))
                      (setf bits (logxor bits low))))))
    (if (typep integer 'fixnum)
        (digit integer 0)
        (dotimes (i (sb-bignum:%bignum-length integer))
          (digit (sb-bignum:%bignum-ref integer i) (* 64 i))))))

(defun variable-set (index layout k cube)
  "The STATE-SET of INDEX's states whose variable K (in LAYOUT) has a value CUBE allows."
  (let* ((offset (svref (layout-offsets layout) k))
         (field (ldb (byte (svref (layout-sizes layout) k) offset) cube)))
    (if (= 1 (logcount field))
        (svref (reachable-index-bit-sets index) (+ offset (1- (integer-length field))))
        (choice-set index offset (svref (layout-sizes layout) k) field))))

(defun compute-cube-sets (cube layout index)
  "CUBE-SETS of CUBE in LAYOUT's reachable INDEX, worked out: a set per
variable with a value CUBE excludes."
  (let ((sets '())
        (previous -1)
        (bit-variables (reachable-index-bit-variables index)))
    (map-set-bits (lambda (bit)
                    ;; a variable's excluded bits come one after another
                    (let ((k (svref bit-variables bit)))
                      (unless (eql k previous)
                        (setf previous k)
                        (push (variable-set index layout k cube) sets))))
                  (logandc1 cube (reachable-index-top index)))
    (if sets
        ;; the most selective first: the AND of a word mostly stops there
        (let ((first (reduce (lambda (a b) (if (< (state-set-count b) (state-set-count a)) b a)) sets)))
          (coerce (cons first (remove first sets :test #'eq)) 'simple-vector))
        (vector (reachable-index-all index)))))

(defmacro do-cube-words ((word pattern cube layout full &key (within '+full-word+) scanned) &body body)
  "Run BODY with WORD bound to each word index of the reachable bitmaps and
PATTERN to the 64-bit mask of CUBE's states in it that are also in WITHIN (a
form of WORD giving a 64-bit mask), for the words where there are some.
Words are taken 64 at a time: only those where every set of the cube has
states and whose bit in FULL (a bitmap of a bit per word, set when the word
is full) is clear are read.  SCANNED, a fixnum variable, counts the words read."
  (with-gensyms (sets count k group open low position)
    `(let* ((,sets (cube-sets ,cube ,layout))
            (,count (length ,sets)))
       (declare (type simple-vector ,sets) (type fixnum ,count))
       (dotimes (,group (length (state-set-words (svref ,sets 0))))
         (incf ,scanned ,count)
         (let ((,open (logandc2 +full-word+ (bitmap-word ,full ,group))))
           (declare (type (unsigned-byte 64) ,open))
           (loop for ,k of-type fixnum from 0 below ,count
                 until (zerop ,open)
                 do (setf ,open (logand ,open (bitmap-word (state-set-words (svref ,sets ,k)) ,group))))
           (loop until (zerop ,open)
                 do (let* ((,low (logand ,open (ldb (byte 64 0) (- ,open))))
                           (,position (1- (integer-length ,low)))
                           (,word (+ (* ,group 64) ,position))
                           (,pattern (logand (the (unsigned-byte 64) ,within)
                                             (bitmap-word (state-set-bits (svref ,sets 0)) ,word))))
                      (declare (type (unsigned-byte 64) ,low ,pattern) (type fixnum ,position ,word))
                      (setf ,open (logxor ,open ,low))
                      (incf ,scanned ,count)
                      (loop for ,k of-type fixnum from 1 below ,count
                            until (zerop ,pattern)
                            do (setf ,pattern (logand ,pattern (bitmap-word (state-set-bits (svref ,sets ,k)) ,word))))
                      (unless (zerop ,pattern)
                        ,@body))))))))

(defun mark-reachable-cube (solved-states cube layout)
  "MARK-CUBE over a reachable index: add CUBE's states to SOLVED-STATES, keeping
its bit per full word up to date; return how many were not in it before."
  (declare (optimize speed))
  (let* ((bitmap (solved-states-bits solved-states))
         (full (solved-states-full-words solved-states))
         (last (1- (length bitmap)))
         ;; the bits of the last word that stand for states
         (last-states (let ((rest (mod (layout-state-count layout) 64)))
                        (if (zerop rest) +full-word+ (1- (ash 1 rest)))))
         (new 0) (scanned 0))
    (declare (type bitmap bitmap full) (type fixnum new last scanned)
             (type (unsigned-byte 64) last-states))
    (do-cube-words (word pattern cube layout full :scanned scanned)
      (let* ((old (bitmap-word bitmap word))
             (now (logior old pattern)))
        (declare (type (unsigned-byte 64) now))
        (unless (= old now)
          (incf new (logcount (logxor old now)))
          (setf (bitmap-word bitmap word) now)
          (when (= now (if (= word last) last-states +full-word+))
            (setf (bitmap-bit full word) 1)))))
    (spend-scanned-words scanned new)))

(defun reachable-cube-has-unmarked-p (solved-states cube layout)
  "CUBE-HAS-UNMARKED-P over a reachable index: does CUBE hold a state not in
SOLVED-STATES?"
  (declare (optimize speed))
  (let ((bitmap (solved-states-bits solved-states)) (scanned 0))
    (declare (type bitmap bitmap) (type fixnum scanned))
    ;; Starting from the clear bits, a word that is already full costs one read.
    (do-cube-words (word pattern cube layout (the bitmap (solved-states-full-words solved-states))
                    :within (logandc2 +full-word+ (bitmap-word bitmap word)) :scanned scanned)
      (return-from reachable-cube-has-unmarked-p (spend-scanned-words scanned (plusp pattern))))
    (spend-scanned-words scanned nil)))

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
