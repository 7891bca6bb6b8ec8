;;;; controls.lisp

(in-package #:player)
