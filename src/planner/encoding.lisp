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
  (state-count 1 :type (integer 1)))

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
    (%make-layout :spec spec :variables vars :sizes sizes
                  :offsets (map 'simple-vector #'var-bit-offset vars)
                  :masks (map 'simple-vector #'var-field-mask vars)
                  :strides strides :state-count count)))

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
  (let* ((sizes (layout-sizes layout))
         (offsets (layout-offsets layout))
         (free (loop for k below (length sizes)
                     while (= (ldb (byte (svref sizes k) (svref offsets k)) cube)
                              (1- (ash 1 (svref sizes k))))
                     count t)))
    (values (coerce (loop for k from free below (length sizes)
                          collect (coerce (loop for i below (svref sizes k)
                                                when (logbitp (+ (svref offsets k) i) cube)
                                                  collect (* i (svref (layout-strides layout) k)))
                                          '(simple-array fixnum (*))))
                    'simple-vector)
            (if (< free (length sizes))
                (svref (layout-strides layout) free)
                (layout-state-count layout)))))

(defmacro do-cube-runs ((start end cube layout) &body body)
  "Run BODY with START and END bound to each run [START, END) of CUBE's dense states."
  (with-gensyms (choices run count counters base k digits)
    `(multiple-value-bind (,choices ,run) (cube-runs ,cube ,layout)
       (declare (type simple-vector ,choices) (type fixnum ,run))
       (let* ((,count (length ,choices))
              (,counters (make-array ,count :element-type 'fixnum :initial-element 0)))
         (declare (type fixnum ,count))
         (loop
           (let ((,base 0))
             (declare (type fixnum ,base))
             (loop for ,k of-type fixnum below ,count
                   do (incf ,base (aref (the (simple-array fixnum (*)) (svref ,choices ,k))
                                        (aref ,counters ,k))))
             (let ((,start ,base) (,end (+ ,base ,run)))
               (declare (type fixnum ,start ,end))
               ,@body))
           (unless (loop for ,k of-type fixnum below ,count
                         for ,digits = (length (the (simple-array fixnum (*)) (svref ,choices ,k)))
                         do (if (< (incf (aref ,counters ,k)) ,digits)
                                (return t)
                                (setf (aref ,counters ,k) 0)))
             (return)))))))

(defun map-cube-states (function cube layout)
  "Call FUNCTION on the dense number of every state in CUBE."
  (do-cube-runs (start end cube layout)
    (loop for dense from start below end do (funcall function dense))))

(defun mark-cube (bitmap cube layout)
  "Set CUBE's states in BITMAP; return how many were not set before."
  (declare (type simple-bit-vector bitmap)
           (optimize speed))
  (let ((new 0))
    (declare (type fixnum new))
    (do-cube-runs (start end cube layout)
      (if (< (- end start) 4096)
          (loop for dense of-type fixnum from start below end
                when (zerop (sbit bitmap dense))
                  do (setf (sbit bitmap dense) 1)
                     (incf new))
          (let ((unset (count 0 bitmap :start start :end end)))
            (declare (type fixnum unset))
            (when (plusp unset)
              (incf new unset)
              (fill bitmap 1 :start start :end end)))))
    new))

(defun cube-has-unmarked-p (bitmap cube layout)
  "True when some state of CUBE is not set in BITMAP."
  (declare (type simple-bit-vector bitmap)
           (optimize speed))
  (do-cube-runs (start end cube layout)
    (when (position 0 bitmap :start start :end end)
      (return-from cube-has-unmarked-p t)))
  nil)
