;;;; arbitration.lisp

(in-package #:player)
