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

;;;# Per function: the map bench/instructions-profile.sh attributes counts with

(defun write-code-map (path)
  "Write to PATH one line per compiled function in the image: its start
address and length in hex and its name (perf's map format).  Addresses of
code saved in a core are the same in every process started from it."
  (with-open-file (out path :direction :output :if-exists :supersede)
    (sb-vm::map-allocated-objects
     (lambda (object type size)
       (when (= type sb-vm:code-header-widetag)
         (let ((count (sb-kernel:code-n-entries object)))
           (dotimes (i count)
             (let* ((fun (sb-kernel:%code-entry-point object i))
                    (start (sb-kernel:get-lisp-obj-address fun))
                    (end (if (< (1+ i) count)
                             (sb-kernel:get-lisp-obj-address (sb-kernel:%code-entry-point object (1+ i)))
                             (+ (logandc2 (sb-kernel:get-lisp-obj-address object) sb-vm:lowtag-mask) size))))
               (format out "~X ~X ~A~%" start (- end start)
                       (substitute #\_ #\Space (princ-to-string (sb-kernel:%simple-fun-name fun)))))))))
     :all)))

(defun write-anchor (path)
  "Write to PATH where ADVANCE-TIMELINE's code is in this process, in hex: the
same function's address in two processes tells how far the heap moved."
  (with-open-file (out path :direction :output :if-exists :supersede)
    (format out "~X" (sb-kernel:get-lisp-obj-address #'player.control::advance-timeline))))

(defun profiled-workload (directory)
  "The timed workload for callgrind, which starts with counting off: warm up,
write DIRECTORY/anchor (where ADVANCE-TIMELINE is in this process: under
valgrind the heap is moved) and DIRECTORY/ready, wait while the script turns
counting on, play one pass, write DIRECTORY/done, and wait to be dumped."
  (setf (sb-ext:bytes-consed-between-gcs) (* 400 1024 1024))
  (let* ((machine (player:compile-spec (first (player:load-spec "specs/peedy.lisp"))))
         (stream (timed-stream machine 20000)))
    (flet ((touch (name &optional (text ""))
             (with-open-file (out (merge-pathnames name directory) :direction :output :if-exists :supersede)
               (write-string text out))))
      (play-timed-stream (fresh-timed-controller machine) stream)
      (write-anchor (merge-pathnames "anchor" directory))
      (touch "ready")
      (sleep 20)
      (play-timed-stream (fresh-timed-controller machine) stream)
      (touch "done")
      (sleep 20))))
