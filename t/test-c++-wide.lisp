;;;; test-c++-wide.lisp -- issue 13's generated C++: lean compiled events, and
;;;; states wider than 64 bits: the one-hot state held in several 64-bit words
;;;; (src/cpp/cpp-words.lisp) must print the Lisp traces, whole-event and
;;;; timed, line for line. Two fixed specs put a 70-value field across the
;;;; boundary of two words, with autoscripts, :if tests and goals on both
;;;; sides, and fill three words; random specs with large enumerations
;;;; (RANDOM-SPEC's :ENUM-VALUES) have 64 (one word, the edge) to 149 bits.
;;;; Every spec is built into one of two programs (BUILD-TIMED-C++-BATCH, on
;;;; two threads) before anything is compared: g++ is the cost.

(in-package #:player-tests)

(def-suite* c++-wide :in c++-backend)

;;; The specs

(defun test-symbol (control &rest arguments)
  "A symbol of this package named by CONTROL and ARGUMENTS (upcased)."
  (intern (string-upcase (apply #'format nil control arguments)) '#:player-tests))

(defun numbered-symbols (prefix count)
  "PREFIX0 ... PREFIX<COUNT-1>, symbols of this package."
  (loop for i below count collect (test-symbol "~A~D" prefix i)))

(defun wide-straddle-forms ()
  "A spec of 81 one-hot bits whose 70-value SPOT occupies bits 6 to 75, across
the boundary of words 0 and 1 (p57 is bit 63, p58 bit 64), with an integer
enumeration beyond it, autoscripts on both sides, channels and cuts."
  `((state-variable flag boolean false)
    (state-variable busy boolean false)
    (state-variable note boolean true)
    (state-variable spot string p0 ,(numbered-symbols "p" 70))
    (state-variable lit boolean false)
    (state-variable gear integer 1 (1 2 3))
    (state-variable count integer 0)
    (time-variable heard (go-far late))
    (op hop :precond (not flag) :add flag :duration 0.5 :interrupt :anytime :if-cut (:sub flag))
    ,@(loop for i in '(0 1 2 56 57 58 59 63 64 65 69)
            collect `(op ,(test-symbol "go~D" i) :precond flag :add ,(test-symbol "spot.p~D" i) :sub flag
                         :duration 1 :interrupt (:at 0.5)))
    (op glow :precond spot.p69 :add lit :duration 0.75 :channels ("light"))
    (op dim :precond lit :sub lit :channels ("light"))
    (op shift :add gear.3 :duration 0.25 :channels ("gears"))
    (op rest :add busy :duration 2 :interrupt :anytime :if-cut (:add spot.p58))
    (macro-op trip :precond (not lit) :add (spot.p63 note) :seq (:op hop :op go64 :op hop :op go56))
    (autoscript spot p57 (near))
    (autoscript spot p58 (past))
    (autoscript spot p69 (end))
    (autoscript lit true (shine))
    (autoscript gear 3 (top-gear))
    (event go-far :state spot.p65 :add (count 1))
    (event go-near :state spot.p57)
    (event go-edge :state (or spot.p57 spot.p58) :if ((or spot.p57 spot.p58) :add lit))
    (event light-up :op glow :if ((> gear 2) :op dim))
    (event trip (:when-busy :interleave) :op trip)
    (event shift :op shift :if ((and spot.p65 (> count 0)) :add spot.p0))
    (event rest :op rest :sub busy)
    (event back :state (and (not flag) spot.p0 (not lit)))
    (event late :if ((> (now) (+ heard 2)) :state spot.p69))))

(defun wide-three-word-forms ()
  "A spec of 142 one-hot bits: ROW in bits 0 to 69, COL in 70 to 139 (c57 is
bit 127, the last of word 1; c58 bit 128, the first of word 2), UP after."
  `((state-variable row string r0 ,(numbered-symbols "r" 70))
    (state-variable col string c0 ,(numbered-symbols "c" 70))
    (state-variable up boolean false)
    (op lift :precond (not up) :add up)
    (op drop :precond up :sub up :duration 0.5)
    ,@(loop for i in '(0 5 63 64 69)
            collect `(op ,(test-symbol "row~D" i) :precond up :add ,(test-symbol "row.r~D" i)))
    ,@(loop for i in '(0 1 57 58 69)
            collect `(op ,(test-symbol "col~D" i) :precond (not up) :add ,(test-symbol "col.c~D" i)))
    (autoscript col c58 (at-58))
    (autoscript col c57 (at-57))
    (autoscript row r64 (at-64))
    (event corner :state (and row.r69 col.c69))
    (event origin :state (and row.r0 col.c0 (not up)))
    (event mid :state (and row.r64 col.c58))
    (event edge :state (and row.r63 col.c57))
    (event either :state (or row.r5 col.c57) :if ((and row.r5 (not up)) :add col.c1))))

(defparameter *wide-random-seeds* '(21 12 19 20)
  "Random wide specs (see WIDE-RANDOM-SPEC): 64 bits (one word, the edge), 67,
128 (two full words) and 149 bits (three words).")

(defun wide-enum-values (seed)
  "The values of random wide spec SEED's enumerations: 24 to 70 of them."
  (mapcar #'string (numbered-symbols "x" (+ 24 (mod (* seed 7) 47)))))

(defun wide-random-spec (seed)
  "(VALUES FORMS MODEL EXTRAS) of random wide spec SEED: C++-TIMELINE-SPEC's
timed random spec with enumerations of WIDE-ENUM-VALUES."
  (c++-timeline-spec seed :enum-values (wide-enum-values seed) :enum-probability 0.5
                          :max-variables 7 :max-states 60000))

;;; Building

(defstruct (wide-case (:conc-name wide-))
  "One spec the suite compares: its MACHINE, how to draw initial states, and
the RUNNER functions of its controller in a built program."
  name machine initial-states whole timed)

(defun wide-fixed-case (name forms initial-states)
  "The case of a fixed spec NAME of FORMS (defined in this package)."
  (make-wide-case :name (string-downcase name)
                  :machine (machine-of-forms name forms (find-package '#:player-tests))
                  :initial-states (lambda (prng) (declare (ignore prng)) initial-states)))

(defun wide-random-case (seed)
  "The case of random wide spec SEED."
  (multiple-value-bind (forms model extras) (wide-random-spec seed)
    (make-wide-case :name (format nil "wide random spec ~D" seed)
                    :machine (machine-of-forms (rs-symbol "c++-wide-~D" seed) forms
                                               (find-package '#:player-user))
                    :initial-states (lambda (prng)
                                      (list '() (random-initial-state prng model extras)
                                            (random-initial-state prng model extras))))))

(defun build-wide-batch (cases)
  "Build CASES into one program and give each its runners; NIL, or the error text."
  (handler-case
      (let ((executable (player.cpp::build-timed-c++-batch (mapcar #'wide-machine cases))))
        (loop for case in cases
              for index from 0
              do (let ((index index) (machine (wide-machine case)))
                   (setf (wide-whole case)
                         (lambda (initial events)
                           (player.cpp::run-whole-c++-batch executable index machine
                                                        :initial-state initial :events events))
                         (wide-timed case)
                         (lambda (initial events until when-busy)
                           (player.cpp::run-timed-c++-batch executable index machine
                                                        :initial-state initial :events events
                                                        :until until :when-busy when-busy)))))
        nil)
    (error (e) (princ-to-string e))))

(defvar *wide-cases* nil "The suite's cases, built once per session by ENSURE-WIDE-CASES.")
(defvar *wide-build-problems* '() "Why a program of the suite could not be built.")

(defun ensure-wide-cases ()
  "Define every spec of the suite and build them into two programs, on two threads."
  (unless *wide-cases*
    (let* ((start (get-internal-real-time))
           (cases (append (list (wide-fixed-case 'c++-wide-straddle (wide-straddle-forms)
                                                 '(() ((spot . p57) (flag . t)) ((spot . p58) (lit . t) (gear . 3))
                                                   ((spot . p64) (count . 2) (heard . 1))))
                                 (wide-fixed-case 'c++-wide-three (wide-three-word-forms)
                                                  '(() ((row . r63) (col . c57)) ((row . r64) (col . c58) (up . t))
                                                    ((col . c69) (up . t)))))
                           (mapcar #'wide-random-case *wide-random-seeds*)))
           (halves (list (loop for case in cases for i from 0 when (evenp i) collect case)
                         (loop for case in cases for i from 0 when (oddp i) collect case))))
      (setf *wide-build-problems*
            (remove nil (mapcar #'sb-thread:join-thread
                                (mapcar (lambda (half)
                                          (sb-thread:make-thread (lambda () (build-wide-batch half))
                                                                 :name "wide c++ build"))
                                        halves))))
      (format t "~&  c++ wide: ~D specs built in ~,1F s~%" (length cases)
              (/ (float (- (get-internal-real-time) start)) internal-time-units-per-second))
      (setf *wide-cases* cases)))
  *wide-cases*)

;;; Comparing

(defun compare-whole-with-runner (case initial events)
  "NIL when CASE's C++ prints the Lisp whole-event trace of EVENTS, else the first difference."
  (let ((lisp (lisp-trace (wide-machine case) initial events))
        (c++ (handler-case (funcall (wide-whole case) initial events)
               (error (e) (return-from compare-whole-with-runner (format nil "C++ signals: ~A" e))))))
    (destructuring-bind (&optional index lisp-line c++-line) (first-difference lisp c++)
      (when index
        (let ((*package* (find-package '#:player-tests)))
          (format nil "from ~S after events ~S: trace line ~D differs~%    Lisp: ~A~%    C++:  ~A"
                  initial events (1+ index) lisp-line c++-line))))))

(defun wide-case-problems (case)
  "Whole-event and timed comparisons of CASE: (VALUES PROBLEMS RUNS FAILED-EVENTS)."
  (let* ((machine (wide-machine case))
         (events (event-names machine))
         (prng (make-rs-prng (sxhash (wide-name case))))  ; SXHASH of a string: its characters'
         (problems '()) (runs 0) (failed 0))
    (dolist (initial (funcall (wide-initial-states case) prng))
      (let ((sequence (loop repeat 30 collect (rs-pick prng events))))
        (incf runs)
        (incf failed (count-if (lambda (line) (search "(:fail " line)) (lisp-trace machine initial sequence)))
        (let ((problem (compare-whole-with-runner case initial sequence)))
          (when problem (push (format nil "~A, whole events: ~A" (wide-name case) problem) problems))))
      (loop repeat 2
            do (destructuring-bind (entries until when-busy &rest counts)
                   (random-timed-scenario prng machine initial :bounded t)
                 (declare (ignore counts))
                 (incf runs)
                 (let ((problem (compare-timed-backends machine initial entries :until until
                                                        :when-busy when-busy :runner (wide-timed case))))
                   (when problem (push (format nil "~A, timed: ~A" (wide-name case) problem) problems))))))
    (values (nreverse problems) runs failed)))

(test c++-wide-state-layout
  "A spec of more than 64 one-hot bits gets kStateWords words of StateBits
(std::array); one of at most 64, Peedy's, keeps one std::uint64_t."
  (flet ((header (forms)
           (let ((machine (machine-of-forms 'c++-wide-layout forms (find-package '#:player-tests))))
             (player.cpp::c++-sources machine "w" "w"))))
    (let ((wide (header (wide-three-word-forms)))
          (peedy (player.cpp::c++-sources (plan-spec (peedy-spec)) "peedy" "peedy")))
      (is (search "constexpr int kStateWords = 3;" wide))
      (is (search "using StateBits = std::array<std::uint64_t, kStateWords>;" wide))
      (is (search "constexpr int kStateWords = 1;" peedy))
      (is (search "using StateBits = std::uint64_t;" peedy)))))

(test c++-wide-specs-match-lisp
  "Specs of 64 to 149 one-hot bits (fields across word boundaries, three
words) print the Lisp trace in C++, whole events from several initial states
and random timed scenarios alike."
  (let ((cases (ensure-wide-cases))
        (problems '()) (runs 0) (failed 0))
    (is (null *wide-build-problems*) "~{~A~^~%~}" *wide-build-problems*)
    (unless *wide-build-problems*
      (dolist (case cases)
        (multiple-value-bind (found case-runs case-failed) (wide-case-problems case)
          (setf problems (append problems found))
          (incf runs case-runs)
          (incf failed case-failed))))
    (is (plusp failed) "no event failed in any run")
    (is (>= runs (* 3 (length cases))))
    (is (null problems) "~D comparisons differ; the first:~{~%~%~A~}"
        (length problems) (subseq problems 0 (min 3 (length problems))))
    (is (<= 4 (count-if (lambda (case)
                          (> (player.cpp::state-word-count (machine-spec (wide-machine case))) 1))
                        cases)))))

;;; Lean events

(defun c++-procedures (source prefix)
  "The texts of SOURCE's Controller procedures whose names start with PREFIX."
  (let ((opening (format nil "int Controller::~A" prefix)))
    (loop for start = (search opening source) then (search opening source :start2 end)
          for end = (and start (+ (search (format nil "~%}~%") source :start2 start) 3))
          while start
          collect (subseq source start end))))

(test c++-compiled-events-are-mask-tests-and-calls
  "Peedy's whole-event procedures (events, goals, ops) allocate nothing and
touch no string: an event is mask tests, stores and the presenter's calls.
An op whose effects no autoscript watches changes the state with one store."
  (let* ((source (nth-value 1 (player.cpp::c++-sources (plan-spec (peedy-spec)) "peedy" "peedy")))
         (procedures (mapcan (lambda (prefix) (c++-procedures source prefix)) '("ev_" "achieve_" "op_"))))
    (is (< 60 (length procedures)))
    (let ((offenders (loop for procedure in procedures
                           for word = (find-if (lambda (word) (search word procedure))
                                               '("std::string" "new " "make_shared" "std::vector"
                                                 "format_number" "field_index"))
                           when word collect (format nil "~A in:~%~A" word procedure))))
      (is (null offenders) "~D procedures allocate or read strings; the first: ~A"
          (length offenders) (first offenders)))
    (let ((search (first (c++-procedures source "op_search("))))
      (is (= 1 (count-occurrences "state_.bits = " search)) "op_search: ~A" search)
      (is (not (search "autoscript" search)) "op_search: ~A" search))))
