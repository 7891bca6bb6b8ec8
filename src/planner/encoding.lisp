;;;; encoding.lisp -- the plannable state space, for the planner's bookkeeping.
;;;; At run time a state is the one-hot integer of canonical.lisp. The planner
;;;; also numbers states densely (mixed radix over the domains) so SolvedStates
;;;; can be a bit vector with one bit per state.

(in-package #:player)

(defparameter *state-limit* (expt 2 26)
  "Most plannable states the planner accepts (the SolvedStates bitmap is this many bits).")

(defstruct (layout (:constructor %make-layout))
  "The plannable variables of a spec with their one-hot fields and dense strides."
  (spec nil)
  (variables #() :type simple-vector)
  (sizes #() :type simple-vector)
  (offsets #() :type simple-vector)
  (masks #() :type simple-vector)
  (strides #() :type simple-vector)
  (state-count 1 :type (integer 1))
  ;; leading variables spanning exactly one 64-bit word, or NIL (see MARK-CUBE-WORDS)
  (word-prefix nil)
  (word-masks #() :type simple-vector))

(defun make-layout (spec)
  "The layout of SPEC's plannable state; STATE-SPACE-TOO-LARGE past *STATE-LIMIT*."
  (let* ((vars (coerce (plannable-variables spec) 'simple-vector))
         (sizes (map 'simple-vector #'var-domain-size vars))
         (strides (make-array (length vars)))
         (count 1))
    (loop for i below (length vars)
          do (setf (aref strides i) count
                   count (* count (aref sizes i))))
    (when (> count *state-limit*)
      (error 'state-space-too-large :states count :limit *state-limit*))
    (let ((layout (%make-layout :spec spec :variables vars :sizes sizes
                                :offsets (map 'simple-vector #'var-bit-offset vars)
                                :masks (map 'simple-vector #'var-field-mask vars)
                                :strides strides :state-count count)))
      (when-let ((prefix (word-prefix layout)))
        (setf (layout-word-prefix layout) prefix
              (layout-word-masks layout) (word-value-masks layout prefix)))
      layout)))

(defun layout-cube-empty-p (cube layout)
  "True when CUBE allows no state."
  (loop for mask across (layout-masks layout)
          thereis (zerop (logand cube mask))))

(defun dense-to-state (dense layout)
  "The one-hot state numbered DENSE."
  (loop with state = 0
        for size across (layout-sizes layout)
        for offset across (layout-offsets layout)
        do (multiple-value-bind (rest index) (floor dense size)
             (setf state (logior state (ash 1 (+ offset index)))
                   dense rest))
        finally (return state)))

(defun state-to-dense (state layout)
  "The dense number of one-hot STATE."
  (loop for size across (layout-sizes layout)
        for offset across (layout-offsets layout)
        for stride across (layout-strides layout)
        ;; a one-hot field holding value I is 2^I
        sum (* stride (1- (integer-length (ldb (byte size offset) state))))))

;;; The planner spends most of its time on the states of cubes. The variables
;;; a cube leaves free at the low end of the numbering make its states come in
;;; contiguous runs, which bit-vector COUNT and FILL handle a word at a time;
;;; the other variables turn like an odometer over fixnums.

(defun cube-runs (cube layout)
  "(VALUES CHOICES RUN): CUBE's states are the runs [BASE, BASE+RUN) for every
BASE that sums one entry of each vector in CHOICES (the constrained and higher
variables' dense contributions)."
  (declare (optimize speed))
  (let* ((sizes (layout-sizes layout))
         (offsets (layout-offsets layout))
         (strides (layout-strides layout))
         (n (length sizes))
         (free (loop for k of-type fixnum below n
                     for size of-type fixnum = (svref sizes k)
                     while (= (ldb (byte size (the fixnum (svref offsets k))) cube)
                              (1- (ash 1 size)))
                     count t))
         (choices (make-array (- n free))))
    (declare (type simple-vector sizes offsets strides) (type fixnum n free))
    (loop for k of-type fixnum from free below n
          for size of-type fixnum = (svref sizes k)
          for offset of-type fixnum = (svref offsets k)
          for stride of-type fixnum = (svref strides k)
          for field = (ldb (byte size offset) cube)
          for values = (make-array (logcount field) :element-type 'fixnum)
          do (loop with j of-type fixnum = 0
                   for i of-type fixnum below size
                   when (logbitp i field)
                     do (setf (aref values j) (* i stride))
                        (incf j))
             (setf (svref choices (- k free)) values))
    (values choices
            (if (< free n) (svref strides free) (layout-state-count layout)))))

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

(defmacro do-cube-runs ((start end cube layout) &body body)
  "Run BODY with START and END bound to each run [START, END) of CUBE's dense states."
  (with-gensyms (choices run base)
    `(multiple-value-bind (,choices ,run) (cube-runs ,cube ,layout)
       (declare (type simple-vector ,choices) (type fixnum ,run))
       (do-odometer (,base ,choices)
         (let ((,start ,base) (,end (+ ,base ,run)))
           (declare (type fixnum ,start ,end))
           ,@body)))))

;;; When the first variables of the dense numbering span exactly 64 states
;;; (six booleans, say), every word of SolvedStates holds all their
;;; combinations for one assignment of the others: a cube then marks a fixed
;;; 64-bit pattern in each of the words its other variables select.

(defun word-prefix (layout)
  "How many leading variables of LAYOUT span exactly 64 states, or NIL."
  (loop with product = 1
        for size across (layout-sizes layout)
        for k from 1
        do (setf product (* product size))
        when (= product 64) return k
        while (< product 64)))

(defun word-value-masks (layout prefix)
  "For each of the first PREFIX variables, a vector giving for each value the
64-bit mask of the word positions where the variable has that value."
  (coerce (loop for k below prefix
                collect (coerce (loop for i below (svref (layout-sizes layout) k)
                                      collect (loop for low below 64
                                                    when (= i (mod (floor low (svref (layout-strides layout) k))
                                                                   (svref (layout-sizes layout) k)))
                                                      sum (ash 1 low)))
                                'simple-vector))
          'simple-vector))

(defun cube-word-pattern (cube layout prefix)
  "The 64-bit mask of the combinations of the first PREFIX variables CUBE allows."
  (let ((pattern (1- (ash 1 64)))
        (masks (layout-word-masks layout)))
    (dotimes (k prefix pattern)
      (let ((offset (svref (layout-offsets layout) k))
            (allowed 0))
        (loop for i below (svref (layout-sizes layout) k)
              when (logbitp (+ offset i) cube)
                do (setf allowed (logior allowed (svref (svref masks k) i))))
        (setf pattern (logand pattern allowed))))))

(defun cube-word-choices (cube layout prefix)
  "Per variable after the first PREFIX, the word-index contributions of the values CUBE allows."
  (coerce (loop for k from prefix below (length (layout-sizes layout))
                collect (coerce (loop for i below (svref (layout-sizes layout) k)
                                      when (logbitp (+ (svref (layout-offsets layout) k) i) cube)
                                        collect (/ (* i (svref (layout-strides layout) k)) 64))
                                '(simple-array fixnum (*))))
          'simple-vector))

(defun mark-cube-words (bitmap cube layout prefix)
  "MARK-CUBE for a layout whose first PREFIX variables span one word."
  (declare (type simple-bit-vector bitmap) (optimize speed))
  (let ((pattern (cube-word-pattern cube layout prefix))
        (choices (cube-word-choices cube layout prefix))
        (new 0))
    (declare (type (unsigned-byte 64) pattern) (type simple-vector choices) (type fixnum new))
    (do-odometer (word choices)
      (let ((old (sb-kernel:%vector-raw-bits bitmap word)))
        (declare (type (unsigned-byte 64) old))
        (incf new (logcount (logandc1 old pattern)))
        (setf (sb-kernel:%vector-raw-bits bitmap word) (logior old pattern))))
    new))

(defun map-cube-states (function cube layout)
  "Call FUNCTION on the dense number of every state in CUBE."
  (do-cube-runs (start end cube layout)
    (loop for dense from start below end do (funcall function dense))))

;;; SolvedStates is marked and tested a 64-bit word at a time: SBCL stores a
;;; bit vector's bit I as bit (MOD I 64) of word (FLOOR I 64).

(declaim (inline range-word-mask))
(defun range-word-mask (start end)
  "(VALUES WORD MASK COUNT): the word holding bit START, the mask of bits
[START, END) within it, and how many bits that is."
  (declare (type fixnum start end) (optimize speed))
  (multiple-value-bind (word bit) (floor start 64)
    (let ((count (min (- 64 bit) (- end start))))
      (values word
              (ldb (byte 64 0) (ash (ldb (byte count 0) (1- (ash 1 64))) bit))
              count))))

(defun mark-range (bitmap start end)
  "Set bits [START, END) of BITMAP; return how many of them were clear."
  (declare (type simple-bit-vector bitmap) (type fixnum start end) (optimize speed))
  (let ((new 0))
    (declare (type fixnum new))
    (loop while (< start end)
          do (multiple-value-bind (word mask count) (range-word-mask start end)
               (declare (type (unsigned-byte 64) mask) (type fixnum count))
               (let ((old (sb-kernel:%vector-raw-bits bitmap word)))
                 (declare (type (unsigned-byte 64) old))
                 (incf new (logcount (logandc1 old mask)))
                 (setf (sb-kernel:%vector-raw-bits bitmap word) (logior old mask))
                 (incf start count))))
    new))

(defun range-has-clear-p (bitmap start end)
  "True when some bit of [START, END) in BITMAP is clear."
  (declare (type simple-bit-vector bitmap) (type fixnum start end) (optimize speed))
  (loop while (< start end)
        do (multiple-value-bind (word mask count) (range-word-mask start end)
             (declare (type (unsigned-byte 64) mask) (type fixnum count))
             (unless (zerop (logandc1 (sb-kernel:%vector-raw-bits bitmap word) mask))
               (return-from range-has-clear-p t))
             (incf start count)))
  nil)

(defun mark-cube (bitmap cube layout)
  "Set CUBE's states in BITMAP; return how many were not set before."
  (declare (type simple-bit-vector bitmap) (optimize speed))
  (when-let ((prefix (layout-word-prefix layout)))
    (return-from mark-cube (mark-cube-words bitmap cube layout prefix)))
  (let ((new 0))
    (declare (type fixnum new))
    (do-cube-runs (start end cube layout)
      (if (< (- end start) 64)
          (loop for dense of-type fixnum from start below end
                when (zerop (sbit bitmap dense))
                  do (setf (sbit bitmap dense) 1)
                     (incf new))
          (incf new (mark-range bitmap start end))))
    new))

(defun cube-has-unmarked-p (bitmap cube layout)
  "True when some state of CUBE is not set in BITMAP."
  (declare (type simple-bit-vector bitmap) (optimize speed))
  (do-cube-runs (start end cube layout)
    (when (range-has-clear-p bitmap start end)
      (return-from cube-has-unmarked-p t)))
  nil)

(defun count-marked (bitmap)
  "How many bits of BITMAP are set, a word at a time."
  (declare (type simple-bit-vector bitmap) (optimize speed))
  (multiple-value-bind (words rest) (floor (length bitmap) 64)
    (+ (loop for i of-type fixnum below words
             sum (logcount (the (unsigned-byte 64) (sb-kernel:%vector-raw-bits bitmap i)))
               of-type fixnum)
       (loop for i of-type fixnum from (* words 64) below (+ (* words 64) rest)
             count (= 1 (sbit bitmap i))))))
