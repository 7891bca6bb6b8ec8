;;;; structure.lisp -- the limits every form read as data must respect before
;;;; anything walks it: no circular structure (#1=(a . #1#)) and no nesting
;;;; deeper than *MAX-FORM-DEPTH*, so parsing and error messages can never
;;;; loop or exhaust the stack; and numbers that are real, finite and in range.

(in-package #:player.base)

(defparameter *max-form-depth* 1000
  "The deepest a spec or script-library form may nest.")

(defparameter *max-seconds* 1d15
  "The largest duration or time, in seconds, a spec may give (about 31 million years).")

(defparameter *shortest-period* 1d-3
  "The shortest period a clock a file gives may have (a timer's :after): a
faster clock sends more events than anything can play or record.")

(defparameter *int64-range* (list (- (expt 2 63)) (1- (expt 2 63)))
  "The smallest and largest integer a spec may give: the C++ backend's long long.")

(defparameter *max-form-size* 2000000
  "The most conses and vector elements a form read as data may hold, counting
a shared part (#1#) once per use: #1=(a a) #2=(#1# #1#) ... doubles the form at
every label, and whatever walks it would take that long.")

(defun check-form-structure (form &key (max-depth *max-form-depth*) (what "form"))
  "FORM, once it is known to be a tree (a cons or vector may be shared, but none
contains itself) no deeper than MAX-DEPTH and no larger than *MAX-FORM-SIZE*
(a shared part counted once per use), whose symbols (names) hold no control
character (a line break in a name would forge trace lines); else a
SPEC-SYNTAX-ERROR naming WHAT.
Walks each list's spine iteratively, so a long list costs no stack; vectors
(other than strings) are walked like lists."
  (let ((open (make-hash-table :test 'eq)) (size 0))
    (labels ((count-one ()
               (when (> (incf size) *max-form-size*)
                 (spec-fail 'spec-syntax-error nil "the ~A has more than ~:D elements (a shared #N# part counts at every use)"
                            what *max-form-size*)))
             (walk-vector (x depth)
               (when (> depth max-depth)
                 (spec-fail 'spec-syntax-error nil "the ~A is nested more than ~D levels deep"
                            what max-depth))
               (when (gethash x open)
                 (spec-fail 'spec-syntax-error nil "the ~A contains itself (circular structure)" what))
               (setf (gethash x open) t)
               (loop for element across x do (count-one) (walk element (1+ depth)))
               (remhash x open))
             (walk (x depth)
               (when (and (symbolp x) (find-if #'control-character-p (symbol-name x)))
                 (spec-fail 'spec-syntax-error nil "the name ~A in the ~A holds a control character, which could forge output"
                            (lisp-text x) what))
               (when (and (vectorp x) (not (stringp x)) (not (bit-vector-p x)))
                 (walk-vector x depth))
               (when (consp x)
                 (when (> depth max-depth)
                   (spec-fail 'spec-syntax-error nil "the ~A is nested more than ~D levels deep"
                              what max-depth))
                 (let ((spine '()))
                   (loop for tail = x then (cdr tail)
                         while (consp tail)
                         do (when (gethash tail open)
                              (spec-fail 'spec-syntax-error nil
                                         "the ~A contains itself (circular structure such as #1=(a . #1#))"
                                         what))
                            (count-one)
                            (setf (gethash tail open) t)
                            (push tail spine)
                            (walk (car tail) (1+ depth)))
                   (dolist (cons spine) (remhash cons open))))))
      (walk form 0)
      form)))

;;;# Numbers

(defun finite-real-p (x)
  "Is X a real that is finite as a double-float (not NaN, not an infinity, not
beyond the largest double)?"
  (typecase x
    (float (and (not (sb-ext:float-nan-p x)) (not (sb-ext:float-infinity-p x))
                (<= (abs x) most-positive-double-float)))
    (rational (<= (abs x) most-positive-double-float))
    (t nil)))

(defun int64-p (x)
  "Is X an integer the C++ backend's long long holds?"
  (and (integerp x) (<= (first *int64-range*) x (second *int64-range*))))

(defun spec-seconds (x form what &key (minimum (- *max-seconds*)))
  "X, a number of seconds from MINIMUM to *MAX-SECONDS*, as a double-float;
else a TYPE-ERROR-IN-SPEC about FORM naming WHAT (e.g. \":duration\")."
  (unless (and (finite-real-p x) (<= minimum x *max-seconds*))
    (spec-fail 'type-error-in-spec form "~A must be a number of seconds from ~A to ~A, not ~A"
               what (format-number minimum) (format-number *max-seconds*) (bounded-lisp-text x 40)))
  (to-double x))

(defun check-spec-number (x form what &key integer)
  "X, when it is a finite real (with INTEGER, an integer from -2^63 to 2^63-1;
an integer must fit that range in any case); else a TYPE-ERROR-IN-SPEC about
FORM naming WHAT."
  (unless (if integer
              (int64-p x)
              (and (finite-real-p x) (or (not (integerp x)) (int64-p x))))
    (spec-fail 'type-error-in-spec form "~A must be ~:[a finite number~;an integer from -2^63 to 2^63-1~], not ~A"
               what integer (bounded-lisp-text x 40)))
  x)

(defparameter *library-number-range* '(1d-9 1d9)
  "The smallest and largest magnitude (besides 0) of a number in a script
library, pose library or skeleton: seconds, metres, degrees and colours all
lie well inside it, and nothing computed from them can overflow.")

(defun out-of-range-number (form)
  "The first real in FORM (a tree, see CHECK-FORM-STRUCTURE) that is not 0 and
whose magnitude lies outside *LIBRARY-NUMBER-RANGE*, or is not finite; NIL
when there is none."
  (destructuring-bind (low high) *library-number-range*
    (labels ((bad-p (x)
               (and (realp x)
                    (or (not (finite-real-p x))
                        (and (/= x 0) (not (<= low (abs x) high))))))
             (walk (x)
               (cond ((bad-p x) (return-from out-of-range-number x))
                     ((consp x) (loop for tail = x then (cdr tail)
                                      while (consp tail)
                                      do (walk (car tail))
                                      finally (walk tail)))
                     ((and (vectorp x) (not (stringp x))) (map nil #'walk x)))))
      (walk form)
      nil)))
