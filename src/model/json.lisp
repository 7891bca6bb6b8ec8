;;;; json.lisp -- a small JSON writer (RFC 8259), enough for a glTF file's
;;;; document: Lisp data in, compact JSON text out.  Only writing: Player never
;;;; reads JSON, so no parser lives here.
;;;;
;;;; The data, and the JSON each is:
;;;;   (:object (KEY . VALUE) ...)   an object, its members in the list's order
;;;;                                 (JSON-OBJECT builds one, leaving out
;;;;                                 members whose value is NIL);
;;;;   a list or a non-string vector an array (so NIL is [], but JSON-OBJECT
;;;;                                 drops a member that is NIL: glTF forbids
;;;;                                 empty arrays);
;;;;   a string                      a string, escaped per RFC 8259 section 7;
;;;;   an integer                    a number;
;;;;   a single- or double-float     a number, the shortest text that reads
;;;;                                 back as the same float; NaN and the
;;;;                                 infinities have no JSON and are refused;
;;;;   :true :false :null            themselves.
;;;; Anything else, and a float that is not finite, is a MODEL-WRITE-ERROR
;;;; (WRITE-FAIL): this writer serves the model writer, whose errors name the
;;;; file being written.

(in-package #:player.model)

(defun json-object (&rest keys-and-values)
  "A JSON object of KEYS-AND-VALUES (alternating strings and values), in
order, leaving out each member whose value is NIL."
  (cons :object
        (loop for (key value) on keys-and-values by #'cddr
              when value collect (cons key value))))

(defun json-object-p (value)
  "Is VALUE a JSON object, a list headed by :OBJECT?"
  (and (consp value) (eq :object (car value))))

(defun write-json-string (string stream)
  "Write STRING to STREAM as a JSON string: quote and backslash escaped,
control characters as escapes, and UTF-16 surrogate code points (which no
UTF-8 text may hold) as \\u escapes; everything else as it is."
  (write-char #\" stream)
  (loop for char across string
        for code = (char-code char)
        do (case char
             (#\" (write-string "\\\"" stream))
             (#\\ (write-string "\\\\" stream))
             (#\Newline (write-string "\\n" stream))
             (#\Return (write-string "\\r" stream))
             (#\Tab (write-string "\\t" stream))
             (t (if (or (< code #x20) (<= #xD800 code #xDFFF))
                    (format stream "\\u~4,'0X" code)
                    (write-char char stream)))))
  (write-char #\" stream))

(defun write-json-float (x stream)
  "Write the float X to STREAM as a JSON number: SBCL's shortest text that
reads back as X, which with *READ-DEFAULT-FLOAT-FORMAT* bound to X's own type
has no exponent marker but e (1.0e-7, never 1.0d-7).  A MODEL-WRITE-ERROR
when X is NaN or infinite."
  (unless (etypecase x
            (single-float (finite-single-p x))
            (double-float (finite-double-p x)))
    (write-fail "it holds a number that is not finite (NaN or infinite), which JSON cannot write"))
  (let ((*read-default-float-format* (type-of x)))
    (write x :stream stream :readably nil :pretty nil :base 10 :radix nil)))

(defun write-json (value stream)
  "Write VALUE (see the head of json.lisp for what each Lisp value is) to
STREAM as compact JSON.  A MODEL-WRITE-ERROR for a float that is not finite
or a value JSON has no text for."
  (cond ((json-object-p value)
         (write-char #\{ stream)
         (loop for (member . more) on (cdr value)
               do (write-json-string (car member) stream)
                  (write-char #\: stream)
                  (write-json (cdr member) stream)
                  (when more (write-char #\, stream)))
         (write-char #\} stream))
        ((stringp value) (write-json-string value stream))
        ((eq value :true) (write-string "true" stream))
        ((eq value :false) (write-string "false" stream))
        ((eq value :null) (write-string "null" stream))
        ((integerp value) (write value :stream stream :base 10 :radix nil))
        ((floatp value) (write-json-float value stream))
        ((or (listp value) (vectorp value))
         (write-char #\[ stream)
         (let ((first t))
           (map nil (lambda (element)
                      (unless first (write-char #\, stream))
                      (setf first nil)
                      (write-json element stream))
                value))
         (write-char #\] stream))
        (t (write-fail "its document holds ~S, which has no JSON" value))))

(defun json-text (value)
  "VALUE written as compact JSON, a string (see WRITE-JSON)."
  (with-output-to-string (stream)
    (write-json value stream)))
