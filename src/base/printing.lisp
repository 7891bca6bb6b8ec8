;;;; printing.lisp -- how Player writes names, expressions, times and trace lines.
;;;; One printer, independent of *PACKAGE* and float settings, so that the Lisp
;;;; and C++ backends (and every user's REPL) produce the same text.

(in-package #:player.base)

(defun lisp-text (object)
  "OBJECT written as lower-case s-expression text: symbols by name (keywords
with their colon), strings quoted, numbers through FORMAT-NUMBER."
  (with-output-to-string (out)
    (write-lisp-text object out)))

(defun write-lisp-text (object stream)
  "Write OBJECT to STREAM as LISP-TEXT does."
  (typecase object
    (null (write-string "nil" stream))
    (keyword (format stream ":~A" (escaped-text (string-downcase (symbol-name object)))))
    (symbol (write-string (escaped-text (string-downcase (symbol-name object))) stream))
    (string (write-string (escaped-text (prin1-to-string object)) stream))
    (real (write-string (format-number object) stream))
    (cons (write-list-text object stream))
    (t (let ((*print-case* :downcase) (*print-circle* t) (*print-length* 20) (*print-level* 4))
         (prin1 object stream)))))

(defun escaped-text (text)
  "TEXT with each control character (CONTROL-CHARACTER-P) written as \\xHH (or
\\uHHHH), so that text from a file or a user (a template, a typed request, a
name) cannot clear, retitle or forge lines on a terminal, a trace or a
recording; TEXT itself when it holds none."
  (if (notany #'control-character-p text)
      text
      (with-output-to-string (out)
        (loop for char across text
              do (cond ((not (control-character-p char)) (write-char char out))
                       ((< (char-code char) 256) (format out "\\x~2,'0X" (char-code char)))
                       (t (format out "\\u~4,'0X" (char-code char))))))))

(defvar *text-limit* nil
  "While BOUNDED-LISP-TEXT writes: the length past which it stops.")

(defun check-text-limit (stream)
  "Stop BOUNDED-LISP-TEXT once STREAM holds more than *TEXT-LIMIT* characters."
  (when (and *text-limit* (> (file-position stream) *text-limit*))
    (throw 'text-limit nil)))

(defun bounded-lisp-text (object &optional (limit 200))
  "LISP-TEXT of OBJECT cut to LIMIT characters (\"...\" at the end when cut).
Safe for messages about any input: circular or deeply nested structure stops
at the limit instead of looping or exhausting the stack."
  (let ((text (with-output-to-string (out)
                (let ((*text-limit* limit))
                  (catch 'text-limit (write-lisp-text object out))))))
    (truncate-text text limit)))

(defun write-list-text (list stream &optional (write-element #'write-lisp-text))
  "Write LIST, proper or dotted, in parentheses, each element (and a dotted
tail) by WRITE-ELEMENT, a function of the element and STREAM."
  (write-char #\( stream)
  (loop for (head . tail) on list
        do (check-text-limit stream)
           (funcall write-element head stream)
           (typecase tail
             (null)
             (cons (write-char #\Space stream))
             (t (write-string " . " stream)
                (funcall write-element tail stream))))
  (write-char #\) stream))

(defun format-number (number)
  "NUMBER as text: integers and integral floats as integers, other reals with up
to six decimals (rounded half up at the microsecond), trailing zeros dropped.
The C++ backend formats the same way, so traces compare as text.  NaN and the
infinities print as nan, inf and -inf; from 1e16 on, reals print in exponent
notation (1.0e16), as the C++ backend's shortest round-trip form does.
A ratio of whole microseconds (a time, see EXACT-TIMES.LISP) prints exactly."
  (cond ((integerp number) (format nil "~D" number))
        ;; A time handed to a presenter: exact seconds, printed exactly.
        ((micros-ratio-p number)
         (format-micros (* number +micros-per-second+)))
        ((and (floatp number) (sb-ext:float-nan-p number)) "nan")
        ((and (floatp number) (sb-ext:float-infinity-p number)) (if (plusp number) "inf" "-inf"))
        ((and (rationalp number) (> (abs number) most-positive-double-float))
         (if (plusp number) "inf" "-inf"))
        ((>= (abs number) 1d16)
         ;; Past 1e16 s a microsecond is below a double's resolution anyway.
         (let ((*read-default-float-format* 'double-float))
           (string-downcase (prin1-to-string (to-double number)))))
        (t (let* ((micros (floor (+ (* (float number 1d0) 1d6) 0.5d0)))
                  (sign (if (minusp micros) "-" ""))
                  (magnitude (abs micros)))
             (multiple-value-bind (whole fraction) (floor magnitude 1000000)
               (if (zerop fraction)
                   (format nil "~A~D" sign whole)
                   (format nil "~A~D.~A" sign whole
                           (string-right-trim "0" (format nil "~6,'0D" fraction)))))))))

;; Declared, so arithmetic on what it returns compiles to float instructions.
(declaim (ftype (function (t) (values double-float &optional)) to-double))
(defun to-double (number)
  "NUMBER as a double-float, taking single-floats at their printed value
(0.1f0 becomes 0.1d0, not 0.10000000149011612d0)."
  (etypecase number
    (double-float number)
    (single-float
     (let ((*read-default-float-format* 'single-float))
       (let ((text (prin1-to-string number)))
         (let ((*read-default-float-format* 'double-float))
           (coerce (read-from-string (substitute #\d #\f (string-left-trim " " text)))
                   'double-float)))))
    (real (coerce number 'double-float))))

(defun unquote (thing)
  "THING without a leading QUOTE, so the paper's quoted style also reads."
  (if (and (consp thing) (eq (first thing) 'quote) (consp (rest thing)) (null (cddr thing)))
      (second thing)
      thing))

(defun form-label (form)
  "How errors name FORM: its kind and name, e.g. \"op whistle\", or NIL."
  (when (and (consp form) (symbolp (first form)) (consp (rest form))
             (symbolp (unquote (second form))) (unquote (second form)))
    (format nil "~(~A~) ~A" (symbol-name (first form)) (lisp-text (unquote (second form))))))
