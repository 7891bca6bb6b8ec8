;;;; test-peedy.lisp

(in-package #:player-tests)
