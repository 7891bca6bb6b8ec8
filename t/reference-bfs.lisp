;;;; reference-bfs.lisp

(in-package #:player-tests)
