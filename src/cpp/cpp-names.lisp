;;;; cpp-names.lisp -- Lisp names as valid, collision-free C++ identifiers, and
;;;; user text (names, docstrings, forms) as safe C++ comments and string literals.

(in-package #:player.cpp)

(defparameter *c++-keywords*
  '("alignas" "alignof" "and" "and_eq" "asm" "auto" "bitand" "bitor" "bool" "break" "case"
    "catch" "char" "char16_t" "char32_t" "char8_t" "class" "compl" "concept" "const" "consteval"
    "constexpr" "constinit" "const_cast" "continue" "co_await" "co_return" "co_yield" "decltype"
    "default" "delete" "do" "double" "dynamic_cast" "else" "enum" "explicit" "export" "extern"
    "false" "float" "for" "friend" "goto" "if" "inline" "int" "long" "mutable" "namespace" "new"
    "noexcept" "not" "not_eq" "nullptr" "operator" "or" "or_eq" "private" "protected" "public"
    "register" "reinterpret_cast" "requires" "return" "short" "signed" "sizeof" "static"
    "static_assert" "static_cast" "struct" "switch" "template" "this" "thread_local" "throw"
    "true" "try" "typedef" "typeid" "typename" "union" "unsigned" "using" "virtual" "void"
    "volatile" "wchar_t" "while" "xor" "xor_eq" "main" "std" "NULL" "assert" "errno"
    ;; Lower-case macros of the standard headers and of GNU modes.
    "offsetof" "setjmp" "va_arg" "va_copy" "va_end" "va_start" "linux" "unix" "i386")
  "Words a generated identifier must not be (C++ keywords and troublesome names).")

