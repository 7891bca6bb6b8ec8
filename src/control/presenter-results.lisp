;;;; presenter-results.lisp -- what a presenter answers a controller is
;;;; checked where the controller takes it (the presenter protocol is
;;;; controller/presenter.lisp; the closures, compiled before it, check too).

(in-package #:player.control)

;;; What a presenter answers is checked where a controller takes it: a
;;; duration or a time into an op must be a finite number of seconds, 0 or
;;; more.  A NaN would trap in the middle of the timeline's work, an infinity
;;; or a negative duration would put the clock where no event can follow.

(define-condition presenter-result-error (player-error)
  ((presenter :initarg :presenter :reader presenter-result-error-presenter)
   (function :initarg :function :reader presenter-result-error-function)
   (op :initarg :op :reader presenter-result-error-op)
   (value :initarg :value :reader presenter-result-error-value))
  (:report (lambda (condition stream)
             (format stream "presenter ~A answered ~A of op ~A with ~A: it must be a finite number of seconds, 0 or more"
                     (type-of (presenter-result-error-presenter condition))
                     (lisp-text (presenter-result-error-function condition))
                     (lisp-text (op-name (presenter-result-error-op condition)))
                     (bounded-lisp-text (presenter-result-error-value condition) 80))))
  (:documentation "A presenter's method answered a duration (PRESENT-OP,
PLANNED-OP-DURATION) or a time into an op (CRITICAL-TIME) that is not a finite
number of seconds, 0 or more.  Signalled before the controller uses it."))

(defun presenter-seconds-p (value)
  "Is VALUE a finite real, 0 or more, as a double-float too (what a presenter
may answer for a duration)?"
  (and (finite-real-p value) (>= value 0)))

;; Out of line, and typed as TO-DOUBLE, which it replaces where a presenter
;; answers: its callers add the double it returns unboxed, so an op's end is
;; not boxed on the path that never calls it (a silent presenter's).
(declaim (ftype (function (t t t t) (values double-float &optional)) presenter-seconds))
(defun presenter-seconds (value presenter function op)
  "VALUE, what PRESENTER's FUNCTION answered about OP, as a double-float when
it is a finite number of seconds, 0 or more; else a PRESENTER-RESULT-ERROR."
  (if (and (typep value 'double-float)
           ;; Finite (its exponent bits not all ones) before it is compared:
           ;; comparing a NaN traps.
           (< (ldb (byte 11 20) (sb-kernel:double-float-high-bits value)) 2047)
           (>= value 0d0))
      value
      (presenter-seconds-slowly value presenter function op)))

(defun presenter-seconds-slowly (value presenter function op)
  "PRESENTER-SECONDS of any VALUE: other reals converted, the rest an error."
  (if (presenter-seconds-p value)
      (to-double value)
      (error 'presenter-result-error :presenter presenter :function function :op op :value value)))
