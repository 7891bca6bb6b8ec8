;;;; package.lisp -- player.cpp: The C++ back end: a standalone controller to embed, built and run for the comparison tests.

(defpackage #:player.cpp
  (:use #:cl #:player.base #:player.spec #:player.planner #:player.ir)
  (:import-from #:alexandria
                #:when-let #:if-let #:ensure-list #:hash-table-keys
                #:with-gensyms #:once-only #:appendf #:read-file-into-string)
  (:documentation "The C++ back end: a standalone controller to embed, built and run for the comparison tests.")
  (:export
   #:*c++-compiler* #:*c++-flags* #:c++-identifier-text-p #:emit-c++ #:id #:run-c++-trace))
