;;;; test-controller.lisp

(in-package #:player-tests)
