;;;; test-language.lisp -- every form of the spec language, parsed and run.

(in-package #:player-tests)

(def-suite* language :in player-tests)

(test smoke-parses
  (with-spec (spec smoke (state-variable a boolean false)
                         (op set-a :add a)
                         (event ev :state a))
    (is (eq 'smoke (spec-name spec)))
    (let ((c (make-controller (compile-spec spec))))
      (is (eq t (send-event c 'ev)))
      (is (eq t (state-value c 'a))))))
