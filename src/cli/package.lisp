;;;; package.lisp -- player.cli: The command line: one table of commands that parsing, help and the docs read.

(defpackage #:player.cli
  (:use #:cl #:player.base #:player.spec #:player.planner #:player.ir #:player.inspect #:player.compose #:player.logic #:player.control #:player.cpp #:player.speech #:player.model #:player.body #:player.ode #:player.physics #:player.performance #:player.render #:player.cast #:player.export #:player.dialogue #:player.traces #:player.rig)
  (:import-from #:alexandria
                #:when-let #:if-let #:ensure-list #:hash-table-keys
                #:with-gensyms #:once-only #:appendf #:read-file-into-string)
  (:documentation "The command line: one table of commands that parsing, help and the docs read.")
  (:export
   #:main #:usage-error))
