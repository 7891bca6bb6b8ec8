;;;; solved-states.lisp -- SolvedStates, the paper's disjunction of the start
;;;; states already solved (Kurlander & Ling, CHI '95, Figure 4), kept as a set
;;;; of dense states: a bit per state, marked and tested a 64-bit word at a
;;;; time. When the layout has groups (64 words spanned by whole variables), a
;;;; second bitmap holds a bit per word telling that the word is full, so a
;;;; cube's words that are already full are skipped 64 at a time: asking
;;;; "is NewState subsumed by SolvedStates?" costs about what is left unsolved.
;;;; And as SolvedStates only grows, a cube once found inside it (or added to
;;;; it) stays inside: the last such cubes are remembered, since regression
;;;; often makes the same cube again.
;;;;
;;;; SBCL stores a bit vector's bit I as bit (MOD I 64) of word (FLOOR I 64).

(in-package #:player.planner)

(defparameter *known-cube-limit* 65536
  "How many cubes known to lie inside a SolvedStates it remembers (it forgets
them all past that).")

(defstruct (solved-states (:constructor %make-solved-states (bits full-words)))
  "A set of dense states of a layout."
  (bits nil :type bitmap)
  ;; a bit per word of BITS, set when the word is full; NIL without groups
  ;; (and with a reachable index, see reachable.lisp)
  (full-words nil :type (or null bitmap))
  ;; cubes known to lie inside
  (known (make-hash-table) :type hash-table))

(defun make-solved-states (layout)
  "An empty SolvedStates for LAYOUT."
  (let ((count (layout-state-count layout)))
    (%make-solved-states (make-bitmap count)
                         (cond ((layout-reachable layout) ; a bit per word, the last one partial
                                (make-bitmap (ceiling count 64)))
                               ((layout-group-prefix layout)
                                (make-bitmap (floor count 64)))))))

(defun copy-solved-states-deeply (solved-states)
  "A fresh SolvedStates holding the same states (and remembering no cube)."
  (%make-solved-states (copy-seq (solved-states-bits solved-states))
                       (when-let ((full (solved-states-full-words solved-states)))
                         (copy-seq full))))

(defun known-inside-p (solved-states cube)
  "True when CUBE is remembered to lie inside SOLVED-STATES."
  (gethash cube (solved-states-known solved-states)))

(defun remember-inside (solved-states cube)
  "Remember that CUBE lies inside SOLVED-STATES."
  (let ((known (solved-states-known solved-states)))
    (when (>= (hash-table-count known) *known-cube-limit*)
      (clrhash known))
    (setf (gethash cube known) t)))

(defun mark-cube (solved-states cube layout)
  "Add CUBE's states to SOLVED-STATES; return how many were not in it before."
  (if (known-inside-p solved-states cube)
      0
      (let ((bits (solved-states-bits solved-states)))
        (prog1 (cond ((layout-reachable layout) (mark-reachable-cube solved-states cube layout))
                     ((solved-states-full-words solved-states) (mark-cube-groups solved-states cube layout))
                     ((layout-word-prefix layout) (mark-cube-words bits cube layout))
                     (t (mark-cube-runs bits cube layout)))
          (remember-inside solved-states cube)))))

(defun cube-has-unmarked-p (solved-states cube layout)
  "True when some state of CUBE is not in SOLVED-STATES."
  (unless (known-inside-p solved-states cube)
    (let ((bits (solved-states-bits solved-states)))
      (or (cond ((layout-reachable layout) (reachable-cube-has-unmarked-p solved-states cube layout))
                ((solved-states-full-words solved-states) (cube-groups-have-unmarked-p solved-states cube layout))
                ((layout-word-prefix layout) (cube-words-have-unmarked-p bits cube layout))
                (t (cube-runs-have-unmarked-p bits cube layout)))
          (progn (remember-inside solved-states cube) nil)))))

;;; Any layout: runs of states.

(declaim (inline range-word-mask))
(defun range-word-mask (start end)
  "(VALUES WORD MASK COUNT): the word holding bit START, the mask of bits
[START, END) within it, and how many bits that is."
  (declare (type fixnum start end) (optimize speed))
  (multiple-value-bind (word bit) (floor start 64)
    (let ((count (min (- 64 bit) (- end start))))
      (values word
              (ldb (byte 64 0) (ash (ldb (byte count 0) +full-word+) bit))
              count))))

(defun mark-range (bitmap start end)
  "Set bits [START, END) of BITMAP; return how many of them were clear."
  (declare (type bitmap bitmap) (type fixnum start end) (optimize speed))
  (let ((new 0))
    (declare (type fixnum new))
    (loop while (< start end)
          do (multiple-value-bind (word mask count) (range-word-mask start end)
               (declare (type (unsigned-byte 64) mask) (type fixnum count))
               (let ((old (bitmap-word bitmap word)))
                 (incf new (logcount (logandc1 old mask)))
                 (setf (bitmap-word bitmap word) (logior old mask))
                 (incf start count))))
    new))

(defun range-has-clear-p (bitmap start end)
  "True when some bit of [START, END) in BITMAP is clear."
  (declare (type bitmap bitmap) (type fixnum start end) (optimize speed))
  (loop while (< start end)
        do (multiple-value-bind (word mask count) (range-word-mask start end)
             (declare (type (unsigned-byte 64) mask) (type fixnum count))
             (unless (zerop (logandc1 (bitmap-word bitmap word) mask))
               (return-from range-has-clear-p t))
             (incf start count)))
  nil)

(defun mark-cube-runs (bitmap cube layout)
  "MARK-CUBE on the bits of BITMAP, run by run."
  (declare (type bitmap bitmap) (optimize speed))
  (let ((new 0) (scanned 0))
    (declare (type fixnum new scanned))
    ;; A run within one word is one masked store, like a long run's words.
    (do-cube-runs (start end cube layout)
      (incf scanned (1+ (ash (- end start) -6)))
      (incf new (mark-range bitmap start end)))
    (spend-scanned-words scanned)
    new))

(defun cube-runs-have-unmarked-p (bitmap cube layout)
  "CUBE-HAS-UNMARKED-P on the bits of BITMAP, run by run."
  (declare (type bitmap bitmap) (optimize speed))
  (let ((scanned 0))
    (declare (type fixnum scanned))
    (do-cube-runs (start end cube layout)
      (incf scanned (1+ (ash (- end start) -6)))
      (when (range-has-clear-p bitmap start end)
        (return-from cube-runs-have-unmarked-p (spend-scanned-words scanned t))))
    (spend-scanned-words scanned nil)))

;;; Layouts with a word prefix: a fixed pattern in each of the cube's words.

(defun mark-cube-words (bitmap cube layout)
  "MARK-CUBE on the bits of BITMAP, word by word."
  (declare (type bitmap bitmap) (optimize speed))
  (let ((pattern (cube-word-pattern cube layout))
        (new 0) (scanned 0))
    (declare (type (unsigned-byte 64) pattern) (type fixnum new scanned))
    (do-cube-indices (word cube layout :from (layout-word-prefix layout) :unit 64)
      (incf scanned)
      (let ((old (bitmap-word bitmap word)))
        (incf new (logcount (logandc1 old pattern)))
        (setf (bitmap-word bitmap word) (logior old pattern))))
    (spend-scanned-words scanned)
    new))

(defun cube-words-have-unmarked-p (bitmap cube layout)
  "CUBE-HAS-UNMARKED-P on the bits of BITMAP, word by word."
  (declare (type bitmap bitmap) (optimize speed))
  (let ((pattern (cube-word-pattern cube layout))
        (scanned 0))
    (declare (type (unsigned-byte 64) pattern) (type fixnum scanned))
    (do-cube-indices (word cube layout :from (layout-word-prefix layout) :unit 64)
      (incf scanned)
      (unless (zerop (logandc1 (bitmap-word bitmap word) pattern))
        (return-from cube-words-have-unmarked-p (spend-scanned-words scanned t))))
    (spend-scanned-words scanned nil)))

;;; Layouts with groups: in each of the cube's groups, only the words that are
;;; not yet full are read.

(defun pattern-positions (pattern)
  "The positions of the bits set in the 64-bit PATTERN, ascending, as a fixnum vector."
  (declare (type (unsigned-byte 64) pattern) (optimize speed))
  (let ((positions (make-array (logcount pattern) :element-type 'fixnum)))
    (loop for j of-type fixnum from 0
          until (zerop pattern)
          do (let ((low (logand pattern (ldb (byte 64 0) (- pattern)))))
               (setf (aref positions j) (1- (integer-length low))
                     pattern (logxor pattern low))))
    positions))

(defmacro do-open-words ((word group-bit full group positions) &body body)
  "Run BODY with WORD bound to each word of GROUP at one of POSITIONS (a fixnum
vector) whose bit in FULL is clear, and GROUP-BIT to that bit's mask in the
group's word of FULL."
  (with-gensyms (full-word position)
    `(let ((,full-word (bitmap-word ,full ,group)))
       (unless (= ,full-word +full-word+)
         (loop for ,position of-type (integer 0 63) across ,positions
               unless (logbitp ,position ,full-word)
                 do (let ((,word (+ (the fixnum (* ,group 64)) ,position))
                          (,group-bit (ash 1 ,position)))
                      (declare (type fixnum ,word) (type (unsigned-byte 64) ,group-bit)
                               (ignorable ,group-bit))
                      ,@body))))))

(defun mark-cube-groups (solved-states cube layout)
  "MARK-CUBE for a layout with groups, keeping the full-word bits up to date."
  (declare (optimize speed))
  (let ((bits (solved-states-bits solved-states))
        (full (solved-states-full-words solved-states))
        (pattern (cube-word-pattern cube layout))
        (positions (pattern-positions (cube-group-pattern cube layout)))
        (new 0) (scanned 0))
    (declare (type bitmap bits full) (type (unsigned-byte 64) pattern)
             (type (simple-array fixnum (*)) positions) (type fixnum new scanned))
    (do-cube-indices (group cube layout :from (+ (layout-word-prefix layout) (layout-group-prefix layout))
                                        :unit 4096)
      ;; a full group is one read; another, a read per word of the pattern
      (incf scanned (if (= (bitmap-word full group) +full-word+) 1 (length positions)))
      (do-open-words (word group-bit full group positions)
        (let* ((old (bitmap-word bits word))
               (now (logior old pattern)))
          (declare (type (unsigned-byte 64) now))
          (unless (= old now)
            (incf new (logcount (logxor old now)))
            (setf (bitmap-word bits word) now)
            (when (= now +full-word+)
              (setf (bitmap-word full group)
                    (logior (bitmap-word full group) group-bit)))))))
    (spend-scanned-words scanned)
    new))

(defun cube-groups-have-unmarked-p (solved-states cube layout)
  "CUBE-HAS-UNMARKED-P for a layout with groups."
  (declare (optimize speed))
  (let ((bits (solved-states-bits solved-states))
        (full (solved-states-full-words solved-states))
        (pattern (cube-word-pattern cube layout))
        (positions (pattern-positions (cube-group-pattern cube layout)))
        (scanned 0))
    (declare (type bitmap bits full) (type (unsigned-byte 64) pattern)
             (type (simple-array fixnum (*)) positions) (type fixnum scanned))
    (do-cube-indices (group cube layout :from (+ (layout-word-prefix layout) (layout-group-prefix layout))
                                        :unit 4096)
      ;; a full group is one read; another, a read per word of the pattern
      (incf scanned (if (= (bitmap-word full group) +full-word+) 1 (length positions)))
      (do-open-words (word group-bit full group positions)
        (unless (zerop (logandc1 (bitmap-word bits word) pattern))
          (return-from cube-groups-have-unmarked-p (spend-scanned-words scanned t)))))
    (spend-scanned-words scanned nil)))
