;;;; test-errors.lisp

(in-package #:player-tests)
