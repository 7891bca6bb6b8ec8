;;;; encoding.lisp -- the plannable state space, for the planner's bookkeeping.
;;;; At run time a state is the one-hot integer of canonical.lisp. The planner
;;;; also numbers states densely (mixed radix over the domains) so SolvedStates
;;;; can be a bit vector with one bit per state (solved-states.lisp).
;;;; Past *FULL-SPACE-THRESHOLD* states (or when the spec says (:state-space
;;;; :reachable)) only the states reachable from the initial state are planned
;;;; for and numbered, in ascending order (reachable.lisp).

(in-package #:player.planner)

(defparameter *state-limit* (expt 2 26)
  "Most plannable states the full-space planner accepts (the SolvedStates bitmap
is this many bits).")

(defparameter *full-space-threshold* (expt 2 26)
  "Most plannable states for which (:state-space :auto), the default, plans
every state; past it, only the reachable ones.")

(defparameter *group-threshold* (expt 2 18)
  "Fewest states for which SolvedStates keeps a bit per full word (solved-states.lisp):
below it, reading the words themselves is as quick.")

(defstruct (layout (:constructor %make-layout))
  "The plannable variables of a spec with their one-hot fields and dense strides."
  (spec nil)
  (variables #() :type simple-vector)
  (sizes #() :type simple-vector)
  (offsets #() :type simple-vector)
  (masks #() :type simple-vector)
  (strides #() :type simple-vector)
  ;; how many states are numbered: the product space, or the reachable states
  (state-count 1 :type (integer 1))
  ;; the product of the domain sizes
  (space-size 1 :type (integer 1))
  ;; the REACHABLE-INDEX of the states numbered, or NIL for the full space
  (reachable nil)
  ;; leading variables spanning exactly one 64-bit word, or NIL (see CUBE-WORD-PATTERN)
  (word-prefix nil)
  (word-masks #() :type simple-vector)
  ;; the next variables, spanning exactly 64 words (a group), or NIL
  (group-prefix nil)
  (group-masks #() :type simple-vector))

(defun make-layout (spec)
  "The layout of SPEC's plannable state: every state when SPEC's :state-space
lets FULL-SPACE-P choose that, else the states reachable from its initial
state and :start-states. STATE-SPACE-TOO-LARGE for (:state-space :full) past
*STATE-LIMIT*, REACHABLE-SPACE-TOO-LARGE past *REACHABLE-STATE-LIMIT*."
  (let* ((vars (coerce (plannable-variables spec) 'simple-vector))
         (sizes (map 'simple-vector #'var-domain-size vars))
         (strides (make-array (length vars)))
         (count 1))
    (loop for i below (length vars)
          do (setf (aref strides i) count
                   count (* count (aref sizes i))))
    (let ((layout (%make-layout :spec spec :variables vars :sizes sizes
                                :offsets (map 'simple-vector #'var-bit-offset vars)
                                :masks (map 'simple-vector #'var-field-mask vars)
                                :strides strides :state-count count :space-size count)))
      (if (full-space-p spec count)
          (add-word-prefixes layout)
          (add-reachable-index layout)))))

(defun full-space-p (spec count)
  "Does SPEC, of COUNT plannable states, get plans from every state? Under
(:state-space :auto) when COUNT is at most *FULL-SPACE-THRESHOLD*; always
under :full, which signals STATE-SPACE-TOO-LARGE past *STATE-LIMIT*; never
under :reachable."
  (ecase (spec-state-space spec)
    (:auto (and (<= count *full-space-threshold*) (full-space-p-or-fail count)))
    (:full (full-space-p-or-fail count))
    (:reachable nil)))

(defun full-space-p-or-fail (count)
  "T when COUNT states fit *STATE-LIMIT*; STATE-SPACE-TOO-LARGE otherwise."
  (when (> count *state-limit*)
    (error 'state-space-too-large :states count :limit *state-limit*))
  t)

(defun add-word-prefixes (layout)
  "LAYOUT, a full space, with its word and group prefixes filled in."
  (when-let ((prefix (span-prefix layout 0 64)))
    (setf (layout-word-prefix layout) prefix
          (layout-word-masks layout) (position-value-masks layout 0 prefix 1))
    (when-let ((group (and (>= (layout-state-count layout) *group-threshold*)
                           (span-prefix layout prefix 64))))
      (setf (layout-group-prefix layout) group
            (layout-group-masks layout) (position-value-masks layout prefix group 64))))
  layout)

(defun layout-cube-empty-p (cube layout)
  "True when CUBE allows no state."
  (if (typep cube 'fixnum)
      (loop for mask across (layout-masks layout)
              thereis (zerop (logand cube mask)))
      ;; Past 62 bits LOGAND makes a bignum per field; LOGBITP makes none,
      ;; nor does reading a large field's 64-bit digits, a digit at a time.
      (loop for offset of-type fixnum across (layout-offsets layout)
            for size of-type fixnum across (layout-sizes layout)
              thereis (if (< size 16)
                          (loop for bit of-type fixnum from offset below (+ offset size)
                                never (logbitp bit cube))
                          (bignum-field-zero-p cube offset size)))))

(defun bignum-field-zero-p (integer offset size)
  "True when bits [OFFSET, OFFSET+SIZE) of the non-negative bignum INTEGER are
all clear, read a 64-bit digit at a time."
  (declare (type unsigned-byte integer) (type fixnum offset size) (optimize speed))
  (let ((length (sb-bignum:%bignum-length integer))
        (end (+ offset size)))
    (declare (type fixnum length end))
    (loop for digit of-type fixnum from (floor offset 64) to (floor (1- end) 64)
          while (< digit length)
          never (let* ((base (* digit 64))
                       (low (max 0 (- offset base)))
                       (high (min 64 (- end base))))
                  (declare (type fixnum base low high))
                  (logtest (sb-bignum:%bignum-ref integer digit)
                           (ldb (byte 64 0) (ash (ldb (byte (- high low) 0) -1) low)))))))

(defun dense-to-state (dense layout)
  "The one-hot state numbered DENSE."
  (when-let ((index (layout-reachable layout)))
    (return-from dense-to-state (reachable-state index dense)))
  (loop with state = 0
        for size across (layout-sizes layout)
        for offset across (layout-offsets layout)
        do (multiple-value-bind (rest index) (floor dense size)
             (setf state (logior state (ash 1 (+ offset index)))
                   dense rest))
        finally (return state)))

(defun state-to-dense (state layout)
  "The dense number of one-hot STATE (NIL for a state the layout does not number)."
  (when-let ((index (layout-reachable layout)))
    (return-from state-to-dense (reachable-number index state)))
  (loop for size across (layout-sizes layout)
        for offset across (layout-offsets layout)
        for stride across (layout-strides layout)
        ;; a one-hot field holding value I is 2^I
        sum (* stride (1- (integer-length (ldb (byte size offset) state))))))

;;; The planner spends most of its time on the states of cubes. The variables
;;; a cube leaves free at the low end of the numbering make its states come in
;;; contiguous runs; the other variables turn like an odometer over fixnums.
;;; The same holds for the words (64 states) and groups (64 words) of a
;;; bitmap: dividing the dense numbers by a UNIT drops the lowest variables.

(declaim (inline cube-field))
(defun cube-field (cube layout k)
  "The bits of the values CUBE allows variable K, shifted to bit 0."
  (ldb (byte (svref (layout-sizes layout) k) (svref (layout-offsets layout) k)) cube))

(defun field-contributions (field step)
  "The dense contributions of the values in FIELD of a variable of stride STEP."
  (declare (type unsigned-byte field) (type fixnum step) (optimize speed))
  (let ((digit (make-array (logcount field) :element-type 'fixnum))
        (j 0))
    (declare (type fixnum j))
    (loop for i of-type fixnum from 0 below (integer-length field)
          when (logbitp i field)
            do (setf (aref digit j) (* i step))
               (incf j))
    digit))

(defun merge-digits (low high)
  "One digit for two: every sum of an entry of LOW and one of HIGH, ascending."
  (declare (type (simple-array fixnum (*)) low high) (optimize speed))
  (let ((merged (make-array (* (length low) (length high)) :element-type 'fixnum))
        (j 0))
    (declare (type fixnum j))
    (loop for b of-type fixnum across high
          do (loop for a of-type fixnum across low
                   do (setf (aref merged j) (+ a b))
                      (incf j)))
    merged))

(defun cube-index-runs (cube layout from unit)
  "(VALUES INNER OUTER RUN): the indices (dense number / UNIT, where UNIT is the
stride of variable FROM) of CUBE's states are the runs [BASE+I, BASE+I+RUN)
for every I in the fixnum vector INNER and every BASE that sums one entry of
each vector in OUTER (DO-ODOMETER's digits). Variables that CUBE fixes never
turn: their contribution is added to INNER; the lowest turning variables are
merged into INNER until it has 64 entries, so the odometer seldom turns."
  (declare (type fixnum from unit) (optimize speed))
  (let* ((sizes (layout-sizes layout))
         (offsets (layout-offsets layout))
         (strides (layout-strides layout))
         (n (length sizes))
         (fields (make-array n :initial-element 0))
         (constrained n)
         (constant 0)
         (digits '()))
    (declare (type simple-vector sizes offsets strides) (type fixnum n constrained constant))
    (loop for k of-type fixnum from (1- n) downto from
          for size of-type fixnum = (svref sizes k)
          for field of-type unsigned-byte = (ldb (byte size (the fixnum (svref offsets k))) cube)
          do (setf (svref fields k) field)
             (unless (= field (1- (ash 1 size)))
               (setf constrained k)))
    (loop for k of-type fixnum from (1- n) downto constrained
          for field of-type unsigned-byte = (svref fields k)
          for step of-type fixnum = (floor (the fixnum (svref strides k)) unit)
          do (if (= (logcount field) 1)
                 (incf constant (the fixnum (* (1- (integer-length field)) step)))
                 (push (field-contributions field step) digits)))
    (loop while (and (rest digits) (< (length (the (simple-array fixnum (*)) (first digits))) 64))
          do (setf digits (cons (merge-digits (first digits) (second digits)) (cddr digits))))
    (let ((inner (or (first digits) (make-array 1 :element-type 'fixnum :initial-element 0))))
      (declare (type (simple-array fixnum (*)) inner))
      (dotimes (j (length inner)) (incf (aref inner j) constant))
      (values inner
              (coerce (rest digits) 'simple-vector)
              (floor (the fixnum (if (< constrained n)
                                     (svref strides constrained)
                                     (layout-state-count layout)))
                     unit)))))

(defmacro do-odometer ((base choices) &body body)
  "Run BODY with BASE bound to every sum of one entry from each vector of
CHOICES (a simple-vector of fixnum vectors), kept up to date digit by digit."
  (with-gensyms (count counters k digit values)
    `(let* ((,count (length ,choices))
            (,counters (make-array ,count :element-type 'fixnum :initial-element 0))
            (,base (loop for ,k of-type fixnum below ,count
                         sum (aref (the (simple-array fixnum (*)) (svref ,choices ,k)) 0)
                           of-type fixnum)))
       (declare (type fixnum ,count ,base))
       (loop
         (progn ,@body)
         (unless (loop for ,k of-type fixnum below ,count
                       for ,values = (the (simple-array fixnum (*)) (svref ,choices ,k))
                       for ,digit of-type fixnum = (aref ,counters ,k)
                       do (if (< (1+ ,digit) (length ,values))
                              (progn (incf ,base (- (aref ,values (1+ ,digit)) (aref ,values ,digit)))
                                     (setf (aref ,counters ,k) (1+ ,digit))
                                     (return t))
                              (progn (decf ,base (- (aref ,values ,digit) (aref ,values 0)))
                                     (setf (aref ,counters ,k) 0))))
           (return))))))

(defmacro do-cube-runs ((start end cube layout &key (from 0) (unit 1)) &body body)
  "Run BODY with START and END bound to each run [START, END) of the indices
(dense number / UNIT) of CUBE's states; UNIT is the stride of variable FROM."
  (with-gensyms (inner outer run base offset)
    `(multiple-value-bind (,inner ,outer ,run) (cube-index-runs ,cube ,layout ,from ,unit)
       (declare (type (simple-array fixnum (*)) ,inner) (type simple-vector ,outer)
                (type fixnum ,run))
       (do-odometer (,base ,outer)
         (loop for ,offset of-type fixnum across ,inner
               do (let* ((,start (+ ,base ,offset))
                         (,end (+ ,start ,run)))
                    (declare (type fixnum ,start ,end))
                    ,@body))))))

(defmacro do-cube-indices ((index cube layout &key (from 0) (unit 1)) &body body)
  "Run BODY with INDEX bound to each index (dense number / UNIT) of CUBE's states."
  (with-gensyms (start end)
    `(do-cube-runs (,start ,end ,cube ,layout :from ,from :unit ,unit)
       (loop for ,index of-type fixnum from ,start below ,end
             do (progn ,@body)))))

;;; When the first variables of the dense numbering span exactly 64 states
;;; (six booleans, say), every 64-bit word of a bitmap holds all their
;;; combinations for one assignment of the others: a cube then covers a fixed
;;; 64-bit pattern in each of the words its other variables select. When the
;;; next variables span exactly 64 words, a cube likewise covers a fixed
;;; pattern of the words of each group of 64 words it touches.

(defun span-prefix (layout from span)
  "How many variables of LAYOUT from FROM on span exactly SPAN values, or NIL."
  (loop with product = 1
        for k from from below (length (layout-sizes layout))
        for count from 1
        do (setf product (* product (svref (layout-sizes layout) k)))
        when (= product span) return count
        while (< product span)))

(defun position-value-masks (layout from count unit)
  "For each of the COUNT variables from FROM on, a vector giving for each value
the 64-bit mask of the positions (dense number / UNIT, modulo 64) where the
variable has that value."
  (coerce (loop for k from from below (+ from count)
                for size = (svref (layout-sizes layout) k)
                for step = (/ (svref (layout-strides layout) k) unit)
                collect (coerce (loop for i below size
                                      collect (loop for position below 64
                                                    when (= i (mod (floor position step) size))
                                                      sum (ash 1 position)))
                                '(simple-array (unsigned-byte 64) (*))))
          'simple-vector))

(defun cube-position-pattern (cube layout from masks)
  "The 64-bit mask of the positions CUBE allows, given the MASKS of
POSITION-VALUE-MASKS for the variables from FROM on."
  (declare (type simple-vector masks) (type fixnum from) (optimize speed))
  (let ((pattern (ldb (byte 64 0) -1)))
    (declare (type (unsigned-byte 64) pattern))
    (loop for k of-type fixnum from from
          for value-masks of-type (simple-array (unsigned-byte 64) (*)) across masks
          do (let ((field (cube-field cube layout k))
                   (allowed 0))
               (declare (type (unsigned-byte 64) allowed))
               (loop for i of-type fixnum below (length value-masks)
                     when (logbitp i field)
                       do (setf allowed (logior allowed (aref value-masks i))))
               (setf pattern (logand pattern allowed))))
    pattern))

(defun cube-word-pattern (cube layout)
  "The 64-bit mask of the states CUBE allows in each of its words."
  (cube-position-pattern cube layout 0 (layout-word-masks layout)))

(defun cube-group-pattern (cube layout)
  "The 64-bit mask of the words CUBE touches in each of its groups."
  (cube-position-pattern cube layout (layout-word-prefix layout) (layout-group-masks layout)))
