;;;; emit-c++.lisp -- `player emit-c++`: the controller as standalone C++17.

(in-package #:player.cli)

(defmethod read-option-value ((type (eql :c++-identifier)) text option)
  ;; A file and namespace name: a C++ identifier, so it can neither inject
  ;; code nor lead out of --out.
  (unless (c++-identifier-text-p text)
    (bad-option-value option text "a C++ identifier (a letter, then letters, digits or _; not a keyword or a macro of the C headers)"))
  text)

(define-command "emit-c++" (file &key spec no-code out name namespace timed)
    (:summary "write NAME.hpp and NAME.cpp, a standalone C++17 controller"
     :arguments ("SPEC-FILE")
     :options ("--spec" "--no-code"
               ("--out" :string "DIR" "the directory to write into (required)")
               ("--name" :c++-identifier "NAME" "the files' base name" :default-text "the spec's name")
               ("--namespace" :c++-identifier "NS" "the C++ namespace" :default-text "NAME")
               ("--timed" :flag "" "also give the Controller the timed API: send_timed, advance and finish_events, with :when-busy policies, cuts, channels, timers and triggers"))
     :output "DIR/NAME.hpp and DIR/NAME.cpp; their paths on standard output")
  (unless out (usage-fail "emit-c++ needs --out DIR"))
  (let ((machine (plan-spec (choose-spec file spec :allow-code (not no-code)))))
    (format t "~{~A~%~}" (mapcar #'namestring (emit-c++ machine out :name name :namespace namespace :timed timed)))))
