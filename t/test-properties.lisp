;;;; test-properties.lisp

(in-package #:player-tests)
