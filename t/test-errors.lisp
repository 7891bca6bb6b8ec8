;;;; test-errors.lisp -- every kind of bad input gives its own condition, with a
;;;; message that names the offending form, and changes nothing.

(in-package #:player-tests)

(def-suite* errors :in player-tests)

(defun spec-error-of (body)
  "The condition DEFINE-SPEC signals for BODY, or NIL."
  (handler-case (progn (define-spec 'bad-spec body) nil)
    (player-error (e) e)))

(defmacro check-spec-error (class fragment &body body)
  "BODY (spec forms) must signal CLASS whose message contains FRAGMENT."
  `(let ((e (spec-error-of ',body)))
     (is (typep e ',class) "expected ~A, got ~A" ',class e)
     (when e
       (is (search ,fragment (princ-to-string e))
           "message ~S does not contain ~S" (princ-to-string e) ,fragment))))

(test malformed-and-unknown-forms
  (check-spec-error spec-syntax-error "expected (state-variable NAME TYPE INITIAL [VALUES])"
    (state-variable x))
  (check-spec-error spec-syntax-error "unknown form frobnicate"
    (frobnicate x))
  (check-spec-error spec-syntax-error "expected a spec form"
    42)
  (check-spec-error spec-syntax-error "unknown option :colour"
    (state-variable x boolean false) (op o :colour red))
  (check-spec-error spec-syntax-error "unknown or misplaced directive :dance"
    (event e :dance 3))
  (check-spec-error spec-syntax-error "misplaced directive :state"
    (state-variable x boolean false) (op a)
    (macro-op m :precond x :seq (:state x)))
  (check-spec-error spec-syntax-error "malformed expression"
    (state-variable x boolean false) (state-variable y boolean false) (op o :precond (x y)))
  (check-spec-error spec-syntax-error "unknown or malformed spec option"
    (:colour red) (state-variable x boolean false)))

(test unknown-names
  (check-spec-error unknown-name-error "op o: unknown variable or state class ghost"
    (state-variable x boolean false) (op o :precond ghost))
  (check-spec-error unknown-name-error "unknown op fly"
    (event e :op fly))
  (check-spec-error unknown-name-error "unknown variable or state class noclass"
    (state-variable x boolean false) (state-class c (noclass x)))
  (check-spec-error unknown-name-error "unknown event ev-nothing"
    (time-variable t1 (ev-nothing)))
  (check-spec-error unknown-name-error "unknown variable nope"
    (autoscript nope true (p))))

(test values-outside-domains-and-wrong-types
  (check-spec-error domain-error "run is not a value of posture"
    (state-variable posture string sit (sit stand)) (event e :state posture.run))
  (check-spec-error domain-error "jump is not a value of posture"
    (state-variable posture string jump (sit stand)))
  (check-spec-error domain-error "zorblax is not a value of flag"
    (state-variable flag boolean true) (event e :state flag.zorblax))
  (check-spec-error domain-error "zorblax is not a value of flag"
    (state-variable flag boolean true) (op lower :add flag.zorblax))
  (check-spec-error type-error-in-spec "initial value 3 of boolean x is not true, false"
    (state-variable x boolean 3))
  (check-spec-error type-error-in-spec "is not an integer"
    (state-variable n integer 1.5))
  (check-spec-error type-error-in-spec "unknown type colour"
    (state-variable n colour red))
  (check-spec-error type-error-in-spec ":duration must be a number of seconds from 0 to"
    (op o :duration -1))
  (check-spec-error type-error-in-spec "maybe is not true or false"
    (op o :must-ask maybe))
  (check-spec-error spec-syntax-error "not boolean: write posture.VALUE"
    (state-variable posture string sit (sit stand)) (event e :state posture)))

(test duplicates
  (check-spec-error duplicate-definition "x is already defined as a variable"
    (state-variable x boolean false) (state-variable x boolean true))
  (check-spec-error duplicate-definition "op o is defined twice"
    (op o) (op o))
  (check-spec-error duplicate-definition "event e is defined twice"
    (event e) (event e))
  (check-spec-error duplicate-definition "VALUES lists a value twice"
    (state-variable p string a (a b a)))
  (check-spec-error duplicate-definition "already defined as a state class"
    (state-class c ()) (state-variable c boolean false)))

(test class-cycles
  (check-spec-error class-cycle-error "a -> b -> a"
    (state-variable x boolean false)
    (state-class a (b x)) (state-class b (a)))
  (check-spec-error class-cycle-error "self -> self"
    (state-class self (self))))

(test labels-before-set
  (check-spec-error label-error "label a is used before it is set"
    (op bow) (event e :time (+ (label a) 3) :op bow :label a))
  (check-spec-error label-error "label inner is used before it is set"
    (state-variable x boolean false) (op bow)
    (event e :if (x :label inner) :time (label inner))))

(test effect-errors
  (check-spec-error effect-error ":sub cannot be used on enumerated variable posture"
    (state-variable posture string sit (sit stand)) (op o :sub posture.sit))
  (check-spec-error effect-error "contradictory effects: posture is set to both"
    (state-variable posture string sit (sit stand)) (op o :add (posture.sit posture.stand)))
  (check-spec-error effect-error "contradictory effects: x is set to both"
    (state-variable x boolean false) (op o :add x :sub x))
  (check-spec-error effect-error "ops cannot change runtime-only variable n"
    (state-variable n integer 0) (op o :add n)))

(test runtime-only-variables-in-goals
  (check-spec-error goal-error "runtime-only variable n"
    (state-variable n integer 0) (op o :precond n))
  (check-spec-error goal-error "runtime-only variable n cannot appear in a goal"
    (state-variable n integer 0) (event e :state n.3))
  (check-spec-error goal-error "runtime-only variable t1"
    (time-variable t1 (e)) (event e :state t1)))

(test mixed-infix-connectives
  (check-spec-error spec-syntax-error "AND and OR are mixed without parentheses"
    (state-variable a boolean false) (state-variable b boolean false) (state-variable c boolean false)
    (event e :state (a and b or c))))

(test macro-recursion
  (check-spec-error spec-syntax-error "macro-op m runs itself"
    (state-variable x boolean false)
    (macro-op m :precond x :seq (:op n))
    (macro-op n :precond x :seq (:op m))))

(test failed-redefinition-keeps-old-definition
  (let ((old (define-spec 'keep-me '((state-variable x boolean false)))))
    (unwind-protect
         (progn
           (signals spec-error (define-spec 'keep-me '((state-variable x boolean 3))))
           (is (eq old (find-spec 'keep-me))))
      (remove-spec 'keep-me))))

(test unknown-spec-name
  (signals unknown-name-error (find-spec 'no-such-spec-anywhere))
  (is (null (find-spec 'no-such-spec-anywhere nil))))

(test bad-initial-state-makes-no-controller
  (with-spec (spec init-errors (state-variable posture string sit (sit stand))
                               (state-variable x boolean false)
                               (state-variable n integer 0))
    (let ((m (compile-spec spec)))
      (signals unknown-name-error (make-controller m :initial-state '((ghost . 1))))
      (signals domain-error (make-controller m :initial-state '((posture . fly))))
      (signals type-error-in-spec (make-controller m :initial-state '((x . 7))))
      (signals type-error-in-spec (make-controller m :initial-state '((n . 1.5))))
      (is (eq 'stand (state-value (make-controller m :initial-state '((posture . stand))) 'posture))))))

(test unknown-event-changes-nothing
  (with-spec (spec unknown-ev (state-variable x boolean false) (op set-x :add x) (event ev :state x))
    (let* ((c (make-controller (compile-spec spec)))
           (before (controller-state c))
           (lines (length (trace-lines (controller-presenter c)))))
      (let ((e (handler-case (progn (send-event c 'ev-nope) nil) (unknown-event (e) e))))
        (is (typep e 'unknown-event))
        (is (search "unknown event ev-nope (known events: ev)" (princ-to-string e))))
      (is (equal before (controller-state c)))
      (is (= lines (length (trace-lines (controller-presenter c)))))
      (is (eq t (send-event c 'ev))))))

(defun write-temp-spec (text)
  "Write TEXT to a fresh temporary spec file and return its pathname."
  (let ((path (pathname (format nil "/tmp/player-test-~D-~D.lisp" (get-universal-time) (random 1000000)))))
    (with-open-file (out path :direction :output :if-exists :supersede)
      (write-string text out))
    path))

(test reader-errors-name-file-and-line
  (let ((path (write-temp-spec (format nil "(in-package :player-user)~%~%(defspec broken~%  (state-variable x boolean false)~%"))))
    (unwind-protect
         (let ((e (handler-case (progn (load-spec path) nil) (player-error (e) e))))
           (is (typep e 'spec-reader-error))
           (is (search (format nil "~A:3:" (file-namestring path)) (princ-to-string e))))
      (delete-file path))))

(test spec-errors-in-files-name-the-line
  (let ((path (write-temp-spec (format nil "(in-package :player-user)~%; a comment~%(defspec located~%  (state-variable x boolean 3))~%"))))
    (unwind-protect
         (let ((e (handler-case (progn (load-spec path) nil) (player-error (e) e))))
           (is (typep e 'type-error-in-spec))
           ;; The line of the offending form itself, named by kind and name.
           (is (search (format nil "~A:4: state-variable x: initial value 3 of boolean x" (file-namestring path))
                       (princ-to-string e))
               "~A" e))
      (delete-file path))))

(test missing-spec-file
  (signals spec-reader-error (load-spec "/nonexistent/peedy.lisp")))
