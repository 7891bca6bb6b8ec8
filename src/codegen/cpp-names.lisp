;;;; cpp-names.lisp -- Lisp names as valid, collision-free C++ identifiers.

(in-package #:player)

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
    "volatile" "wchar_t" "while" "xor" "xor_eq" "main" "std" "NULL" "assert" "errno")
  "Words a generated identifier must not be (C++ keywords and troublesome names).")

(defun c++-base-identifier (name)
  "NAME (a symbol or string) lower-cased with every other character made an underscore."
  (let* ((text (string-downcase (if (symbolp name) (symbol-name name) name)))
         (id (map 'string (lambda (c) (if (or (alphanumericp c) (char= c #\_)) c #\_)) text))
         (id (string-trim "_" (remove-if-not (lambda (c) (< (char-code c) 128)) id))))
    (cond ((string= id "") "x")
          ((digit-char-p (char id 0)) (concatenate 'string "n" id))
          (t id))))

(defparameter *c++-reserved-members*
  '("state" "clock" "send" "send_at" "failed_goal" "state_line" "presenter_" "state_"
    "clock_" "schedule_" "span_start_" "span_end_" "failed_goal_" "active_" "fail"
    "note_op_end" "transition" "start_initial_autoscripts" "Controller" "Presenter" "State"
    "Op" "Event" "event_count" "event_name" "find_event" "initial_state" "assign"
    "format_number" "field_index" "kOps" "kEventNames")
  "Names the generated code uses itself, so no Lisp name may take them.")

(defun make-identifier-table ()
  "A table giving each Lisp object its own C++ identifier; the generated code's
own member and helper names are taken from the start."
  (let ((used (make-hash-table :test 'equal)))
    (dolist (name *c++-reserved-members*) (setf (gethash name used) t))
    (cons (make-hash-table :test 'equal) used)))

(defun c++-safe-identifier (name)
  "NAME mangled into an identifier that is not a C++ keyword (for file and namespace names)."
  (let ((id (c++-base-identifier name)))
    (if (member id *c++-keywords* :test #'string=) (concatenate 'string id "_") id)))

(defun c++-identifier (object name table &key (prefix ""))
  "The identifier for OBJECT (named NAME) in TABLE, made once: PREFIX plus the
mangled name, a trailing underscore for keywords, a number for collisions."
  (or (gethash object (car table))
      (let* ((base (concatenate 'string prefix (c++-base-identifier name)))
             (base (if (member base *c++-keywords* :test #'string=)
                       (concatenate 'string base "_")
                       base))
             (id (loop for n from 1
                       for candidate = (if (= n 1) base (format nil "~A_~D" base n))
                       unless (gethash candidate (cdr table)) return candidate)))
        (setf (gethash id (cdr table)) t
              (gethash object (car table)) id))))

(defun c++-string (text)
  "TEXT as a C++ string literal."
  (with-output-to-string (out)
    (write-char #\" out)
    (loop for c across text
          do (case c
               (#\" (write-string "\\\"" out))
               (#\\ (write-string "\\\\" out))
               (#\Newline (write-string "\\n" out))
               (t (write-char c out))))
    (write-char #\" out)))

(defun c++-double (number)
  "NUMBER as a C++ double literal that reads back to the same double."
  (let ((*read-default-float-format* 'double-float))
    (let ((text (prin1-to-string (to-double number))))
      (if (find #\. text) text (concatenate 'string text ".0")))))

(defun c++-hex (integer)
  "INTEGER as a 64-bit unsigned C++ literal."
  (format nil "0x~XULL" integer))
