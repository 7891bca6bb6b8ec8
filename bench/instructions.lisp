;;;; instructions.lisp -- the workload bench/instructions.sh counts under
;;;; valgrind: Peedy's events through a timed controller (half of them
;;;; preempting, as bench-timeline sends them) or through the whole-event API.
;;;; Instruction counts do not drift with the machine as times do, so they
;;;; compare two builds of the timeline where a timing cannot.

(in-package #:player-bench)

(defun instructions-workload (kind passes)
  "Play Peedy's 20,000-event stream once to warm up, then PASSES more times:
KIND :TIMED through a timed controller, :WHOLE through the whole-event API.
Nothing is garbage-collected meanwhile (the nursery is made large enough), so
the count is the work of the events alone."
  (setf (sb-ext:bytes-consed-between-gcs) (* 400 1024 1024))
  (let* ((machine (player:compile-spec (first (player:load-spec "specs/peedy.lisp"))))
         (stream (timed-stream machine 20000)))
    (flet ((pass ()
             (ecase kind
               (:timed (play-timed-stream (fresh-timed-controller machine) stream))
               (:whole (let ((controller (player:make-controller
                                          machine :presenter (player:make-null-presenter))))
                         (loop for (name) across stream
                               do (player:send-event controller name)))))))
      (pass)
      (loop repeat passes do (pass)))))
