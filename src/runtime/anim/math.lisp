;;;; math.lisp

(in-package #:player)
