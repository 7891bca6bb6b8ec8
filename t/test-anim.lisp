;;;; test-anim.lisp

(in-package #:player-tests)
