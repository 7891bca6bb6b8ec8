;;;; random-specs.lisp

(in-package #:player-tests)
