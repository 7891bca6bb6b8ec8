;;;; test-c++.lisp -- the C++ backend against the Lisp-closure backend: the
;;;; trace the generated C++ prints (RUN-C++-TRACE) must equal the Lisp
;;;; controller's, line for line, for Peedy and for random specs with runtime
;;;; numbers, time variables, labels, :if, :add/:sub and autoscripts. Also:
;;;; identifier mangling, independent instances in one program, deterministic
;;;; output and readable compiler errors. Hostile names, numbers at the edges
;;;; of 64 bits and huge times are in test-c++-hostile.lisp.
;;;;
;;;; Builds are cached by content in ~/.cache/player/c++/ (or $XDG_CACHE_HOME),
;;;; so only the first run pays for g++; the random specs are built two at a
;;;; time on threads before they are compared.

(in-package #:player-tests)

(def-suite* c++-backend :in player-tests)

;;; Comparing the two backends

(defun lisp-trace (machine initial-state events)
  "The Lisp backend's trace lines for EVENTS sent from INITIAL-STATE."
  (let ((controller (make-controller machine :initial-state initial-state)))
    (dolist (event events) (send-event controller event))
    (trace-of controller)))

(defun first-difference (lisp c++)
  "NIL when the line lists LISP and C++ are equal, else (INDEX LISP-LINE C++-LINE)
with \"<none>\" for a missing line."
  (loop for i from 0
        for a = (nth i lisp)
        for b = (nth i c++)
        while (or a b)
        unless (equal a b)
          return (list i (or a "<none>") (or b "<none>"))))

(defun compare-backends (machine initial-state events)
  "NIL when the two backends print the same trace, else a description of the first difference."
  (let ((lisp (lisp-trace machine initial-state events))
        (c++ (handler-case (run-c++-trace machine :initial-state initial-state :events events)
               (error (e) (return-from compare-backends (format nil "run-c++-trace: ~A" e))))))
    (destructuring-bind (&optional index lisp-line c++-line) (first-difference lisp c++)
      (when index
        (let ((*package* (find-package '#:player-user)))
          (format nil "from ~S after events ~S: trace line ~D differs~%    Lisp: ~A~%    C++:  ~A~%  (~D Lisp lines, ~D C++ lines)"
                  initial-state events (1+ index) lisp-line c++-line (length lisp) (length c++)))))))

(defmacro with-temporary-directory ((var) &body body)
  "Bind VAR to a fresh directory pathname under /tmp, deleted afterwards."
  `(let ((,var (pathname (format nil "/tmp/player-c++-test-~36R/" (random (expt 2 60) (make-random-state t))))))
     (ensure-directories-exist ,var)
     (unwind-protect (progn ,@body)
       (sb-ext:delete-directory ,var :recursive t))))

(defun file-bytes (path)
  "The contents of PATH as an octet vector."
  (with-open-file (in path :element-type '(unsigned-byte 8))
    (let ((bytes (make-array (file-length in) :element-type '(unsigned-byte 8))))
      (read-sequence bytes in)
      bytes)))

(defun file-first-line (path)
  (with-open-file (in path) (read-line in nil "")))

(defun run-g++ (directory arguments)
  "Run g++ with *C++-FLAGS* and ARGUMENTS in DIRECTORY: (VALUES EXIT-CODE STDERR)."
  (let ((err (make-string-output-stream)))
    (let ((process (sb-ext:run-program "g++" (append *c++-flags* arguments)
                                       :search t :output nil :error err
                                       :directory (namestring directory))))
      (values (sb-ext:process-exit-code process) (get-output-stream-string err)))))

(defun program-output-lines (program &rest arguments)
  "Run PROGRAM (a pathname) with ARGUMENTS: (VALUES EXIT-CODE LINES)."
  (let* ((out (make-string-output-stream))
         (process (sb-ext:run-program (namestring program) arguments :output out :error nil)))
    (values (sb-ext:process-exit-code process)
            (with-input-from-string (in (get-output-stream-string out))
              (loop for line = (read-line in nil) while line collect line)))))

(defun build-in-parallel (machines &key (threads 2))
  "Build the C++ driver of each of MACHINES (RUN-C++-TRACE with no events, which
fills the cache), THREADS at a time. Returns an alist (MACHINE . ERROR-TEXT) of the failures."
  (let ((queue (copy-list machines))
        (failures '())
        (lock (sb-thread:make-mutex :name "c++ builds")))
    (flet ((work ()
             (loop (let ((machine (sb-thread:with-mutex (lock) (pop queue))))
                     (unless machine (return))
                     (handler-case (run-c++-trace machine)
                       (error (e)
                         (let ((text (princ-to-string e)))
                           (sb-thread:with-mutex (lock) (push (cons machine text) failures)))))))))
      (if (find :sb-thread *features*)
          (mapc #'sb-thread:join-thread
                (loop repeat threads collect (sb-thread:make-thread #'work :name "c++ build")))
          (work)))
    failures))

;;; Peedy

(defparameter *peedy-initial-states*
  '(()
    ((alert . snore) (posture . sit))
    ((alert . awake) (posture . stand))
    ((posture . fly))
    ((wing-at-ear . t))
    ((alert . sleep) (posture . sit) (holding-note . t))
    ((wearing-phones . t) (music-playing . t))
    ((alert . awake) (posture . stand) (last-heard . 2.5))
    ((alert . snore) (posture . fly) (wing-at-ear . t) (holding-note . t)))
  "Initial states Peedy's events are played from, C++ against Lisp.")

(test c++-peedy-matches-lisp
  "Peedy's generated C++ compiles, and prints the Lisp trace for all 38 events in
order from several initial states, and for seeded random event sequences."
  (let* ((spec (peedy-spec))
         (machine (compile-spec spec))
         (events (event-names machine))
         (prng (make-rs-prng 35)))
    (is (= 38 (length events)))
    (finishes (run-c++-trace machine))
    (dolist (initial *peedy-initial-states*)
      (let ((problem (compare-backends machine initial events)))
        (is (null problem) "Peedy: ~A" problem)))
    (loop repeat 4
          for initial = (rs-pick prng *peedy-initial-states*)
          for sequence = (loop repeat 60 collect (rs-pick prng events))
          do (let ((problem (compare-backends machine initial sequence)))
               (is (null problem) "Peedy, random events: ~A" problem)))))

;;; Random specs with runtime variables, time variables and autoscripts

(defparameter *c++-random-seeds* (sweep-sample (loop for seed from 1 to 50 collect seed) 12)
  "The seeds of the random specs compared across backends (fixed, so failures
reproduce); 12 of them in the fast tier, each a program of its own in the cache.")

(defun describe-c++-problem (seed forms problem)
  "The failure message for random spec SEED."
  (let ((*package* (find-package '#:player-user))
        (*print-pretty* nil))
    (format nil "seed ~D: ~A~%  reproduce: (player-tests::check-c++-random-spec ~D)~%  spec:~{~%    ~S~}"
            seed problem seed forms)))

(defun c++-random-runs (seed machine model extras)
  "The (INITIAL-STATE EVENTS) runs compared for random spec SEED: the declared
initial state and two random ones, each with 25 random events."
  (let ((prng (make-rs-prng (+ 100000 seed)))
        (events (event-names machine)))
    (loop for i below 3
          collect (list (if (zerop i) '() (random-initial-state prng model extras))
                        (loop repeat 25 collect (rs-pick prng events))))))

(defun check-c++-random-spec (seed &key (build t))
  "Compare the backends on random spec SEED. Returns (VALUES PROBLEM RUNS
FAILED-EVENTS): a failure message or NIL, how many runs, and how many events failed."
  (multiple-value-bind (forms model extras) (c++-random-spec seed)
    (let ((name (rs-symbol "c++-random-~D" seed)))
      (handler-case
          (unwind-protect
               (let* ((spec (define-spec name forms :package (find-package '#:player-user)))
                      (machine (compile-spec spec))
                      (runs (c++-random-runs seed machine model extras))
                      (failed 0))
                 (when build (run-c++-trace machine))
                 (loop for (initial events) in runs
                       for problem = (compare-backends machine initial events)
                       do (incf failed (count-if (lambda (line) (search "(:fail " line))
                                                 (lisp-trace machine initial events)))
                       when problem
                         do (return-from check-c++-random-spec
                              (values (describe-c++-problem seed forms problem) (length runs) failed)))
                 (values nil (length runs) failed))
            (remove-spec name))
        (error (e)
          (values (describe-c++-problem seed forms (format nil "error: ~A" e)) 0 0))))))

(test c++-random-specs-match-lisp
  "For every random spec (runtime numbers, time variables, labels, :time, :if
with comparisons, :add/:sub, must-ask ops, macro-ops, autoscripts), the C++
trace equals the Lisp trace line for line, from the declared and from random
initial states, over random event sequences (some events fail)."
  (let ((start (get-internal-real-time))
        (prepared '()) (problems '()) (problem-count 0) (runs 0) (failed-events 0) (build-seconds 0))
    (unwind-protect
         (progn
           ;; Define and compile every spec here; only g++ runs on threads.
           (dolist (seed *c++-random-seeds*)
             (multiple-value-bind (forms model extras) (c++-random-spec seed)
               (handler-case
                   (let* ((spec (define-spec (rs-symbol "c++-random-~D" seed) forms
                                  :package (find-package '#:player-user))))
                     (push (list seed forms model extras (compile-spec spec)) prepared))
                 (error (e)
                   (incf problem-count)
                   (push (describe-c++-problem seed forms (format nil "error defining or compiling the spec: ~A" e))
                         problems)))))
           (setf prepared (nreverse prepared))
           (let ((build-start (get-internal-real-time))
                 (failures (build-in-parallel (mapcar #'fifth prepared) :threads 3)))
             (setf build-seconds (/ (float (- (get-internal-real-time) build-start)) internal-time-units-per-second))
             (loop for (seed forms model extras machine) in prepared
                   for build-failure = (cdr (assoc machine failures))
                   do (if build-failure
                          (progn (incf problem-count)
                                 (push (describe-c++-problem seed forms build-failure) problems))
                          (loop for (initial events) in (c++-random-runs seed machine model extras)
                                for problem = (compare-backends machine initial events)
                                do (incf runs)
                                   (incf failed-events
                                         (count-if (lambda (line) (search "(:fail " line))
                                                   (lisp-trace machine initial events)))
                                when problem
                                  do (incf problem-count)
                                     (push (describe-c++-problem seed forms problem) problems)
                                     (return))))))
      (dolist (seed *c++-random-seeds*) (remove-spec (rs-symbol "c++-random-~D" seed))))
    (setf *c++-statistics*
          (list :specs (length *c++-random-seeds*) :runs runs :failed-events failed-events
                :build-seconds build-seconds
                :seconds (/ (float (- (get-internal-real-time) start)) internal-time-units-per-second)))
    (is (>= (length *c++-random-seeds*) (sweep-count 50 12)))
    (is (plusp failed-events) "no event failed in any run")
    (is (zerop problem-count) "~D of ~D random specs print different traces in C++ and Lisp; the first:~{~%~%~A~}"
        problem-count (length *c++-random-seeds*)
        (let ((all (reverse problems))) (subseq all 0 (min 3 (length all)))))))

;;; Identifiers

(test c++-identifier-mangling
  "Names that are C++ keywords, names that differ only by punctuation, an event
named main compile, and the C++ behaves as Lisp does."
  (with-spec (spec mangling
               (state-variable new boolean false)
               (state-variable delete boolean true)
               (state-variable class string int (int return namespace))
               (state-variable wing-at-ear boolean false)
               (state-variable wing_at_ear boolean true)
               (state-variable wing+at+ear boolean false)
               (state-variable stat boolean false)
               (state-variable int integer 2)
               (state-variable return float 0.5)
               (time-variable namespace (main new))
               (op return :add new :duration 0.5)
               (op namespace :precond new :sub delete)
               (op int :precond (not delete) :add class.return)
               (op class :precond class.return :add class.namespace :duration 2)
               (op main :add wing-at-ear :must-ask true)
               (op wing_at_ear :precond wing-at-ear :add wing_at_ear :sub wing-at-ear)
               (op wing+at+ear :precond (and wing-at-ear wing_at_ear) :add wing+at+ear)
               (op delete :add (delete stat) :sub new)
               (macro-op new :precond (not wing+at+ear) :add wing+at+ear :seq (:op main :op wing_at_ear))
               (autoscript class return (this))
               (autoscript wing+at+ear true (operator))
               (autoscript stat true (std))
               (event main :state (and new (not delete)) :op int)
               (event new :add wing+at+ear :add (int 3) :sub (return 0.25))
               (event delete :if ((> int 2) :sub wing_at_ear :add stat))
               (event class :state class.namespace :label int :time (+ (label int) 1.5) :op main)
               (event int :op new)
               (event wing-at-ear :op main :op wing_at_ear)
               (event wing_at_ear :op wing+at+ear :op delete)
               (event wing+at+ear :if ((> (now) (+ namespace 1)) :op return)))
    (let* ((machine (compile-spec spec))
           (events (event-names machine))
           (prng (make-rs-prng 7)))
      (is (= 8 (length events)))
      (is (null (handler-case (progn (run-c++-trace machine) nil) (error (e) e))))
      (dolist (initial '(()
                         ((new . t) (delete . nil))
                         ((class . namespace) (wing-at-ear . t) (wing_at_ear . nil) (int . 5))
                         ((stat . t) (wing+at+ear . t) (return . 1.5) (namespace . 2))))
        (let ((problem (compare-backends machine initial events)))
          (is (null problem) "mangling, every event: ~A" problem))
        (let* ((sequence (loop repeat 30 collect (rs-pick prng events)))
               (problem (compare-backends machine initial sequence)))
          (is (null problem) "mangling, random events: ~A" problem))))))

(test c++-variables-named-like-controller-members
  "Variables named state, clock, state-line and failed-goal (the names of
Controller's own members) compile, and the C++ behaves as Lisp does."
  (with-spec (spec members
               (state-variable state boolean false)
               (state-variable clock boolean false)
               (state-variable state-line string a (a b))
               (state-variable failed-goal integer 0)
               (op tick :add (state clock state-line.b))
               (autoscript state true (run))
               (event ev :op tick :add (failed-goal 1)))
    (let ((problem (compare-backends (compile-spec spec) '() '(ev ev))))
      (is (null problem) "~A" problem))))

;;; Two controllers in one program

(defparameter *two-instances-main*
  "#include \"twins.hpp\"

#include <cstdio>

namespace {
class Quiet : public twins::Presenter {};
}  // namespace

int main() {
  Quiet presenter;
  twins::State asleep = twins::initial_state();
  if (!twins::assign(asleep, \"mood\", \"asleep\")) return 3;
  twins::Controller a(presenter, asleep);
  twins::Controller b(presenter);
  twins::Event wake, poke;
  if (!twins::find_event(\"ev-wake\", wake) || !twins::find_event(\"ev-poke\", poke)) return 4;
  a.send(wake);
  b.send(poke);
  b.send(twins::Event::ev_poke);
  std::printf(\"%s\\n%s\\n\", a.state_line().c_str(), b.state_line().c_str());
  return 0;
}
"
  "A program with two controllers of one machine, sent different events.")

(test c++-two-controllers-keep-separate-states
  "Two Controllers of one generated machine in one program (with a presenter
that overrides nothing) have their own states: each prints the state a Lisp
controller reaches on the same events."
  (with-spec (spec twins
               (state-variable mood string awake (asleep awake happy))
               (state-variable pokes integer 0)
               (op wake-up :precond mood.asleep :add mood.awake)
               (op cheer :precond mood.awake :add mood.happy)
               (autoscript mood happy (smile))
               (event ev-wake :state mood.awake)
               (event ev-poke :add (pokes 1) :op cheer))
    (let ((machine (compile-spec spec)))
      (with-temporary-directory (directory)
        (emit-c++ machine directory)
        (with-open-file (out (merge-pathnames "main.cpp" directory) :direction :output)
          (write-string *two-instances-main* out))
        (multiple-value-bind (code errors) (run-g++ directory '("main.cpp" "twins.cpp" "-o" "twins"))
          (is (eql 0 code) "g++ failed: ~A" errors)
          (when (eql 0 code)
            (flet ((final-state (initial events)
                     (car (last (lisp-trace machine initial events)))))
              (multiple-value-bind (status lines) (program-output-lines (merge-pathnames "twins" directory))
                (is (eql 0 status))
                (is (equal (list (final-state '((mood . asleep))  '(ev-wake))
                                 (final-state '() '(ev-poke ev-poke)))
                           lines))
                (is (equal '("(:state (mood . awake) (pokes . 0))"
                             "(:state (mood . happy) (pokes . 2))")
                           lines))))))))))

;;; Determinism

(test c++-output-is-deterministic
  "EMIT-C++ writes byte-identical files for the same spec, each opening with a
comment naming the spec."
  (let ((first-machine (compile-spec (peedy-spec)))
        (second-machine (compile-spec (peedy-spec))))
    (with-temporary-directory (one)
      (with-temporary-directory (two)
        (let ((files-one (emit-c++ first-machine one))
              (files-two (emit-c++ second-machine two)))
          (is (equal '("peedy.hpp" "peedy.cpp") (mapcar #'file-namestring files-one)))
          (is (equal (mapcar #'file-namestring files-one) (mapcar #'file-namestring files-two)))
          (loop for a in files-one
                for b in files-two
                do (is (equalp (file-bytes a) (file-bytes b)) "~A differs between two runs" (file-namestring a))
                   (is (search "generated by Player from spec peedy" (file-first-line a))
                       "~A opens with ~S" (file-namestring a) (file-first-line a)))
          ;; Emitting again into the same directory gives the same bytes too.
          (let ((before (mapcar #'file-bytes files-one)))
            (emit-c++ first-machine one)
            (is (equalp before (mapcar #'file-bytes files-one)))))))))

;;; Compiler errors

(test c++-compile-errors-are-clear
  ":c++ text that is not C++ makes RUN-C++-TRACE signal a PLAYER-ERROR saying
g++ failed on the generated code, with the compiler's message."
  (with-spec (spec broken-c++
               (state-variable lit boolean false)
               (op light :add lit)
               (autoscript lit true (glow))
               (event ev-light :c++ "this is not C++;" :op light))
    (let ((condition (handler-case (progn (run-c++-trace (compile-spec spec) :events '(ev-light)) nil)
                       (player-error (e) e))))
      (is (typep condition 'player-error))
      (when condition
        (let ((message (princ-to-string condition)))
          (is (eql 0 (search "g++ failed on the generated code" message)) "message: ~A" message)
          (is (search "error:" message) "no compiler message in: ~A" message)
          (is (search "broken_c.cpp" message) "the message does not name the file: ~A" message))))))

;;; Specs that once failed to build

(test c++-spec-without-autoscripts-compiles
  "A spec without autoscripts builds with -Werror (Controller::transition's TIME
parameter must not be unused) and behaves as in Lisp."
  (with-spec (spec door
               (state-variable open boolean false)
               (state-variable locked boolean true)
               (op unlock :precond locked :sub locked)
               (op open-door :precond (not locked) :add open)
               (event ev-enter :state open))
    (let ((problem (compare-backends (compile-spec spec) '() '(ev-enter ev-enter))))
      (is (null problem) "~A" problem))))

(test c++-comparison-on-an-integer-enumeration-compiles
  "An :if comparing a plannable integer variable builds with -Werror
(-Warray-bounds on kValues_...[field_index(...)]) and behaves as in Lisp."
  (with-spec (spec gears
               (state-variable v0 boolean false)
               (state-variable gear integer 1 (1 2 3))
               (autoscript gear 3 (p1))
               (event e1 :add gear.3)
               (event e2 :if ((/= gear gear) :add gear.2) :if ((> gear 2) :add v0)))
    (let ((problem (compare-backends (compile-spec spec) '() '(e2 e1 e2))))
      (is (null problem) "~A" problem))))

(test c++-missing-compiler-names-the-debian-package
  (with-spec (spec no-compiler (state-variable on boolean false) (op switch-on :add on)
                               (event ev :state on) (event ev-2 :c++ "/* unique to this test */"))
    (let* ((player:*c++-compiler* "g++-that-does-not-exist")
           (e (handler-case (progn (run-c++-trace (compile-spec spec) :events '(ev)) nil)
                (player-error (e) e))))
      (is (typep e 'player-error))
      (is (search "g++-that-does-not-exist is not installed; install the Debian package g++"
                  (princ-to-string e))))))
