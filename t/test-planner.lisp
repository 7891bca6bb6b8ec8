;;;; test-planner.lisp

(in-package #:player-tests)
