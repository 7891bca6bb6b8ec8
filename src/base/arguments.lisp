;;;; arguments.lisp -- checking the arguments of the Lisp API.  Every exported
;;;; function checks its arguments on entry, one line each, before it changes
;;;; anything; a bad one is an ARGUMENT-ERROR naming the function, the argument
;;;; and the value (printed safely, however circular or huge), never a raw
;;;; TYPE-ERROR, CASE-FAILURE or FLOATING-POINT-* from deep inside.

(in-package #:player.base)

(define-condition argument-error (player-error)
  ((function-name :initarg :function :reader argument-error-function
                  :documentation "The API function that was called, a symbol.")
   (argument :initarg :argument :reader argument-error-argument
             :documentation "The argument: a symbol for a positional one, a keyword for a keyword one.")
   (value :initarg :value :reader argument-error-value
          :documentation "The value it was given.")
   (expected :initarg :expected :initform nil :reader argument-error-expected
             :documentation "What it must be, as a phrase (\"a finite number of seconds\").")
   ;; The whole sentence, for the readers of the older condition classes a
   ;; subclass may also inherit from (ANIM-ERROR-MESSAGE, SPEC-ERROR-MESSAGE):
   ;; they share this slot by name.
   (message :initarg :message :initform nil))
  (:report report-argument-error)
  (:documentation "An API function was called with an argument of the wrong type
or out of range.  Nothing was changed.  A subclass may also inherit from an
older, more specific condition class (ANIM-CONTROL-ERROR, say): put
ARGUMENT-ERROR first among its superclasses, so the report is this one."))

(defun argument-message (function argument value expected)
  "The sentence \"FUNCTION: ARGUMENT must be EXPECTED, not VALUE\"."
  (format nil "~A: ~A must be ~A, not ~A" (lisp-text function) (lisp-text argument)
          expected (argument-value-text value)))

(defun report-argument-error (condition stream)
  "FUNCTION: ARGUMENT must be EXPECTED, not VALUE."
  (write-string (argument-message (argument-error-function condition)
                                  (argument-error-argument condition)
                                  (argument-error-value condition)
                                  (argument-error-expected condition))
                stream))

(defun argument-value-text (value)
  "VALUE as a message shows it: BOUNDED-LISP-TEXT, with the float traps masked
so that a NaN prints as nan instead of trapping when compared.  A number too
small for the microseconds LISP-TEXT keeps is written in full: an error about
1d-9 must not say 0."
  (sb-int:with-float-traps-masked (:invalid :overflow :inexact :divide-by-zero)
    (if (and (realp value)
             (not (and (floatp value) (or (sb-ext:float-nan-p value) (sb-ext:float-infinity-p value))))
             (not (zerop value)) (< (abs value) 1d-6))
        (let ((*read-default-float-format* 'double-float))
          (string-downcase (prin1-to-string (float value 1d0))))
        (bounded-lisp-text value 80))))

(declaim (notinline argument-fail))
(defun argument-fail (function argument value expected &optional (class 'argument-error))
  "Signal an ARGUMENT-ERROR (or its subclass CLASS): FUNCTION's ARGUMENT must be
EXPECTED (a phrase), not VALUE."
  (error class :function function :argument argument :value value :expected expected
               :message (argument-message function argument value expected)))

(defmacro check-argument (function argument value predicate expected &optional (class ''argument-error))
  "VALUE when (FUNCALL PREDICATE VALUE) is true; else an ARGUMENT-ERROR (or
CLASS): FUNCTION's ARGUMENT must be EXPECTED.  EXPECTED is evaluated only on
failure, so a FORMAT there costs nothing on the good path.
  (check-argument 'send-event 'controller controller #'controller-p \"a controller\")"
  (with-gensyms (v)
    `(let ((,v ,value))
       (if (funcall ,predicate ,v)
           ,v
           (argument-fail ,function ,argument ,v ,expected ,class)))))

;;;# Numbers

(defun finite-number-p (x)
  "Is X a finite real (see FINITE-REAL-P)?  Safe with float traps enabled: a
NaN is recognised without comparing it, which would trap."
  (and (realp x)
       (not (and (floatp x) (sb-ext:float-nan-p x)))
       (finite-real-p x)))

(declaim (inline seconds-p))
(defun seconds-p (x)
  "Is X a finite real within +-*MAX-SECONDS*?  Conses nothing for a double-float."
  (let ((limit (float *max-seconds* 1d0)))
    (typecase x
      (double-float (and (not (sb-ext:float-nan-p x)) (<= (- limit) x limit)))
      (single-float (and (not (sb-ext:float-nan-p x)) (<= (- limit) (float x 1d0) limit)))
      (rational (<= (- limit) x limit))
      (t nil))))

(defun number-text (x)
  "X for a message: a power of ten from 1e6 on as 1e6, 1e15...; others as FORMAT-NUMBER."
  (let ((exponent (and (realp x) (/= x 0) (round (log (abs (float x 1d0)) 10)))))
    (if (and exponent (>= exponent 6) (= (abs x) (expt 10 exponent)))
        (format nil "~:[~;-~]1e~D" (minusp x) exponent)
        (format-number x))))

(defun seconds-phrase (&optional minimum maximum)
  "\"a finite number of seconds from MINIMUM to MAXIMUM\" (by default +-*MAX-SECONDS*)."
  (format nil "a finite number of seconds from ~A to ~A"
          (number-text (or minimum (- *max-seconds*))) (number-text (or maximum *max-seconds*))))

(declaim (inline plain-seconds-p))
(defun plain-seconds-p (x)
  "Is X a double-float that CHECK-SECONDS takes as it is, without asking more:
finite, below 2^49 in magnitude, and *MAX-SECONDS* at least that?"
  ;; Inline where a double is checked on every call (a timed send): a full
  ;; call of CHECK-SECONDS, with keyword arguments and a generic compare of
  ;; *MAX-SECONDS*, costs more than the check.  The exponent's bits exclude
  ;; NaNs and infinities without comparing them, which would trap.
  (and (typep x 'double-float)
       (< (ldb (byte 11 20) (sb-kernel:double-float-high-bits x)) (+ 1023 49))
       (let ((limit *max-seconds*))
         (and (typep limit 'double-float) (>= limit #.(expt 2d0 49))))))

(defun check-seconds (function argument value &key minimum maximum (class 'argument-error))
  "VALUE, a finite number of seconds from MINIMUM to MAXIMUM (by default
+-*MAX-SECONDS*), as a double-float (see TO-DOUBLE); else an ARGUMENT-ERROR (or
CLASS).  Conses nothing for a double-float in range."
  ;; The usual case first: a plain double and no bounds of the caller's.
  (when (and (null minimum) (null maximum) (plain-seconds-p value))
    (return-from check-seconds value))
  (if (and (seconds-p value)
           (or (null minimum) (>= value minimum))
           (or (null maximum) (<= value maximum)))
      (to-double value)
      (argument-fail function argument value (seconds-phrase minimum maximum) class)))

(defun check-real (function argument value &key minimum above maximum integer what (class 'argument-error))
  "VALUE when it is a finite real (with INTEGER, an integer), at least MINIMUM,
greater than ABOVE and at most MAXIMUM where those are given; else an
ARGUMENT-ERROR saying so (or saying WHAT, a phrase, when given)."
  (unless (and (if integer (integerp value) (finite-number-p value))
               (or (null minimum) (>= value minimum))
               (or (null above) (> value above))
               (or (null maximum) (<= value maximum)))
    (argument-fail function argument value
                   (or what
                       (format nil "~:[a finite real~;an integer~]~A" integer
                               (cond ((and minimum maximum)
                                      (format nil " from ~A to ~A" (number-text minimum) (number-text maximum)))
                                     ((and above maximum)
                                      (format nil " above ~A and at most ~A" (number-text above) (number-text maximum)))
                                     (above (format nil " above ~A" (number-text above)))
                                     (minimum (format nil " of at least ~A" (number-text minimum)))
                                     (maximum (format nil " of at most ~A" (number-text maximum)))
                                     (t ""))))
                   class))
  value)

;;;# Lists and forms

(defun bounded-form-p (x &optional (max-depth *max-form-depth*))
  "Is X a tree (no cons contains itself) nested at most MAX-DEPTH deep?  Safe
on any input; see CHECK-FORM-STRUCTURE."
  (or (atom x)
      (handler-case (progn (check-form-structure x :max-depth max-depth) t)
        (spec-syntax-error () nil))))

(defun finite-form-p (x)
  "Is X, a bounded tree (see BOUNDED-FORM-P), free of NaNs and infinities?"
  (labels ((walk (x)
             (typecase x
               (float (finite-number-p x))
               (cons (loop for tail = x then (cdr tail)
                           while (consp tail)
                           always (walk (car tail))
                           finally (return (walk tail))))
               (t t))))
    (walk x)))

(defun report-spec-error-safely (condition stream)
  "REPORT-SPEC-ERROR with the float traps masked, so a NaN in the offending form
prints as nan instead of trapping when compared: the :REPORT of the spec errors
the runtime signals about forms (motor calls, skeletons, poses, scripts)."
  (sb-int:with-float-traps-masked (:invalid :overflow :inexact :divide-by-zero)
    (report-spec-error condition stream)))

(defun proper-form-list-p (x)
  "Is X a proper list, not circular, whose elements are bounded forms?"
  (and (alexandria:proper-list-p x) (bounded-form-p x)))

(defun name-designator-p (x)
  "Is X a name: a symbol or a string?"
  (or (symbolp x) (stringp x)))

(defun string-designator-p (x)
  "Is X a string designator: a symbol, a string or a character?"
  (or (symbolp x) (stringp x) (characterp x)))

(defun pathname-designator-p (x)
  "Is X a string or a pathname that names one file: not empty, not wild?"
  (and (or (and (stringp x) (plusp (length x))) (pathnamep x))
       (handler-case (not (wild-pathname-p (pathname x)))
         (error () nil))))

(defparameter *path-phrase* "a file's path (a string or pathname, not wild)"
  "How argument errors describe a file's path.")

(defun output-stream-designator-p (x)
  "Is X NIL, T (standard output) or an output stream?"
  (or (null x) (eq x t) (and (streamp x) (output-stream-p x))))

