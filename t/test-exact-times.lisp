;;;; test-exact-times.lisp -- issue 31: times exact to the microsecond up to
;;;; 1e15 s, in both backends.  The boundary cases in Lisp; a property test
;;;; that the Lisp and C++ conversions (decimal text, doubles) and printing
;;;; agree with an exact rational reference; and both backends on a spec
;;;; whose timers and ops fall at large offsets.  One C++ build serves all.

(in-package #:player-tests)

(def-suite* exact-times :in player-tests)

(defun reference-micros (rational)
  "The independent rule: RATIONAL seconds to the nearest microsecond, ties to even."
  (round (* rational 1000000)))

(defun reference-time-text (micros)
  "MICROS as the trace prints a time, worked out digit by digit from the integer."
  (let* ((digits (format nil "~7,'0D" (abs micros)))
         (whole (string-left-trim "0" (subseq digits 0 (- (length digits) 6))))
         (fraction (string-right-trim "0" (subseq digits (- (length digits) 6)))))
    (format nil "~:[~;-~]~A~:[.~A~;~*~]" (minusp micros) (if (string= whole "") "0" whole)
            (string= fraction "") fraction)))

(test boundary-times-convert-and-print-exactly
  "0, 1 us, 2^32 s + 1 us, 9e9 s + 1 us, 123456789012.000001, 1e15 - 1 us, 1e15
and negative times: text and doubles to microseconds, and back to text."
  (loop for (text micros) in '(("0" 0) ("0.000001" 1) ("4294967296.000001" 4294967296000001)
                               ("9000000000.000001" 9000000000000001)
                               ("123456789012.000001" 123456789012000001)
                               ("999999999999999.999999" 999999999999999999999)
                               ("1e15" 1000000000000000000000) ("1E15" 1000000000000000000000)
                               ("1.5E-3" 1500) (".5" 500000) ("2." 2000000)
                               ("-0.25" -250000) ("-1.0000005" -1000000) ("-1.0000015" -1000002)
                               ("0.0000005" 0) ("0.0000015" 2) ("0.00000150001" 2))
        do (let ((seconds (player.base:parse-decimal-seconds text)))
             (is (eql micros (player.base:seconds->micros seconds)) "~A: ~A, not ~A" text (player.base:seconds->micros seconds) micros)
             (is (string= (reference-time-text micros) (player.base:format-micros micros)))
             (is (string= (player.base:format-micros micros) (player.base:format-number (player.base:micros->seconds micros))))))
  (dolist (text '("" "." "e5" "1e" "1.2.3" "1x" "--1" "1e-" "0x10"))
    (is (null (player.base:parse-decimal-seconds text)) "~S is no decimal" text))
  ;; Doubles at their exact binary value: 2.5e-6 is a little above 2.5 us.
  (dolist (x (list 0d0 1d-6 2.5d-6 -2.5d-6 0.5d-6 1.5d-6 4294967296.000001d0 9d9 1d15 -1d15
                   0.1d0 0.3d0 (scale-float 1d0 -21) 12345.0000005d0))
    (is (eql (reference-micros (rational x)) (player.base:seconds->micros x)) "~A" x)))

(test a-timed-controller-keeps-every-microsecond
  "A timed controller far from 0 keeps its events' microseconds: the trace, the
clock in microseconds, and CONTROLLER-TIME's double."
  (with-spec (spec exact-far
               (state-variable posture string sit (sit stand))
               (op stand-up :precond posture.sit :add posture.stand :duration 0.000001)
               (event ev-stand :state posture.stand))
    (let ((controller (make-controller (compile-spec spec) :timed t)))
      (send-event controller 'ev-stand :at (player.base:parse-decimal-seconds "123456789012.000001"))
      (finish-events controller)
      (is (equal '("(:event ev-stand :time 123456789012.000001)"
                   "(:op stand-up :script stand-up :start 123456789012.000001 :end 123456789012.000002)"
                   "(:state (posture . stand))")
                 (trace-of controller)))
      (is (eql 123456789012000002 (controller-microseconds controller)))
      (is (= 123456789012.000002d0 (controller-time controller)))
      (signals argument-error (send-event controller 'ev-stand :at (player.base:parse-decimal-seconds "123456789012.000001")))
      (advance controller 1d15)
      (is (eql (expt 10 21) (controller-microseconds controller))))))

(test the-clock-may-start-below-zero
  "A controller's clock may start at a negative time: it prints exactly too."
  (with-spec (spec exact-negative
               (state-variable posture string sit (sit stand))
               (op stand-up :precond posture.sit :add posture.stand :duration 0.75)
               (event ev-stand :state posture.stand))
    (let ((controller (make-controller (compile-spec spec) :clock -5/2000000)))
      (is (eql -2 (controller-microseconds controller)) "ties to even")
      (send-event controller 'ev-stand)
      (is (equal '("(:event ev-stand :time -0.000002)"
                   "(:op stand-up :script stand-up :start -0.000002 :end 0.749998)"
                   "(:state (posture . stand))")
                 (trace-of controller))))))

;;; Both backends: one program holding two controllers

(defun random-decimal-cases (prng count)
  "COUNT (TEXT . RATIONAL) pairs, sorted by value, of decimals from 0 to 1e15:
up to nine decimals (so some round, some tie), some in exponent form."
  (sort (loop repeat count
              collect (let* ((scale (random 10 prng))
                             (digits (random (* (expt 10 (+ 6 (random 10 prng))) (if (zerop (random 4 prng)) 5 1))
                                             prng))
                             (digits (if (zerop (random 5 prng)) (* 5 (expt 10 (max 0 (1- scale)))) digits))
                             (value (/ digits (expt 10 scale)))
                             (plain (let ((text (format nil "~V,'0D" (1+ scale) digits)))
                                      (if (zerop scale)
                                          text
                                          (format nil "~A.~A" (subseq text 0 (- (length text) scale))
                                                  (subseq text (- (length text) scale)))))))
                        (cons (if (zerop (random 3 prng)) (format nil "~De-~D" digits scale) plain)
                              value)))
        #'< :key #'cdr))

(defun random-duration-doubles (prng count)
  "COUNT doubles from 0 to 1e15 s, many near half a microsecond: random
magnitudes, random bits, and ties of the decimal kind (2.5e-6) that no double holds."
  (loop repeat count
        collect (ecase (random 3 prng)
                  (0 (* (random 1d0 prng) (expt 10d0 (- (random 17 prng) 6))))
                  (1 (/ (+ (random 10000000 prng) 0.5d0) (expt 10d0 (+ 6 (random 3 prng)))))
                  (2 (scale-float (float (random (expt 2 53) prng) 1d0) (- (random 60 prng) 80))))))

(defparameter *exact-duration-count* (sweep-count 120 30)
  "How many random durations the property test gives ops.")

(defun durations-spec-forms (durations)
  "A spec whose event EV-I plays op D-I of duration the Ith of DURATIONS, and
whose event EV (no op) marks the decimal times."
  (append '((state-variable posture string sit (sit stand))
            (event ev :state posture.sit))
          (loop for duration in durations
                for i from 0
                collect `(op ,(intern (format nil "D~D" i) :player-tests) :duration ,duration)
                collect `(event ,(intern (format nil "EV~D" i) :player-tests)
                                :op ,(intern (format nil "D~D" i) :player-tests)))))

(defparameter *exact-far-forms*
  '((state-variable posture string sit (sit stand))
    (state-variable alert boolean false)
    (op stand-up :precond posture.sit :add posture.stand :duration 0.000001d0)
    (op sit-down :precond posture.stand :add posture.sit :duration 1.5d0)
    (op long :duration 123456789012.000001d0 :interrupt (:at 4294967296.000001d0 9000000000.000001d0))
    (op wake :add alert :duration 0.333333d0)
    (event ev-long :op long :op stand-up :op sit-down)
    (event ev-stand (:when-busy :queue) :state posture.stand)
    (event ev-wake (:when-busy :preempt) :op wake)
    (timer beat :after 3333333.333333d0 :event ev-stand :restart-on :any)
    (timer late :after 999999999999.999999d0 :event ev-wake))
  "Timers and interruption points at large offsets from large times (doubles,
as a spec file reads them; the nearest doubles are not the decimals).")

(defvar *exact-times-program* nil
  "(EXECUTABLE DURATIONS DURATION-MACHINE FAR-MACHINE), built once a session.")

(defun exact-times-program ()
  "The one C++ program of this suite: the durations spec and the far spec."
  (or *exact-times-program*
      (let* ((durations (random-duration-doubles (sb-ext:seed-random-state 31) *exact-duration-count*))
             (machines (list (machine-of-forms 'exact-durations (durations-spec-forms durations)
                                               (find-package '#:player-tests))
                             (machine-of-forms 'exact-far *exact-far-forms* (find-package '#:player-tests)))))
        (setf *exact-times-program*
              (list* (player.cpp::build-timed-c++-batch machines) durations machines)))))

(defun c++-event-times (lines)
  "The :time texts of the (:event EV ...) lines of LINES."
  (loop for line in lines
        when (eql 0 (search "(:event ev :time " line))
          collect (subseq line (length "(:event ev :time ") (1- (length line)))))

(test c++-reads-and-prints-decimal-times-as-lisp-does
  "Random decimal texts, read by the C++ driver (never through a double), print
as the exact rational reference says, and as the Lisp CLI reads them."
  (destructuring-bind (executable durations machine far) (exact-times-program)
    (declare (ignore durations far))
    (let* ((cases (random-decimal-cases (sb-ext:seed-random-state 131) (sweep-count 300 60)))
           (lines (player.cpp::run-batch-driver
                   executable 0 "timed"
                   (list* "0" "-" "0" (mapcar (lambda (case) (format nil "~D@~A" (player.cpp::event-index (machine-spec machine) 'ev) (car case)))
                                              cases))))
           (printed (c++-event-times lines)))
      (is (= (length cases) (length printed)))
      (loop for (text . value) in cases
            for c++ in printed
            for expected = (reference-time-text (reference-micros value))
            do (is (string= expected c++) "C++ reads ~A as ~A, not ~A" text c++ expected)
               (is (string= expected (player.base:format-micros (player.base:seconds->micros (player.base:parse-decimal-seconds text))))
                   "Lisp reads ~A differently" text)))))

(test c++-converts-doubles-as-lisp-does
  "Ops of random double durations (many near half a microsecond): both backends
end each op where the exact rational reference says."
  (destructuring-bind (executable durations machine far) (exact-times-program)
    (declare (ignore far))
    (let* ((events (loop for i below (length durations)
                         collect (intern (format nil "EV~D" i) :player-tests)))
           (c++ (player.cpp::run-timed-c++-batch executable 0 machine :events events))
           (lisp (lisp-timed-trace machine nil events)))
      (is (equal lisp c++) "~A" (first-difference lisp c++))
      (let ((now 0))
        (loop for duration in durations
              for i from 0
              for line = (find-if (lambda (line) (search (format nil "(:op d~D " i) line)) lisp)
              do (incf now (reference-micros (rational duration)))
                 (is (search (format nil ":end ~A)" (reference-time-text now)) line)
                     "~A s: ~A" duration line))))))

(test both-backends-agree-far-from-zero
  "Timers, interruption points and ops at large offsets, events up to 1e15 s:
the same trace from both backends, every microsecond kept."
  (destructuring-bind (executable durations machine far) (exact-times-program)
    (declare (ignore durations machine))
    (loop for (events until mark)
            in (flet ((at (name text) (cons name (player.base:parse-decimal-seconds text))))
                 (list (list (list (at 'ev-long "999999999.999999") (at 'ev-wake "4294967295.5"))
                             (player.base:parse-decimal-seconds "123456789012.000001")
                             "(:cut long :time 5294967296 ")
                       (list (list (at 'ev-stand "123456789012.000001") (at 'ev-long "123456789013"))
                             (player.base:parse-decimal-seconds "999999999999999.999999")
                             "(:event ev-stand :time 123456789012.000001)")
                       (list (list (at 'ev-wake "999999999999999.999999"))
                             1000000000000000
                             ":time 999999999999999.999999")))
          do (let ((lisp (lisp-timed-trace far nil events :until until))
                   (c++ (player.cpp::run-timed-c++-batch executable 1 far :events events :until until)))
               (is (equal lisp c++) "~A" (first-difference lisp c++))
               (is (find-if (lambda (line) (search mark line)) lisp) "no ~A in ~S" mark lisp)))))
