;;;; cpp.lisp -- the C++ backend's rows: Peedy's events per second through the
;;;; generated code (null presenter, -O2) beside the Lisp closures, the same
;;;; events on a Peedy whose state spans two 64-bit words, and the generated
;;;; code's size.

(in-package #:player-bench)

(defparameter *c++-rounds* 400000
  "How many times one run of the C++ benchmark plays all of Peedy's events.")

(defparameter *c++-runs* 7
  "How many runs of the C++ benchmark; the fastest is reported. The machine
is shared, so a run can only be slowed down by others: the best run is the
one that measured the code.")

(defparameter *c++-target* 5d7
  "Issue 13's target for the generated C++: 50 M events/s.")

(defun c++-bench-main (namespace)
  "A main() playing every event in order, ROUNDS times (its argument, by
default *C++-ROUNDS*), from the declared initial state; it prints the events
per second and how many succeeded."
  (format nil "#include \"~A.hpp\"
#include <chrono>
#include <cstdio>
#include <cstdlib>
int main(int argc, char** argv) {
  ~A::Presenter quiet;  // the defaults play nothing and report declared durations
  ~A::Controller agent(quiet);
  const long rounds = argc > 1 ? std::atol(argv[1]) : ~D;
  long ok = 0;
  const auto start = std::chrono::steady_clock::now();
  for (long round = 0; round < rounds; ++round)
    for (int e = 0; e < ~A::event_count; ++e) ok += agent.send(static_cast<~A::Event>(e));
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf(\"%.1f %ld\\n\", static_cast<double>(rounds) * ~A::event_count / seconds, ok);
  return 0;
}
" namespace namespace namespace *c++-rounds* namespace namespace namespace))

(defun count-lines (path)
  "Lines in the file PATH."
  (with-open-file (in path) (loop while (read-line in nil) count t)))

(defun build-c++-bench (machine directory name)
  "Emit MACHINE's C++ as NAME into DIRECTORY with the benchmark's main() and
compile it: (VALUES EXECUTABLE FILES), or NIL when g++ fails."
  (let ((files (player:emit-c++ machine directory :name name :namespace name))
        (main (merge-pathnames (format nil "~A_bench.cpp" name) directory)))
    (with-open-file (out main :direction :output :if-exists :supersede)
      (write-string (c++-bench-main name) out))
    (let ((compile (sb-ext:run-program "g++" (append player:*c++-flags*
                                                    (list "-o" name (file-namestring (second files))
                                                          (file-namestring main)))
                                       :search t :directory directory :output nil :error nil)))
      (when (zerop (sb-ext:process-exit-code compile))
        (values (merge-pathnames name directory) files)))))

(defun c++-rates (executable)
  "Events per second of *C++-RUNS* runs of the benchmark EXECUTABLE."
  (loop repeat *c++-runs*
        collect (let ((output (with-output-to-string (out)
                                (sb-ext:run-program (namestring executable) '() :output out))))
                  (with-input-from-string (in output) (read in)))))

(defun wide-peedy (spec bits)
  "Peedy (SPEC) with a variable of BITS values declared before his own, which
no op or event touches: his fields then lie across a 64-bit word boundary.
Defined as the spec PEEDY-WIDE."
  (let* ((forms (player.spec::spec-forms spec))
         (at (position-if (lambda (form) (and (consp form) (string= (symbol-name (first form)) "STATE-VARIABLE")))
                          forms))
         (values (loop for i below bits collect (intern (format nil "W~D" i) :player-user)))
         (padding `(,(intern "STATE-VARIABLE" :player-user) ,(intern "PADDING" :player-user)
                    ,(intern "STRING" :player-user) ,(first values) ,values)))
    (player:define-spec 'peedy-wide (append (subseq forms 0 at) (list padding) (subseq forms at))
                        :source-file (player::spec-source-file spec)
                        :package (player.spec::spec-package spec))))

(defun bench-c++-wide (spec directory one-word-rate)
  "The row of Peedy's events on a state of two words, next to ONE-WORD-RATE."
  (let* ((wide (wide-peedy spec 58))
         (machine (player:compile-spec wide))
         (bits (player.spec::spec-bit-count wide))
         (executable (build-c++-bench machine directory "peedy_wide")))
    (if (null executable)
        (row "5. events/s, generated C++, Peedy in two words" "build failed" "" "")
        (let ((rate (reduce #'max (c++-rates executable))))
          (row (format nil "5. events/s, generated C++, Peedy with a 58-value variable (~D bits, ~D words)"
                       bits (ceiling bits 64))
               (format-count rate) "" "")
          (when one-word-rate
            (row "   ratio two words / one word (same events)" (format-ratio (/ rate one-word-rate)) "" ""))))
    (player:remove-spec 'peedy-wide)))

(defun bench-c++ (machine lisp-rate)
  "Add the C++ rows: events/s next to LISP-RATE, the same on a two-word
state, and lines of generated code."
  (let ((directory (format nil "/tmp/player-bench-c++-~D/" (sb-posix:getpid))))
    (ensure-directories-exist directory)
    (multiple-value-bind (executable files) (build-c++-bench machine directory "peedy")
      (if (null executable)
          (row "5. C++ events/s" "build failed" ">= 50 M/s" nil)
          (let* ((rates (c++-rates executable))
                 (rate (reduce #'max rates)))
            (row "5. events/s, generated C++ (-O2), null presenter: all events in spec order"
                 (format-count rate) ">= 50 M/s" (>= rate *c++-target*))
            (note "C++ events/s: the fastest of ~D runs of ~D events (median ~A: the machine is shared)"
                  *c++-runs* (* *c++-rounds* (length (player:event-names machine)))
                  (format-count (median rates)))
            (when lisp-rate
              (row "   ratio C++ / Lisp closures (same mix)" (format-ratio (/ rate lisp-rate)) "" ""))
            (row (format nil "   generated code: peedy.hpp + peedy.cpp")
                 (format nil "~D lines" (reduce #'+ (mapcar #'count-lines files))) "" "")
            (bench-c++-wide (player:machine-spec machine) directory rate))))
    (sb-ext:run-program "rm" (list "-rf" directory) :search t)))
