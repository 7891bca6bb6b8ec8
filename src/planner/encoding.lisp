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

(defun cube-choices (cube layout)
  "Per variable, the dense-index contributions of the values CUBE allows."
  (map 'simple-vector
       (lambda (size offset stride)
         (coerce (loop for i below size
                       when (logbitp (+ offset i) cube) collect (* i stride))
                 'simple-vector))
       (layout-sizes layout) (layout-offsets layout) (layout-strides layout)))

(defun map-cube-states (function cube layout)
  "Call FUNCTION on the dense number of every state in CUBE."
  (let ((choices (cube-choices cube layout)))
    (labels ((walk (k base)
               (if (minusp k)
                   (funcall function base)
                   (loop for c across (the simple-vector (aref choices k))
                         do (walk (1- k) (+ base c))))))
      (walk (1- (length choices)) 0))))

(defun mark-cube (bitmap cube layout)
  "Set CUBE's states in BITMAP; return how many were not set before."
  (declare (type simple-bit-vector bitmap))
  (let ((new 0))
    (declare (type fixnum new))
    (map-cube-states (lambda (dense)
                       (when (zerop (sbit bitmap dense))
                         (setf (sbit bitmap dense) 1)
                         (incf new)))
                     cube layout)
    new))

(defun cube-has-unmarked-p (bitmap cube layout)
  "True when some state of CUBE is not set in BITMAP."
  (declare (type simple-bit-vector bitmap))
  (map-cube-states (lambda (dense)
                     (when (zerop (sbit bitmap dense))
                       (return-from cube-has-unmarked-p t)))
                   cube layout)
  nil)
