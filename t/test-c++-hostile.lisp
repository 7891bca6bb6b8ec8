;;;; test-c++-hostile.lisp -- the C++ backend against hostile input: names and
;;;; docstrings holding newlines, carriage returns, backslashes (trailing too),
;;;; trigraphs, comment delimiters, quotes, keywords, Unicode (bidirectional
;;;; overrides among it) and 1000 characters; names that collide once mangled;
;;;; integers at the edges of 64 bits and floats at the edge of the doubles
;;;; (runtime overflow fails the event with (:overflow VAR)); times up to 1e15
;;;; seconds and past 1e16; a spec with nothing in it; bad :name and
;;;; :namespace arguments. Every generated controller must build with
;;;; *C++-FLAGS* (-Wall -Wextra -Werror -pedantic) and print the Lisp trace.
;;;; Uses the helpers of test-c++.lisp (COMPARE-BACKENDS, RUN-G++...).

(in-package #:player-tests)

(def-suite* c++-hostile :in c++-backend)

;;; Building specs from constructed names

(defun hostile (text)
  "A fresh symbol named TEXT, for names the reader would need |...| for; its
control characters made spaces, since a name may not hold them (issue 31:
a line break in a name would forge trace lines), while strings still may."
  (make-symbol (substitute-if #\Space #'player.base:control-character-p text)))

(defmacro with-hostile-spec ((var name forms) &body body)
  "Define spec NAME (a symbol) from FORMS (evaluated), bind VAR to it, run BODY, forget it."
  (let ((spec-name (gensym "NAME")))
    `(let* ((,spec-name ,name)
            (,var (define-spec ,spec-name ,forms :package (find-package '#:player-tests))))
       (unwind-protect (progn ,@body)
         (remove-spec ,spec-name)))))

(defun check-backends-agree (machine initial-states &key (seed 1) (random-runs 2) (length 30))
  "Check that MACHINE prints the same trace in C++ and Lisp from each of
INITIAL-STATES, over every event in order and over seeded random sequences."
  (let ((events (event-names machine))
        (prng (make-rs-prng seed)))
    (dolist (initial initial-states)
      (let ((problem (compare-backends machine initial events)))
        (is (null problem) "every event: ~A" problem))
      (loop repeat random-runs
            for sequence = (loop repeat length collect (rs-pick prng events))
            do (let ((problem (compare-backends machine initial sequence)))
                 (is (null problem) "random events: ~A" problem))))))

(defun emitted-text (machine)
  "The .hpp and .cpp EMIT-C++ writes for MACHINE, as one string."
  (with-temporary-directory (directory)
    (format nil "~{~A~%~}"
            (mapcar (lambda (path)
                      (with-open-file (in path :external-format :utf-8)
                        (let ((text (make-string (file-length in))))
                          (subseq text 0 (read-sequence text in)))))
                    (emit-c++ machine directory)))))

;;; Comment text and string literals

(defparameter *hostile-texts*
  (list "plain" (format nil "line~%break") (format nil "cr~Cret" #\Return)
        (format nil "crlf~C~%int injected = 1;" #\Return) "back\\slash" "trailing\\"
        "trailing\\  " (format nil "trailing\\~%") "??=" "???/" "a??/" "?" "??" "*/" "/*" "*/*/"
        "quote\"d" "tab	tab" (format nil "nul~Cnul" (code-char 0)) (format nil "del~C" (code-char 127))
        (format nil "bell~C7" (code-char 7)) (format nil "esc~C9" (code-char 27)) "\\x41\\101"
        "caf\\u00e9" (coerce (list #\c #\a #\f (code-char #xe9)) 'string)
        (coerce (list (code-char #x65e5) (code-char #x672c)) 'string)
        (coerce (list #\a (code-char #x202e) #\b (code-char #x2066) #\c) 'string)
        (coerce (list #\a (code-char #x2028) #\b (code-char #x85) #\c) 'string)
        (coerce (list (code-char #x1f99c) #\?) 'string)
        (make-string 1000 :initial-element #\w))
  "Texts a name, docstring or form may hold.")

(defun comment-text-safe-p (text)
  "True when TEXT cannot end, continue or close a C++ comment, nor form a trigraph."
  (and (every (lambda (c) (or (<= 32 (char-code c) 126)
                              (and (> (char-code c) 160)
                                   (not (member (char-code c) '(#x2028 #x2029 #x202e #x2066))))))
              text)
       (not (search "??" text))
       (not (search "*/" text))
       (not (search "/*" text))
       (not (and (plusp (length text)) (find (char text (1- (length text))) "\\ ")))))

(test c++-comment-text-is-inert
  "C++-COMMENT-TEXT leaves no line break, control or bidirectional character,
trigraph, comment delimiter or final backslash, and keeps ordinary text."
  (dolist (text *hostile-texts*)
    (let ((comment (player.cpp::c++-comment-text text)))
      (is (comment-text-safe-p comment) "~S became the comment text ~S" text comment)))
  (is (equal "ev-search (and a b)" (player.cpp::c++-comment-text "ev-search (and a b)")))
  (is (equal "trailing\\." (player.cpp::c++-comment-text (format nil "trailing\\~%")))))

(defun utf-8 (text)
  "TEXT's UTF-8 octets, as a list."
  (coerce (sb-ext:string-to-octets text :external-format :utf-8) 'list))

(defun program-output-octets (program)
  "Run PROGRAM (a pathname): (VALUES EXIT-CODE OCTETS), its standard output as a list of octets."
  (let* ((file (make-pathname :type "out" :defaults program))
         (process (sb-ext:run-program (namestring program) '() :output file :error nil
                                                              :if-output-exists :supersede)))
    (values (sb-ext:process-exit-code process) (coerce (file-bytes file) 'list))))

(test c++-string-literals-hold-any-text
  "Each hostile text as a C++-STRING literal compiles with *C++-FLAGS* and holds
exactly the text's UTF-8 bytes: control characters (NUL too), backslashes,
quotes, ?? (no trigraph), octal escapes followed by digits, Unicode."
  (with-temporary-directory (directory)
    (with-open-file (out (merge-pathnames "strings.cpp" directory) :direction :output
                                                                   :external-format :utf-8)
      (format out "#include <cstdio>~%int main() {~%")
      (loop for text in *hostile-texts*
            for i from 0
            do (format out "  { static const char s~D[] = ~A; std::fwrite(s~D, 1, sizeof s~D - 1, stdout); }~%"
                       i (player.cpp::c++-string text) i i))
      (format out "  return 0;~%}~%"))
    (multiple-value-bind (code errors) (run-g++ directory '("strings.cpp" "-o" "strings"))
      (is (eql 0 code) "g++ failed: ~A" errors)
      (when (eql 0 code)
        (multiple-value-bind (status octets) (program-output-octets (merge-pathnames "strings" directory))
          (is (eql 0 status))
          (is (equal (loop for text in *hostile-texts* append (utf-8 text)) octets)))))))

;;; Names and paths

(test c++-identifier-text-p-accepts-only-identifiers
  "C++-IDENTIFIER-TEXT-P: ASCII identifiers that are neither keywords nor reserved."
  (dolist (good '("peedy" "x" "_x" "a1" "A_b" "Peedy2" "wing_at_ear" "_"))
    (is (player.cpp::c++-identifier-text-p good) "~S should be accepted" good))
  (dolist (bad (list "" "1a" "a::b;int x" "../escape" "a/b" "a.b" "a b" "a-b" "int" "namespace"
                     "class" "main" "std" "__x" "_X" "a__b" "x__" (format nil "a~%b")
                     (coerce (list #\c #\a #\f (code-char #xe9)) 'string) nil 'peedy 42))
    (is (not (player.cpp::c++-identifier-text-p bad)) "~S should be refused" bad)))

(defun emit-c++-error (machine directory &rest arguments)
  "The PLAYER-ERROR EMIT-C++ signals for ARGUMENTS, or NIL."
  (handler-case (progn (apply #'emit-c++ machine directory arguments) nil)
    (player-error (e) e)))

(test c++-emit-refuses-bad-names
  "EMIT-C++ refuses a :name or :namespace that is not a C++ identifier with a
PLAYER-ERROR naming the argument and the value, writing nothing anywhere."
  (with-spec (spec plain (state-variable on boolean false) (op flip :add on) (event ev :state on))
    (let ((machine (plan-spec spec)))
      (with-temporary-directory (parent)
        (let ((out (merge-pathnames "out/" parent)))
          (loop for (argument value) in '((:name "../escape") (:namespace "a::b;int x")
                                          (:name "/tmp/absolute") (:name "int") (:namespace "std")
                                          (:name "a b") (:name ""))
                do (let ((e (emit-c++-error machine out argument value)))
                     (is (typep e 'player-error) "~S ~S was accepted" argument value)
                     (when e
                       (let ((message (princ-to-string e)))
                         (is (search (string-downcase (symbol-name argument)) message) "message: ~A" message)
                         (is (search (player.cpp::c++-string value) message) "message: ~A" message)))))
          (is (null (directory (merge-pathnames "**/*.*" parent))) "files were written")
          ;; Good names write exactly NAME.hpp and NAME.cpp inside --out.
          (let ((files (emit-c++ machine out :name "Ctl_1" :namespace "ns_1")))
            (is (equal '("Ctl_1.hpp" "Ctl_1.cpp") (mapcar #'file-namestring files)))
            (is (every (lambda (f) (equal (pathname-directory f) (pathname-directory out))) files))
            (is (search "namespace ns_1 {" (emitted-text-of files)))))))))

(defun emitted-text-of (files)
  "The contents of FILES, concatenated."
  (format nil "~{~A~}" (mapcar #'uiop:read-file-string files)))

;;; Integers beyond 64 bits

(defun c++-range-error-of (machine)
  "The PLAYER-ERROR EMIT-C++ (into a temporary directory) signals for MACHINE, or NIL."
  (with-temporary-directory (directory)
    (emit-c++-error machine directory)))

(test c++-integers-beyond-64-bits-are-errors
  "An integer the C++ long long cannot hold (an enumerated value, an initial
value, a watched value, an :add delta; the spec checks are bypassed by editing
the parsed spec) makes EMIT-C++ and RUN-C++-TRACE signal a PLAYER-ERROR naming
the spec, the variable and the value."
  (let ((big (expt 2 63)))
    (flet ((check (edit what &optional (value-text "9223372036854775808"))
             (with-spec (spec wide
                          (state-variable gear integer 1 (1 2 3))
                          (state-variable count integer 0)
                          (state-variable on boolean false)
                          (op flip :add on)
                          (autoscript count 5 (tick))
                          (event ev :add (count 1) :if ((> count 2) :add (count -1)) :op flip))
               (funcall edit spec)
               (let ((machine (compile-spec spec)))
                 (dolist (e (list (c++-range-error-of machine)
                                  (handler-case (progn (run-c++-trace machine) nil)
                                    (player-error (e) e))))
                   (is (typep e 'player-error) "~A: no error" what)
                   (when e
                     (let ((message (princ-to-string e)))
                       (is (search "wide" message) "~A: ~A" what message)
                       (is (search (if (search "gear" what) "gear" "count") message) "~A: ~A" what message)
                       (is (search value-text message) "~A: ~A" what message)
                       (is (search "64-bit signed integer" message) "~A: ~A" what message)))))))
             (var (spec name) (find name (player.spec::spec-variables spec) :key #'player.spec::var-name
                                                                          :test #'string-equal)))
      (check (lambda (spec) (setf (aref (player.spec::var-domain (var spec "gear")) 2) big)) "gear value")
      (check (lambda (spec) (setf (player.spec::var-initial (var spec "count")) big)) "count initial")
      (check (lambda (spec) (setf (player.spec::autoscript-value-index (first (player.spec::spec-autoscripts spec))) big))
             "count watched")
      (check (lambda (spec)
               (let ((event (first (player.spec::spec-events spec))))
                 (setf (player.spec::event-directives event)
                       (subst-if (list :increment (var spec "count") (1+ big))
                                 (lambda (d) (and (consp d) (eq (first d) :increment) (eql (third d) 1)))
                                 (player.spec::event-directives event)))))
             "count delta" "9223372036854775809")
      (check (lambda (spec)
               (let ((event (first (player.spec::spec-events spec))))
                 (setf (player.spec::event-directives event)
                       (subst-if (list :increment (var spec "count") (- (1+ big)))
                                 (lambda (d) (and (consp d) (eq (first d) :increment) (eql (third d) -1)))
                                 (player.spec::event-directives event)))))
             "count delta in :if" "-9223372036854775809")
      (check (lambda (spec) (setf (player.spec::var-initial (var spec "count")) (- (1+ big))))
             "count initial, negative" "-9223372036854775809"))))

;;; Runtime overflow: (:overflow VAR)

(test c++-runtime-overflow-fails-like-lisp
  "An :add/:sub that would take an integer variable out of 64 bits or a float
variable out of the finite doubles leaves it unchanged and fails the event with
the goal (:overflow VAR) at the directive's time; the C++ trace equals the Lisp
trace (after ops, inside :if, with autoscripts watching, at -2^63 and 2^63-1)."
  (with-spec (spec overflow
               (state-variable n integer 9223372036854775800)
               (state-variable m integer -9223372036854775800)
               (state-variable x float 1d308)
               (state-variable lit boolean false)
               (op glow :add lit :duration 0.5)
               (op dim :sub lit :duration 0.25)
               (autoscript n 9223372036854775807 (at-max))
               (autoscript m -9223372036854775808 (at-min))
               (autoscript x 1.7d308 (nearly-huge))
               (event up :op glow :add (n 3) :op dim)
               (event up-if :if ((> n 0) :add (n 4611686018427387904)) :op glow)
               (event down :sub (m 3) :op glow)
               (event to-min :sub (m -9223372036854775808))
               (event from-min :add (m 9223372036854775807) :add (m 1))
               (event sub-min :sub (n -9223372036854775808))
               (event grow :op dim :add (x 7d307) :op glow)
               (event shrink :sub (x 1.5d308))
               (event same :add (n 0) :add (x 0)))
    (let* ((machine (compile-spec spec))
           (trace (lisp-trace machine '() '(up up up up))))
      ;; The Lisp side: the third UP overflows after GLOW, at its end.
      (is (member "(:fail up :goal (:overflow n) :time 2)" trace :test #'string=)
          "the Lisp trace has no overflow failure: ~{~%  ~A~}" trace)
      (check-backends-agree machine
                            '(() ((n . -9223372036854775807) (m . 9223372036854775807) (x . -1d308))
                              ((n . 0) (m . 0) (x . 0) (lit . t)))
                            :seed 11 :random-runs 3 :length 40))))

;;; Times

(defun run-format-number (numbers)
  "The C++ format_number of each of NUMBERS (doubles), printed by a program
built against a generated controller."
  (with-spec (spec clocks (state-variable on boolean false) (op flip :add on) (event ev :state on))
    (with-temporary-directory (directory)
      (emit-c++ (plan-spec spec) directory)
      (with-open-file (out (merge-pathnames "numbers.cpp" directory) :direction :output)
        (format out "#include \"clocks.hpp\"
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
int main(int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    const std::uint64_t bits = std::strtoull(argv[i], nullptr, 10);
    double x;
    std::memcpy(&x, &bits, sizeof x);
    std::printf(\"%s\\n\", clocks::format_number(x).c_str());
  }
  return 0;
}
"))
      (multiple-value-bind (code errors) (run-g++ directory '("numbers.cpp" "clocks.cpp" "-o" "numbers"))
        (is (eql 0 code) "g++ failed: ~A" errors)
        (when (eql 0 code)
          (nth-value 1 (apply #'program-output-lines (merge-pathnames "numbers" directory)
                              (mapcar (lambda (x) (princ-to-string (double-bits x))) numbers))))))))

(defun double-bits (x)
  "The 64 bits of double X as an unsigned integer."
  (logior (ash (ldb (byte 32 0) (sb-kernel:double-float-high-bits x)) 32)
          (sb-kernel:double-float-low-bits x)))

(defun bits-double (bits)
  "The double whose 64 bits are BITS."
  (sb-kernel:make-double-float (let ((high (ldb (byte 32 32) bits)))
                                 (if (logbitp 31 high) (- high (expt 2 32)) high))
                               (ldb (byte 32 0) bits)))

(defun sample-times ()
  "Doubles at the edges of FORMAT-NUMBER: rounding at the microsecond, past
2^63 microseconds, up to 1e15 seconds and past 1e16, the extremes, and
seeded random ones of every magnitude; NaN and the infinities when Lisp
prints them."
  (let ((prng (make-rs-prng 16))
        (special (list (bits-double #x7ff8000000000000) (bits-double #x7ff0000000000000)
                       (bits-double #xfff0000000000000))))
    (append (list 0d0 -0d0 0.5d-6 -0.5d-6 0.4999999d-6 1d-6 -1d-6 0.1d0 2.5d0 -2.5d0 1234.5678915d0
                  9.2233720368547758d12 9.3d12 1d14 1.00000000000001d14 1d15 1.000000000000125d15
                  -1d15 123456789012345.67d0 9999999999999998d0 1d16 -1d16 1.5d16 1d22 1d23
                  4.35d17 most-positive-double-float most-negative-double-float
                  least-positive-double-float)
            (loop repeat 400
                  collect (* (if (zerop (rs-below prng 2)) 1 -1)
                             (/ (float (rs-below prng 1000000000) 1d0) 1d9)
                             (expt 10d0 (- (rs-below prng 40) 12))))
            (remove-if-not (lambda (x) (ignore-errors (player.base::format-number x))) special))))

(test c++-format-number-matches-lisp
  "The generated format_number prints every sample double as FORMAT-NUMBER does
(no long long overflow past 2^63 microseconds, exponent form from 1e16 on)."
  (let* ((numbers (sample-times))
         (lines (run-format-number numbers)))
    (is (= (length numbers) (length lines)))
    (loop for x in numbers
          for line in lines
          for expected = (player.base::format-number x)
          unless (equal expected line)
            do (fail "format_number(~S) printed ~S; Lisp prints ~S" x line expected))))

(test c++-large-times-match-lisp
  "Ops of 1e14 s and :time 1e15 s (and clocks summing past 1e16 s) print the
same times in C++ as in Lisp; the controller no longer crashes."
  (with-spec (spec far-future
               (state-variable on boolean false)
               (state-variable ticks float 0.125)
               (time-variable seen (far))
               (op long :duration 1e14)
               (op short :duration 0.123457)
               (op flip :add on :duration 0.5)
               (autoscript on true (glow))
               (event far :time 1e15 :op long :op short :label done :time (+ (label done) 0.25) :op flip)
               (event quick :op short :add (ticks 1e14))
               (event late :if ((> (now) 1e15) :op short) :time (+ seen 1e15) :op short))
    (let ((machine (compile-spec spec)))
      (is (some (lambda (line) (search ":start 1000000000000000 " line))
                (lisp-trace machine '() '(far))))
      (check-backends-agree machine '(() ((on . t) (ticks . 1.5d14)))
                            :seed 15 :random-runs 2 :length 24))))

;;; Specs that once failed to build

(test c++-spec-without-variables-compiles
  "Specs without state variables (assign()'s parameters unused), without ops
and without events build with -Werror and behave as in Lisp."
  (with-spec (spec no-variables (op wave) (event hello :op wave) (event bye :code (progn nil)))
    (let ((problem (compare-backends (compile-spec spec) '() '(hello bye hello))))
      (is (null problem) "~A" problem)))
  (with-spec (spec nothing)
    (is (equal '("(:state)")
               (handler-case (run-c++-trace (compile-spec spec)) (error (e) (list (princ-to-string e))))))))

;;; Adversarial names, compared across backends

(defparameter *long-name* (make-string 1000 :initial-element #\w)
  "A 1000-character name.")

(defun hostile-spec-forms ()
  "(VALUES NAME FORMS INITIAL-STATES) of a spec whose every name and docstring is hostile."
  (let* ((nl (hostile (format nil "line~%break")))
         (cr (hostile (format nil "carriage~Creturn" #\Return)))
         (bs (hostile "back\\slash\\"))
         (tri (hostile "trigraph??="))
         (close (hostile "close*/ /*comment\"quote"))
         (int (hostile "int"))
         (ab1 (hostile "a-b")) (ab2 (hostile "a_b")) (ab3 (hostile (format nil "a~%b")))
         (mood-text (format nil "mood~C" #\Tab))
         (mood (hostile mood-text))
         (happy (hostile "happy??/")) (sad (hostile "sad\\"))
         (quoted "str \"q\" line")  ; no line break: a value is a name (issue 31)
         (cafe (hostile (coerce (list #\c #\a #\f (code-char #xe9)) 'string)))
         (nihon (hostile (coerce (list (code-char #x65e5) (code-char #x672c)) 'string)))
         (long (hostile *long-name*))
         (bidi (hostile (coerce (list #\u #\n #\i (code-char #x202e) #\x) 'string)))
         (count (hostile "count\\"))
         (level (hostile "level*/"))
         (seen (hostile "seen??="))
         (op1 (hostile (format nil "op~%int injected = 1;")))
         (op2 (hostile "op??="))
         (op3 (hostile "op\\"))
         (op4 (hostile "int"))
         (op5 (hostile *long-name*))
         (op6 (hostile "a-b")) (op7 (hostile "a_b")) (op8 (hostile (format nil "a~Cb" #\Return)))
         (op9 (hostile (coerce (list #\o #\p (code-char #x202e)) 'string)))
         (op10 (hostile "close*/"))
         (op11 (hostile "main"))
         (macro (hostile (format nil "macro~C~%??/" #\Return)))
         (label (hostile (format nil "lab~%\\")))
         (label2 (hostile (format nil "other*/label\\")))
         (e1 (hostile (format nil "ev~%int injected = 3;")))
         (e2 (hostile "ev\\"))
         (e3 (hostile "ev??="))
         (e4 (hostile "ev*/\"q\""))
         (e5 (hostile (coerce (list (code-char #xe9) #\v (code-char #x202e)) 'string)))
         (e6 (hostile *long-name*))
         (e7 (hostile "namespace"))
         (e8 (hostile (format nil "seen~%ev")))
         (name (hostile (format nil "hostile~%spec??= */ \\")))
         (dotted (lambda (var value) (hostile (format nil "~A.~A" (symbol-name var) value)))))
    (values
     name
     `(,(format nil "A hostile spec.~%int injected = 2;~C~%??= */ /* \\" #\Return)
       (state-variable ,nl boolean false)
       (state-variable ,cr boolean false)
       (state-variable ,bs boolean false)
       (state-variable ,tri boolean false)
       (state-variable ,close boolean false)
       (state-variable ,int boolean false)
       (state-variable ,ab1 boolean false)
       (state-variable ,ab2 boolean false)
       (state-variable ,ab3 boolean false)
       (state-variable ,mood string ,happy (,happy ,sad ,quoted ,cafe ,nihon))
       (state-variable ,long boolean false)
       (state-variable ,bidi boolean false)
       (state-variable ,count integer 0)
       (state-variable ,level float 0.5)
       (time-variable ,seen (,e8))
       (op ,op1 :add ,nl :duration 0.5)
       (op ,op2 :script ,(hostile (format nil "script~%\\")) :precond ,nl :add (,tri ,bs))
       (op ,op3 :director ,(hostile "dir*/\\") :precond (not ,cr) :add ,(funcall dotted mood "sad\\"))
       (op ,op4 :code (progn "code ??= \\" nil) :add ,int :duration 0.25)
       (op ,op5 :precond ,int :add ,long)
       (op ,op6 :add ,ab1)
       (op ,op7 :precond ,ab1 :add ,ab2)
       (op ,op8 :add ,ab3 :sub ,ab1)
       (op ,op9 :add (,bidi ,(funcall dotted mood (symbol-name cafe))))
       (op ,op10 :add ,close :sub ,nl)
       (op ,op11 :add ,(funcall dotted mood quoted) :must-ask true)
       (macro-op ,macro :precond (not ,cr) :add ,cr :seq (:op ,op1 :label ,label :op ,op2 :time (label ,label)))
       (autoscript ,mood ,happy (,(hostile (format nil "proc~%\\")) ,(hostile "proc??=")))
       (autoscript ,mood ,quoted (,(hostile "quoted*/")))
       (autoscript ,count 2 (,(hostile "p*/")))
       (autoscript ,level 1.5 (,(hostile "float\\")))
       (autoscript ,bidi true (,nihon))
       (event ,e1 :state ,tri :label ,label2 :op ,op5)
       (event ,e2 :add (,count 1) :add (,level 0.5) :if ((> ,count 1) :op ,op10))
       (event ,e3 :op ,macro)
       (event ,e4 :state (and ,ab3 ,ab2) :op ,op11)
       (event ,e5 :op ,op9 :code (progn ,(format nil "x~C~%??=" #\Return) nil))
       (event ,e6 :op ,op4 :time 2.5 :op ,op3)
       (event ,e7 :state ,(funcall dotted mood "sad\\") :state ,(funcall dotted mood (symbol-name nihon)))
       (event ,e8 :if ((> (now) (+ ,seen 1)) :add (,count -1)) :op ,op6))
     `(()
       ((,nl . t) (,mood . ,quoted) (,count . 1))
       ((,cr . t) (,int . t) (,mood . ,cafe) (,level . 1.0d0) (,seen . 0.5))
       ((,ab1 . t) (,bidi . t) (,mood . ,sad) (,long . t))))))

(test c++-hostile-names-match-lisp
  "A spec whose variable, value, op, script, director, event, class, label,
autoscript proc and spec names and docstring hold newlines, CRs, backslashes
(trailing too), ??=, */, quotes, keywords, Unicode (bidirectional overrides
too) and 1000 characters, and names that collide once mangled, builds with
-Wall -Wextra -Werror -pedantic, injects no code, and prints the Lisp trace."
  (multiple-value-bind (name forms initial-states) (hostile-spec-forms)
    (with-hostile-spec (spec name forms)
      (let* ((machine (compile-spec spec))
             (text (emitted-text machine)))
        (is (not (search (format nil "~%int injected") text)) "user text became code")
        (is (not (find (code-char #x202e) text)) "a bidirectional override reached the C++ source")
        (is (null (handler-case (progn (run-c++-trace machine) nil) (error (e) (princ-to-string e)))))
        (check-backends-agree machine initial-states :seed 42 :random-runs 3 :length 40)))))

(test c++-hostile-classes-and-names-colliding-with-the-runtime
  "Classes with hostile names in goals, and names that mangle onto the
generated code's own (same_value, format_number, field_index, s, fail) build
and behave as in Lisp."
  (let* ((base (hostile (format nil "base~%class\\")))
         (ready (hostile "ready??/"))
         (same (hostile "same-value"))
         (fmt (hostile "format_number"))
         (field (hostile "field-index"))
         (s (hostile "s"))
         (fail (hostile "fail"))
         (forms `((state-variable ,same boolean false)
                  (state-variable ,fmt float 0.5)
                  (state-variable ,field integer 1 (1 2 3))
                  (state-variable ,s boolean false)
                  (state-class ,base ((not ,same)))
                  (state-class ,ready (,base ,s))
                  (op ,fail :precond (not ,s) :add ,s)
                  (op ,field :add ,(hostile (format nil "~A.3" (symbol-name field))))
                  (autoscript ,fmt 1.0 (,(hostile "at-one")))
                  (autoscript ,field 3 (,(hostile "at-three")))
                  (event ,(hostile "go") :state ,ready :add (,fmt 0.5) :op ,field)
                  (event ,(hostile "back") :add ,same :sub ,s :add (,fmt -0.5)))))
    (with-hostile-spec (spec (hostile (format nil "classes~%??=")) forms)
      (check-backends-agree (compile-spec spec) '(()) :seed 3 :random-runs 2 :length 20))))
