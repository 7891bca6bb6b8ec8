;;;; exact-times.lisp -- a timed controller's times as integer microseconds:
;;;; converting seconds (numbers and decimal text) to them by one rule, and
;;;; back to seconds and to text.  The C++ backend's Time (timed-types.hpp)
;;;; follows the same rules, so both print the same trace for any time up to
;;;; *MAX-SECONDS* (1e15 s = 1e21 us: past a fixnum's 4.6e12 s, bignums).

(in-package #:player.base)

(deftype micros ()
  "A time or a duration in whole microseconds."
  'integer)

(defconstant +micros-per-second+ 1000000)

(defconstant +never-micros+ (* 4 (expt 10 21))
  "Later than any time a timeline holds (1e15 s with any sum of durations):
what FINISH-EVENTS advances towards.")

(defun exact-seconds->micros (seconds)
  "SECONDS (a finite real) as the nearest whole microsecond of its exact value,
ties to even."
  (round (* (rational seconds) +micros-per-second+)))

(declaim (ftype (function (t) (values integer &optional)) seconds->micros)
         ;; Inline: a double handed to a full call is boxed, once per op planned.
         (inline seconds->micros))
(defun seconds->micros (seconds)
  "SECONDS (a finite real; a double is taken at its exact binary value) as the
nearest whole microsecond, ties to even.  The usual double (under 1e9 s, a
product with 10^6 well away from half a microsecond) costs a multiplication:
its exact product then lies within 1/16 of the double one, so both round alike."
  (if (typep seconds 'double-float)
      (let ((product (* seconds 1d6)))
        (if (< (abs product) 1d15)
            ;; Typed bounds, so rounding and subtracting compile to instructions.
            (let* ((bounded (the (double-float (-1d15) (1d15)) product))
                   ;; Half away from zero: a tie is left to the exact path anyway.
                   (nearest (truncate (+ bounded (if (minusp bounded) -0.5d0 0.5d0)))))
              (if (< (abs (- bounded (float nearest 1d0))) 0.25d0)
                  nearest
                  (exact-seconds->micros seconds)))
            (exact-seconds->micros seconds)))
      (exact-seconds->micros seconds)))

(defun seconds-value->micros (seconds)
  "SECONDS, a finite real an API was handed, in whole microseconds: a rational
exactly, a float as the double TO-DOUBLE makes of it (SECONDS->MICROS)."
  (seconds->micros (if (rationalp seconds) seconds (to-double seconds))))

;; Fixnum fast paths: a time past 4.6e12 s (a bignum) takes generic arithmetic.
(declaim (inline micros< micros<= micros+))
(defun micros+ (a b)
  "Time A plus duration B (whole microseconds)."
  (if (and (typep a 'fixnum) (typep b 'fixnum)) (+ a b) (+ a b)))

(defun micros< (a b)
  "Is time A (whole microseconds) before time B?"
  (if (and (typep a 'fixnum) (typep b 'fixnum)) (< a b) (< a b)))

(defun micros<= (a b)
  "Is time A (whole microseconds) at or before time B?"
  (if (and (typep a 'fixnum) (typep b 'fixnum)) (<= a b) (<= a b)))

(defun micros->seconds (micros)
  "MICROS as exact seconds: an integer or a ratio (what presenters are handed)."
  (/ micros +micros-per-second+))

(declaim (ftype (function (integer) (values double-float &optional)) micros->double)
         (inline micros->double))
(defun micros->double (micros)
  "MICROS as seconds in a double: the whole seconds plus the microseconds over
10^6, each step an IEEE operation, as the C++ Time's to_double() does (so
both backends hand expressions the same double)."
  (multiple-value-bind (whole fraction) (floor micros +micros-per-second+)
    (if (typep whole 'fixnum)
        (+ (float (the fixnum whole) 1d0) (/ (float (the fixnum fraction) 1d0) 1d6))
        (+ (coerce whole 'double-float) (/ (coerce fraction 'double-float) 1d6)))))

(defun format-micros (micros)
  "MICROS as Player prints a time: the whole seconds, then up to six decimals
with trailing zeros dropped (1.5, 123456789012.000001, -0.25)."
  (multiple-value-bind (whole fraction) (truncate (abs micros) +micros-per-second+)
    (let ((sign (if (minusp micros) "-" "")))
      (if (zerop fraction)
          (format nil "~A~D" sign whole)
          (format nil "~A~D.~A" sign whole (string-right-trim "0" (format nil "~6,'0D" fraction)))))))

(defun micros-ratio-p (number)
  "Is NUMBER a rational holding a whole number of microseconds (a time handed
to a presenter), so that it prints exactly?"
  (and (rationalp number) (integerp (* number +micros-per-second+))))

(defparameter *most-decimal-digits* 100
  "Most digits PARSE-DECIMAL-SECONDS reads in a number: far more than a time to
the microsecond up to 1e15 s needs (22), few enough to read at once.")

(defun parse-decimal-seconds (text)
  "TEXT, an exact decimal -- optional sign, digits with an optional fraction,
an optional exponent (1e15, 1.5E-3, .5, 2.) -- as an exact rational; NIL when
it is not one.  Never goes through a double, so 123456789012.000001 stays
exact.  An exponent beyond +-400 gives NIL (no time is that far), and so do
more than *MOST-DECIMAL-DIGITS* digits: each digit multiplies a growing
integer, so a command line of 100,000 digits took seconds."
  (let* ((length (length text)) (at 0) (sign 1) (digits 0) (count 0) (scale 0) (exponent 0))
    (flet ((peek () (and (< at length) (char text at))))
      (case (peek) (#\- (setf sign -1) (incf at)) (#\+ (incf at)))
      (loop for char = (peek) while (and char (digit-char-p char) (<= count *most-decimal-digits*))
            do (setf digits (+ (* digits 10) (digit-char-p char))) (incf count) (incf at))
      (when (eql (peek) #\.)
        (incf at)
        (loop for char = (peek) while (and char (digit-char-p char) (<= count *most-decimal-digits*))
              do (setf digits (+ (* digits 10) (digit-char-p char))) (incf count) (incf scale) (incf at)))
      (when (or (zerop count) (> count *most-decimal-digits*)) (return-from parse-decimal-seconds nil))
      (when (member (peek) '(#\e #\E #\d #\D))
        (incf at)
        (let ((exponent-sign 1) (exponent-count 0))
          (case (peek) (#\- (setf exponent-sign -1) (incf at)) (#\+ (incf at)))
          (loop for char = (peek) while (and char (digit-char-p char))
                do (setf exponent (min 1000 (+ (* exponent 10) (digit-char-p char))))
                   (incf exponent-count) (incf at))
          (when (zerop exponent-count) (return-from parse-decimal-seconds nil))
          (setf exponent (* exponent-sign exponent))))
      (when (or (< at length) (> (abs exponent) 400))
        (return-from parse-decimal-seconds nil))
      (* sign digits (expt 10 (- exponent scale))))))
