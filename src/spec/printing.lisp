;;;; printing.lisp -- how Player writes names, expressions, times and trace lines.
;;;; One printer, independent of *PACKAGE* and float settings, so that the Lisp
;;;; and C++ backends (and every user's REPL) produce the same text.

(in-package #:player)

(defun lisp-text (object)
  "OBJECT written as lower-case s-expression text: symbols by name (keywords
with their colon), strings quoted, numbers through FORMAT-NUMBER."
  (with-output-to-string (out)
    (write-lisp-text object out)))

(defun write-lisp-text (object stream)
  "Write OBJECT to STREAM as LISP-TEXT does."
  (typecase object
    (null (write-string "nil" stream))
    (keyword (format stream ":~(~A~)" (symbol-name object)))
    (symbol (format stream "~(~A~)" (symbol-name object)))
    (string (prin1 object stream))
    (real (write-string (format-number object) stream))
    (cons (write-list-text object stream))
    (t (let ((*print-case* :downcase)) (prin1 object stream)))))

(defun write-list-text (list stream &optional (write-element #'write-lisp-text))
  "Write LIST, proper or dotted, in parentheses, each element (and a dotted
tail) by WRITE-ELEMENT, a function of the element and STREAM."
  (write-char #\( stream)
  (loop for (head . tail) on list
        do (funcall write-element head stream)
           (typecase tail
             (null)
             (cons (write-char #\Space stream))
             (t (write-string " . " stream)
                (funcall write-element tail stream))))
  (write-char #\) stream))

(defun format-number (number)
  "NUMBER as text: integers and integral floats as integers, other reals with up
to six decimals (rounded half up at the microsecond), trailing zeros dropped.
The C++ backend formats the same way, so traces compare as text."
  (if (integerp number)
      (format nil "~D" number)
      (let* ((micros (floor (+ (* (float number 1d0) 1d6) 0.5d0)))
             (sign (if (minusp micros) "-" ""))
             (magnitude (abs micros)))
        (multiple-value-bind (whole fraction) (floor magnitude 1000000)
          (if (zerop fraction)
              (format nil "~A~D" sign whole)
              (format nil "~A~D.~A" sign whole
                      (string-right-trim "0" (format nil "~6,'0D" fraction))))))))

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