(defun read-c-macros (path)
  "The macro names listed in PATH, one a line (; lines are comments), as an EQUAL hash table."
  (let ((table (make-hash-table :test 'equal)))
    (with-open-file (in path :external-format :utf-8)
      (loop for line = (read-line in nil) while line
            for name = (string-trim " " line)
            unless (or (string= name "") (char= (char name 0) #\;))
              do (setf (gethash name table) t)))
    table))

(defparameter *c-macros*
  (read-c-macros (merge-pathnames "c++-macros.txt" #.(or *compile-file-truename* *load-truename*)))
  "The macros (EOF, INT64_MAX, math_errhandling, alloca ...) the headers the
generated code includes define, read from c++-macros.txt (made by g++ -dM -E
on those headers): an identifier that is one would be replaced by the
preprocessor.")

(defun c-macro-p (text)
  "Is TEXT a macro of the headers the generated code includes?"
  (values (gethash text *c-macros*)))

(defun ascii-identifier-char-p (char)
  "True for the characters of a C++ identifier: ASCII letters, digits and underscore."
  (or (char= char #\_)
      (and (< (char-code char) 128) (alphanumericp char))))

(defun collapse-underscores (text)
  "TEXT with every run of underscores made one: identifiers containing a double
underscore are reserved to the implementation."
  (with-output-to-string (out)
    (loop for previous = nil then c
          for c across text
          unless (and (eql c #\_) (eql previous #\_))
            do (write-char c out))))

(defun c++-base-identifier (name)
  "NAME (a symbol or string) lower-cased with every other character made an
underscore; no leading, trailing or double underscores, never a leading digit."
  (let* ((text (string-downcase (if (symbolp name) (symbol-name name) name)))
         (id (map 'string (lambda (c) (if (ascii-identifier-char-p c) c #\_)) text))
         (id (string-trim "_" (collapse-underscores id))))
    (cond ((string= id "") "x")
          ((digit-char-p (char id 0)) (concatenate 'string "n" id))
          (t id))))

(defun c++-identifier-text-p (text)
  "True when TEXT is a valid C++ identifier that is neither a keyword nor
reserved, so that it can name generated files and namespaces: an ASCII letter
or underscore, then letters, digits and underscores; no double underscore and
no underscore followed by a capital (reserved to the implementation); not in
*C++-KEYWORDS* nor a macro of the included headers (*C-MACROS*)."
  (and (stringp text)
       (plusp (length text))
       (every #'ascii-identifier-char-p text)
       (not (digit-char-p (char text 0)))
       (not (search "__" text))
       (not (and (char= (char text 0) #\_) (> (length text) 1) (upper-case-p (char text 1))))
       (not (member text *c++-keywords* :test #'string=))
       (not (c-macro-p text))))

(defparameter *c++-reserved-members*
  '("state" "clock" "send" "send_at" "failed_goal" "state_line" "presenter_" "state_"
    "clock_" "schedule_" "span_start_" "span_end_" "failed_goal_" "active_" "fail"
    "note_op_end" "transition" "start_initial_autoscripts" "Controller" "Presenter" "State"
    "Op" "Event" "event_count" "event_name" "find_event" "initial_state" "assign"
    "format_number" "field_index" "kOps" "kEventNames" "same_value" "exponent_form"
    ;; The one-hot state's type and helpers (cpp-words.lisp), and the timed layer's.
    "StateBits" "kStateWords" "with_delta" "bits_meet" "add_bits" "common_bits"
    "differing_bits" "notify_autoscripts_" "changed_fields"
    ;; Exact times (time.hpp, time.cpp).
    "Time" "to_string" "parse_time" "from_micros" "from_seconds" "from_seconds_exact" "never" "to_double")
  "Names the generated code uses itself, so no Lisp name may take them.")

(defun make-identifier-table ()
  "A table giving each Lisp object its own C++ identifier; the generated code's
own member and helper names are taken from the start."
  (let ((used (make-hash-table :test 'equal)))
    (dolist (name *c++-reserved-members*) (setf (gethash name used) t))
    (cons (make-hash-table :test 'equal) used)))

(defun not-a-keyword (id)
  "ID, with a trailing underscore when it is one of *C++-KEYWORDS* or a macro of
the included headers (*C-MACROS*)."
  (if (or (member id *c++-keywords* :test #'string=) (c-macro-p id)) (concatenate 'string id "_") id))

(defparameter *c++-default-name-length* 64
  "The longest default file and namespace name made from a spec's name.")

(defun c++-safe-identifier (name &key (limit *c++-default-name-length*))
  "NAME mangled into an identifier of at most LIMIT characters (plus a keyword's
trailing underscore) satisfying C++-IDENTIFIER-TEXT-P, for file and namespace names."
  (let ((id (c++-base-identifier name)))
    (not-a-keyword (if (> (length id) limit)
                       (string-right-trim "_" (subseq id 0 limit))
                       id))))

(defun numbered-identifier (base n)
  "BASE for N = 1, else BASE with N appended (after an underscore unless BASE ends in one)."
  (cond ((= n 1) base)
        ((char= (char base (1- (length base))) #\_) (format nil "~A~D" base n))
        (t (format nil "~A_~D" base n))))

(defun c++-identifier (object name table &key (prefix ""))
  "The identifier for OBJECT (named NAME) in TABLE, made once: PREFIX plus the
mangled name, a trailing underscore for keywords, a number for collisions."
  (or (gethash object (car table))
      (let* ((base (not-a-keyword (concatenate 'string prefix (c++-base-identifier name))))
             (id (loop for n from 1
                       for candidate = (numbered-identifier base n)
                       unless (gethash candidate (cdr table)) return candidate)))
        (setf (gethash id (cdr table)) t
              (gethash object (car table)) id))))

;;; User text in comments and string literals

(defun comment-safe-char-p (char)
  "True when CHAR may appear as itself in a C++ comment: not a control, format
(bidirectional overrides among them), line or paragraph separator, surrogate
or unassigned character."
  (let ((code (char-code char)))
    (if (< code 128)
        (<= 32 code 126)
        (not (member (sb-unicode:general-category char) '(:cc :cf :zl :zp :cs :co :cn))))))

(defun c++-comment-text (text)
  "TEXT (any user text: a name, a docstring, a printed form) made safe to put in
a C++ comment, // or /* */: every control or line-breaking character becomes a
space, so the text cannot end the comment's line; ?? (a trigraph's start), */
and /* are broken by a space; and text ending in a backslash gets a full stop,
so the backslash cannot continue the comment onto the next line."
  (let* ((text (map 'string (lambda (c) (if (comment-safe-char-p c) c #\Space)) text))
         (text (with-output-to-string (out)
                 (loop for previous = nil then c
                       for c across text
                       do (when (or (and (eql previous #\?) (char= c #\?))
                                    (and (eql previous #\*) (char= c #\/))
                                    (and (eql previous #\/) (char= c #\*)))
                            (write-char #\Space out))
                          (write-char c out))))
         (text (string-right-trim " " text)))
    (if (and (plusp (length text)) (char= (char text (1- (length text))) #\\))
        (concatenate 'string text ".")
        text)))

(defun write-octal-escape (octet out)
  "Write OCTET as a three-digit octal escape: exactly three digits, so the
character after it can never be read as part of it."
  (format out "\\~3,'0O" octet))

(defun write-c++-string-char (char previous out)
  "Write CHAR inside a C++ string literal, PREVIOUS being the character before it."
  (let ((code (char-code char)))
    (cond ((char= char #\") (write-string "\\\"" out))
          ((char= char #\\) (write-string "\\\\" out))
          ((char= char #\Newline) (write-string "\\n" out))
          ((and (char= char #\?) (eql previous #\?)) (write-string "\\?" out))
          ((<= 32 code 126) (write-char char out))
          ((< code 128) (write-octal-escape code out))
          (t (loop for octet across (sb-ext:string-to-octets
                                     (string char) :external-format '(:utf-8 :replacement #\?))
                   do (write-octal-escape octet out))))))

(defun c++-string (text)
  "TEXT as a C++ string literal of its UTF-8 bytes, readable whatever the
compiler's source and execution character sets: quote and backslash escaped,
newline as \\n, every other control character and every non-ASCII byte as a
three-digit octal escape, and the second ? of ?? escaped so no trigraph forms."
  (with-output-to-string (out)
    (write-char #\" out)
    (loop for previous = nil then c
          for c across text
          do (write-c++-string-char c previous out))
    (write-char #\" out)))

;;; Numbers

(defun c++-int64-p (integer)
  "True when INTEGER fits a C++ long long (*INT64-RANGE*)."
  (int64-p integer))

(defun c++-int64 (integer)
  "INTEGER (which must fit 64 bits) as a C++ long long literal. The smallest is
written as an expression: -9223372036854775808LL negates a literal too large
for long long."
  (assert (c++-int64-p integer) (integer) "~D does not fit a C++ long long" integer)
  (if (= integer (first *int64-range*))
      "(-9223372036854775807LL - 1)"
      (format nil "~DLL" integer)))

(defun c++-micros (micros)
  "C++ for MICROS whole microseconds, a Time (time.hpp) literal: {SECONDS, MICROS}
in its floor form, exact whatever its size."
  (multiple-value-bind (seconds rest) (floor micros +micros-per-second+)
    (format nil "Time{~D, ~D}" seconds rest)))

(defun c++-time (seconds)
  "C++ for SECONDS (a spec's duration or time) as a Time literal, converted as
the Lisp backend converts it (SECONDS->MICROS of its double)."
  (c++-micros (seconds->micros (to-double seconds))))

(defun c++-double (number)
  "NUMBER as a C++ double literal that reads back to the same double; HUGE_VAL
(with its sign) for an infinity or a rational beyond the largest double, and
std::nan(\"\") for NaN."
  (let ((double (handler-case (to-double number) (error () nil))))
    (cond ((and double (/= double double)) "std::nan(\"\")")
          ((or (null double) (sb-ext:float-infinity-p double))
           (if (minusp number) "(-HUGE_VAL)" "HUGE_VAL"))
          (t (let* ((*read-default-float-format* 'double-float)
                    (text (prin1-to-string double)))
               (if (find #\. text) text (concatenate 'string text ".0")))))))

(defun c++-hex (integer)
  "INTEGER as a 64-bit unsigned C++ literal."
  (format nil "0x~XULL" integer))
