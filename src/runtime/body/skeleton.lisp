;;;; skeleton.lisp

(in-package #:player)
