;;;; test-body.lisp

(in-package #:player-tests)
