;;;; cpp.lisp -- the C++ backend's row: Peedy's events per second through the
;;;; generated code (null presenter, -O2) beside the Lisp closures, and the
;;;; generated code's size.

(in-package #:player-bench)

(defparameter *c++-rounds* 400000
  "How many times the C++ benchmark plays all of Peedy's events.")

(defun c++-bench-main (namespace)
  "A main() playing every event in order, *C++-ROUNDS* times, from the declared initial state."
  (format nil "#include \"~A.hpp\"
#include <chrono>
#include <cstdio>
int main() {
  ~A::Presenter quiet;  // the defaults play nothing and report declared durations
  ~A::Controller agent(quiet);
  long ok = 0;
  const auto start = std::chrono::steady_clock::now();
  for (long round = 0; round < ~D; ++round)
    for (int e = 0; e < ~A::event_count; ++e) ok += agent.send(static_cast<~A::Event>(e));
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf(\"%.1f %ld\\n\", ~D.0 * ~A::event_count / seconds, ok);
  return 0;
}
" namespace namespace namespace *c++-rounds* namespace namespace *c++-rounds* namespace))

(defun count-lines (path)
  "Lines in the file PATH."
  (with-open-file (in path) (loop while (read-line in nil) count t)))

(defun bench-c++ (machine lisp-rate)
  "Add the C++ rows: events/s next to LISP-RATE, and lines of generated code."
  (let* ((directory (format nil "/tmp/player-bench-c++-~D/" (sb-unix:unix-getpid)))
         (files (player:emit-c++ machine directory :name "peedy" :namespace "peedy"))
         (main (merge-pathnames "bench_main.cpp" directory)))
    (with-open-file (out main :direction :output :if-exists :supersede)
      (write-string (c++-bench-main "peedy") out))
    (let ((compile (sb-ext:run-program "g++" (append player:*c++-flags*
                                                    (list "-o" "bench" "peedy.cpp" "bench_main.cpp"))
                                       :search t :directory directory :output nil :error nil)))
      (if (/= 0 (sb-ext:process-exit-code compile))
          (row "5. C++ events/s" "build failed" ">= 20 M/s" nil)
          (let* ((output (with-output-to-string (out)
                           (sb-ext:run-program (concatenate 'string directory "bench") '()
                                               :output out)))
                 (rate (with-input-from-string (in output) (read in))))
            (row "5. events/s, generated C++ (-O2), null presenter: all events in spec order"
                 (format-count rate) ">= 20 M/s" (>= rate 2d7))
            (when lisp-rate
              (row "   ratio C++ / Lisp closures (same mix)" (format-ratio (/ rate lisp-rate)) "" ""))
            (row (format nil "   generated code: peedy.hpp + peedy.cpp")
                 (format nil "~D lines" (reduce #'+ (mapcar #'count-lines files))) "" ""))))
    (sb-ext:run-program "rm" (list "-rf" directory) :search t)))
