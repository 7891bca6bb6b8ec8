;;;; test-hostile-input.lisp -- a spec file is data: opening one runs no code,
;;;; and every malformed input (circular or deep structure, huge or non-finite
;;;; numbers, odd shapes, files that are not regular or not UTF-8) is one
;;;; PLAYER-ERROR naming the form, never a raw SBCL condition.

(in-package #:player-tests)

(def-suite* hostile-input :in player-tests)

(defvar *scratch-counter* 0 "Numbers the scratch files of this test run.")

(defun scratch-file (text &key (name "hostile"))
  "A fresh file under /tmp holding TEXT (a string, or octets); its path as a string."
  (let ((path (format nil "/tmp/player-hostile-~D-~D-~A.lisp" (sb-posix:getpid)
                      (incf *scratch-counter*) name)))
    (if (stringp text)
        (with-open-file (out path :direction :output :if-exists :supersede :external-format :utf-8)
          (write-string text out))
        (with-open-file (out path :direction :output :if-exists :supersede
                                  :element-type '(unsigned-byte 8))
          (write-sequence text out)))
    path))

(defun load-error (text)
  "The condition LOAD-SPEC signals for a file holding TEXT (a PLAYER-ERROR or
anything else that escapes) and its message, or NIL when it loads; the specs
it defines are forgotten.  The message is taken while the file exists, since
it names the file's line."
  (let ((file (scratch-file text)))
    (unwind-protect
         (handler-case (progn (mapc (lambda (spec) (remove-spec (spec-name spec))) (load-spec file))
                              nil)
           (serious-condition (condition)
             (values condition (handler-case (princ-to-string condition) (error () "?")))))
      (delete-file file))))

(defmacro check-load-error (class fragment text)
  "Loading TEXT must signal CLASS with FRAGMENT in its message."
  `(multiple-value-bind (e message) (load-error ,text)
     (is (typep e ',class) "expected ~A, got ~S for ~S" ',class (type-of e) (subseq ,text 0 (min 80 (length ,text))))
     (when (typep e 'player-error)
       (is (search ,fragment message) "message ~S lacks ~S" message ,fragment))))

(defun marker-path (name)
  "A path that a hostile payload would create, unique to this test run."
  (format nil "/tmp/player-hostile-marker-~D-~A" (sb-posix:getpid) name))

(test opening-a-spec-file-runs-no-code
  (let ((read-time (marker-path "read-eval"))
        (top-level (marker-path "top-level")))
    (check-load-error spec-reader-error "can't read #. while *READ-EVAL* is NIL"
      (format nil "(in-package :player-user)~%(defspec evil (state-variable x boolean #.(progn (with-open-file (s ~S :direction :output :if-exists :supersede) (print 1 s)) 'false)))~%"
              read-time))
    (check-load-error spec-syntax-error "a spec file holds only in-package and defspec forms"
      (format nil "(in-package :player-user)~%(with-open-file (s ~S :direction :output :if-exists :supersede) (print 1 s))~%(defspec ok (state-variable x boolean false))~%"
              top-level))
    (check-load-error spec-syntax-error "a spec file holds only in-package and defspec forms"
      "(defun evil () 1)")
    (check-load-error spec-reader-error "#S(...) structures are not data"
      "(defspec s (state-variable x boolean #S(player::spec)))")
    (check-load-error spec-reader-error "may only switch to player-user"
      "(in-package :cl-user) (defspec x)")
    (is (not (probe-file read-time)) "#. ran")
    (is (not (probe-file top-level)) "a top-level form ran")))

(test spec-errors-in-files-name-file-and-line
  (multiple-value-bind (e message)
      (load-error (format nil "(in-package :player-user)~%~%(defspec d~%  (state-variable x boolean 1d308))~%"))
    (is (typep e 'type-error-in-spec))
    (is (search ":4: state-variable x: initial value 1.0e308 of boolean x" message) "~A" message)))

(test circular-and-deep-structure
  ;; Found while reading a file: a SPEC-READER-ERROR at the form's line.
  (check-load-error spec-reader-error "contains itself (circular structure"
    "(defspec c (state-variable x boolean false) (op o :precond #1=(x and . #1#) :add x))")
  (check-load-error spec-reader-error "contains itself"
    "(defspec c (state-variable p string #1=(x . #1#) (x y)))")
  (check-load-error spec-reader-error "nests more than 1000 levels deep"
    (format nil "(defspec deep (state-variable x boolean false) (op o :add x :precond ~A x ~A))"
            (with-output-to-string (s) (dotimes (i 15000) (write-string "(not " s)))
            (make-string 15000 :initial-element #\))))
  ;; In memory, through the API: the same limits.
  (let ((circular (list 'x 'and 'x)))
    (setf (cdr (last circular)) circular)
    (signals spec-syntax-error (define-spec 'circ `((state-variable x boolean false) (op o :precond ,circular :add x))))
    (let ((e (handler-case (define-spec 'circ `((state-variable x boolean false) (op o :precond ,circular)))
               (spec-error (e) e))))
      (is (search "contains itself" (princ-to-string e)))))
  (let ((deep 'x))
    (dotimes (i 5000) (setf deep (list 'not deep)))
    (signals spec-syntax-error (define-spec 'deep `((state-variable x boolean false) (op o :precond ,deep :add x))))))

(test messages-about-circular-forms-are-bounded
  (let ((circular (list 1 2)))
    (setf (cdr (last circular)) circular)
    (is (<= (length (player.base::bounded-lisp-text circular 100)) 100))
    (let ((nested (list nil)))
      (setf (car nested) nested)
      (is (<= (length (player.base::bounded-lisp-text nested 50)) 50)))))

(test numbers-must-be-finite-and-in-range
  (let ((huge (make-string 401 :initial-element #\9)))
    (check-load-error type-error-in-spec ":duration must be a number of seconds from 0 to"
      (format nil "(defspec n (state-variable x boolean false) (op o :add x :duration ~A))" huge))
    (check-load-error type-error-in-spec ":time must be a number of seconds"
      (format nil "(defspec n (state-variable x boolean false) (op o :add x) (event e :time ~A :op o))" huge))
    (check-load-error type-error-in-spec "from -2^63 to 2^63-1"
      (format nil "(defspec n (state-variable c integer ~A))" huge))
    (check-load-error type-error-in-spec "is not an integer from -2^63 to 2^63-1"
      (format nil "(defspec n (state-variable c integer 0 (1 ~A)))" huge)))
  (check-load-error type-error-in-spec ":duration must be a number of seconds from 0"
    "(defspec n (state-variable x boolean false) (op o :add x :duration -1))")
  (check-load-error type-error-in-spec "is not true, false, t or nil"
    "(defspec n (state-variable x boolean 1d308))")
  ;; NaN and the infinities can only arrive through the API.
  (sb-int:with-float-traps-masked (:invalid :overflow)
    (let* ((infinity sb-ext:double-float-positive-infinity)
           (nan (locally (declare (notinline -)) (- infinity infinity)))) ; not folded
      (dolist (bad (list infinity (- infinity) nan))
        (signals type-error-in-spec
          (define-spec 'nan `((state-variable x boolean false) (op o :add x :duration ,bad))))
        (signals type-error-in-spec
          (define-spec 'nan `((state-variable n float ,bad))))
        (signals type-error-in-spec
          (define-spec 'nan `((state-variable n float 0) (event e :add (n ,bad))))))))
  (remove-spec 'nan))

(test shapes-are-spec-errors
  (check-load-error spec-syntax-error "(a . b) is not a literal or a list of literals"
    "(defspec d (state-variable x boolean false) (op o :add (a . b)))")
  (check-load-error spec-syntax-error "a spec's name must be a symbol, not \"door\""
    "(defspec \"door\" (state-variable x boolean false))")
  (check-load-error spec-syntax-error "the body of defspec d is not a proper list"
    "(defspec d (state-variable x boolean false) . 5)")
  (check-load-error spec-syntax-error "a spec's name must be a symbol"
    "(defspec)")
  (check-load-error spec-syntax-error "true is a boolean word, not a variable name"
    "(defspec d (state-variable true boolean false) (op o :add true))")
  (signals spec-syntax-error (eval '(defspec)))
  (signals spec-syntax-error (eval '(defspec "door" (state-variable x boolean false)))))

(test files-that-are-not-regular-utf-8-text
  (let ((directory (format nil "/tmp/player-hostile-dir-~D/" (sb-posix:getpid))))
    (ensure-directories-exist directory)
    (let ((e (handler-case (load-spec directory) (player-error (e) e))))
      (is (search "not a regular file" (princ-to-string e))))
    (sb-ext:delete-directory directory))
  (let ((fifo (format nil "/tmp/player-hostile-fifo-~D" (sb-posix:getpid))))
    (sb-ext:run-program "/usr/bin/mkfifo" (list fifo))
    (unwind-protect
         (let ((e (handler-case (load-spec fifo) (player-error (e) e))))
           (is (search "not a regular file" (princ-to-string e))))
      (delete-file fifo)))
  (let* ((octets (concatenate '(vector (unsigned-byte 8))
                              (sb-ext:string-to-octets (format nil "(defspec d~%  (state-variable x boolean false))~%; ") :external-format :utf-8)
                              #(255 254 10)))
         (file (scratch-file octets))
         (e (handler-case (load-spec file) (player-error (e) e))))
    (is (typep e 'spec-reader-error))
    (is (search ":3: the file is not valid UTF-8 text" (princ-to-string e)) "~A" e)
    (delete-file file))
  (is (null (load-spec (scratch-file "")))))

(test no-code-refuses-code
  (let ((text "(defspec coded (state-variable x boolean false)
  (op o :add x :code (print 1))
  (op p :add x :c++ \"x = 1;\")
  (event e :op o :if (x :code (print 2))))"))
    (let ((file (scratch-file text)))
      (let ((e (handler-case (load-spec file :allow-code nil) (player-error (e) e))))
        (is (typep e 'player::untrusted-code-error))
        (is (search "op o: :code" (princ-to-string e)))
        (is (search "op p: :c++" (princ-to-string e)))
        (is (search "event e: :code (print 2)" (princ-to-string e))))
      (is (null (find-spec 'coded nil)) "a refused spec is not defined")
      (is (= 1 (length (load-spec file))) "accepted without :allow-code nil")
      (remove-spec 'coded)
      (multiple-value-bind (out err code) (player-command "plans" file "--no-code")
        (declare (ignore out))
        (is (= 1 code))
        (is (search "code refused" err)))
      (delete-file file)))
  (let ((file (scratch-file "(defspec plain (state-variable x boolean false) (op o :add x) (event e :op o))")))
    (multiple-value-bind (out err code) (player-command "run" file "--no-code" "--events" "e")
      (is (= 0 code) "~A" err)
      (is (search "(:op o :script o :start 0 :end 1)" out)))
    (delete-file file)))

(test run-time-overflow-fails-the-event
  (with-spec (spec overflowing
              (state-variable n float 0)
              (state-variable c integer 9223372036854775806)
              (event big :add (n 1d308))
              (event inc :add (c 1)))
    (let ((controller (make-controller (compile-spec spec))))
      (is (eq t (send-event controller 'big)))
      (is (equal '(nil (:overflow player-tests::n))
                 (multiple-value-list (send-event controller 'big))))
      (is (= 1d308 (state-value controller 'n)) "the value is kept")
      (is (eq t (send-event controller 'inc)))
      (is (equal '(nil (:overflow player-tests::c)) (multiple-value-list (send-event controller 'inc))))
      (is (= 9223372036854775807 (state-value controller 'c)))
      (is (member "(:fail big :goal (:overflow n) :time 0)" (trace-of controller) :test #'string=)))))

(test cli-numbers-and-storage
  (let ((file (scratch-file "(defspec t1 (state-variable n float 0) (time-variable heard (e)) (event e :add (n 1)))")))
    (check-cli-error 1 "is not a finite number for n" "run" file "--initial" (format nil "n=~A" (make-string 401 :initial-element #\9)))
    (check-cli-error 1 "time variable heard must be a number of seconds" "run" file "--initial" (format nil "heard=~A" (make-string 401 :initial-element #\9)))
    (check-cli-error 2 "cannot read the value \"1e400\"" "run" file "--initial" "n=1e400")
    (delete-file file)))

(test nesting-hidden-from-the-text-is-still-measured
  ;; Nested block comments and runs of quotes nest the reader too.
  (check-load-error spec-reader-error "nests more than 1000 levels deep"
    (format nil "#| #| |# |# (defspec deep (state-variable x boolean false) (op o :add x :precond ~A x ~A))"
            (with-output-to-string (s) (dotimes (i 15000) (write-string "(not " s)))
            (make-string 15000 :initial-element #\))))
  (check-load-error spec-reader-error "nests more than 1000 levels deep"
    (format nil "(defspec q (state-variable x boolean false) (event e :state ~Ax))"
            (make-string 15000 :initial-element #\`)))
  (let ((deep 1))
    (dotimes (i 5000) (setf deep (vector deep)))
    (signals spec-syntax-error (define-spec 'deep-vector `((state-variable x boolean ,deep))))))

(test run-time-times-out-of-range-fail-the-event
  (with-spec (spec far-off
              (state-variable on boolean false)
              (op switch-on :add on)
              (event late :label a :time (+ (label a) 1d308 1d308) :op switch-on))
    (let ((controller (make-controller (compile-spec spec))))
      (is (equal '(nil (:overflow :time)) (multiple-value-list (send-event controller 'late))))
      (is (null (state-value controller 'on)))
      (is (member "(:fail late :goal (:overflow :time) :time 0)" (trace-of controller) :test #'string=)))))

(test library-numbers-are-in-range
  (flet ((library-error (text)
           (let ((file (scratch-file text)))
             (unwind-protect (handler-case (progn (load-script-library file) nil)
                               (serious-condition (c) (values c (princ-to-string c))))
               (delete-file file)))))
    (dolist (text '("(defscript s () (:at 0 :animate (:self position) (:keys ((0 :vec3 0 0 0) (1d-12 :vec3 1 0 0)) :interpolation :catmull-rom)))"
                    "(defscript s () (:at 0 :animate (:self position) (:keys ((0 :vec3 0 0 0) (1 :vec3 1d308 0 0)))))"
                    "(defobject far :position (0 0 1d308))"))
      (multiple-value-bind (e message) (library-error text)
        (is (typep e 'script-error) "~S for ~A" e text)
        (is (search "is out of range" (or message "")) "~A" message)))
    (multiple-value-bind (e message) (library-error "(defscript spin (:duration 1d-6 :loop t) (:at 0 :set (:self visible) t))")
      (is (typep e 'script-error))
      (is (search "a looping script must last some time (at least 0.001 s)" (or message "")) "~A" message))))

;;; Errors point at their own form (issue 14): the line of the op, event or
;;; variable at fault, named by kind and name.

(defparameter *located-spec-lines*
  '("(in-package :player-user)"
    ";; a small spec; each case below replaces line 6"
    "(defspec cat \"A cat.\""
    "  (state-variable posture string sit (sit stand lie))"
    "  (state-variable hungry boolean true)"
    "  (op placeholder :duration 1)"
    "  (state-class awake-cat (posture.stand))"
    "  (op stand-up :precond posture.sit :add posture.stand)"
    "  (op eat :precond awake-cat :sub hungry :duration 2)"
    "  (event ev-feed :op eat))")
  "The spec the located-error cases edit; line 6 is replaced by each case.")

(defparameter *located-mistakes*
  '(("(op whistle :precond ack-opp)" "op whistle: unknown variable or state class ack-opp")
    ("(op purr :add hungryy)" "op purr: unknown variable hungryy")
    ("(op purr :sub posture.sit)" "op purr: :sub cannot be used on enumerated variable posture")
    ("(op purr :add (a . b))" "op purr: (a . b) is not a literal or a list of literals")
    ("(op purr :duration -2)" "op purr: :duration must be a number of seconds")
    ("(op purr :colour red)" "op purr: unknown option :colour")
    ("(op purr :add posture.fly)" "op purr: fly is not a value of posture")
    ("(op purr :add hungry :sub hungry)" "op purr: contradictory effects")
    ("(event ev-purr :op purrr)" "event ev-purr: unknown op purrr")
    ("(event ev-purr :dance 3)" "event ev-purr: unknown or misplaced directive :dance")
    ("(event ev-purr :state (posture.sit hungry))" "event ev-purr: malformed expression")
    ("(state-variable mood string calm)" "state-variable mood: a string variable needs a VALUES list")
    ("(state-variable mood boolean 3)" "state-variable mood: initial value 3 of boolean mood")
    ("(state-variable posture boolean true)" "state-variable posture: posture is already defined")
    ("(state-class sleepy (posture.snooze))" "state-class sleepy: snooze is not a value of posture")
    ("(time-variable fed (ev-never))" "time-variable fed: unknown event ev-never")
    ("(autoscript moood true (p))" "autoscript moood: unknown variable moood"))
  "Each mistake (a replacement for line 6) and what its message must say after FILE:6:.")

(test errors-name-the-line-and-form-at-fault
  (loop for (line expected) in *located-mistakes*
        do (let ((text (format nil "~{~A~%~}" (substitute line (sixth *located-spec-lines*) *located-spec-lines*
                                                          :test #'string=))))
             (multiple-value-bind (e message) (load-error text)
               (is (typep e 'spec-error) "~A: got ~S" line e)
               (is (search (format nil "hostile.lisp:6: ~A" expected) (or message ""))
                   "~A~%  gave: ~A" line message)))))
