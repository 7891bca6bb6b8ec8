;;;; test-cli.lisp

(in-package #:player-tests)
