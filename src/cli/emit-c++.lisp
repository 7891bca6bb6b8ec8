;;;; emit-c++.lisp -- `player emit-c++`: the controller as standalone C++17.

(in-package #:player)

(define-command "emit-c++" (file &key spec out name namespace)
    (:summary "write NAME.hpp and NAME.cpp, a standalone C++17 controller"
     :arguments ("SPEC-FILE")
     :options ("--spec"
               ("--out" :string "DIR" "the directory to write into (required)")
               ("--name" :string "NAME" "the files' base name" :default-text "the spec's name")
               ("--namespace" :string "NS" "the C++ namespace" :default-text "NAME"))
     :output "DIR/NAME.hpp and DIR/NAME.cpp; their paths on standard output")
  (unless out (usage-fail "emit-c++ needs --out DIR"))
  (format t "~{~A~%~}"
          (mapcar #'namestring
                  (emit-c++ (plan-spec (choose-spec file spec)) out :name name :namespace namespace))))
