;;;; timeline.lisp -- issue 12's figures: events per second through a timed
;;;; controller when half the events interrupt the one playing, and what
;;;; ADVANCE costs per item it presents.

(in-package #:player-bench)

(defun timed-stream (machine count &key (seed 12))
  "COUNT (EVENT . INTERRUPTS-P) pairs drawn from MACHINE's events with SEED:
about half arrive while the previous event plays and preempt it."
  (let ((names (coerce (player:event-names machine) 'simple-vector))
        (*random-state* (sb-ext:seed-random-state seed)))
    (coerce (loop repeat count
                  collect (cons (svref names (random (length names))) (zerop (random 2))))
            'simple-vector)))

(defun play-timed-stream (controller stream)
  "Send STREAM to timed CONTROLLER: an interrupting event 0.3 s after now, by
:preempt; the others once everything before has finished."
  (declare (simple-vector stream))
  (loop for (name . interrupts) across stream
        do (if interrupts
               (player:send-event controller name :at (+ (player:controller-time controller) 0.3d0)
                                                  :when-busy :preempt)
               (progn (player:finish-events controller)
                      (player:send-event controller name))))
  (player:finish-events controller))

(defun fresh-timed-controller (machine)
  "A timed controller of MACHINE on a null presenter, its timers disarmed (so
only the stream's events play)."
  (let* ((controller (player:make-controller machine :timed t :presenter (player:make-null-presenter)))
         (timeline (player.control::controller-timeline controller)))
    (dolist (state (player.control::timeline-timers timeline))
      (let ((item (player.control::timer-state-item state)))
        (when item (setf (player.control::agenda-item-status item) :cancelled))))
    (setf (player.control::timeline-timers timeline) '())
    controller))

(defun bench-timeline (machine)
  "Rows: timed events/s with half interrupting, and ADVANCE's cost per due item."
  (let* ((stream (timed-stream machine 20000))
         (items 0)
         (seconds (seconds-per-call
                   (lambda ()
                     (let ((controller (fresh-timed-controller machine)))
                       (play-timed-stream controller stream)
                       (setf items (player.control::timeline-seq (player.control::controller-timeline controller)))))
                   :batches 5 :batch-seconds 0.2d0))
         (rate (/ (length stream) seconds)))
    (row "12. events/s, timed controller, null presenter, half the events preempt"
         (format-count rate) ">= 1 M/s" (>= rate 1d6))
    ;; This machine's speed drifts by up to 2x from minute to minute: the same
    ;; events sent whole, measured now, say which minute this was.
    (let ((whole (/ (length stream)
                    (seconds-per-call (lambda ()
                                        (let ((controller (player:make-controller
                                                           machine :presenter (player:make-null-presenter))))
                                          (loop for (name) across stream
                                                do (player:send-event controller name))))
                                      :batches 5 :batch-seconds 0.2d0))))
      (note "the same events sent whole (untimed controller), in the same minute: ~A events/s; the timed controller runs at ~,2F of that"
            (format-count whole) (/ rate whole)))
    (note "timed stream: ~D events gave ~D sequence numbers (~,1F per event: one per op, state change and macro span planned, and one per event's end, though a run cut short never makes its :finish item), consing ~D bytes per event; by CPU time (what other processes on the machine take does not count), the best of 7 passes gives ~A events/s"
          (length stream) items (/ items (length stream))
          (let ((before (sb-ext:get-bytes-consed)))
            (play-timed-stream (fresh-timed-controller machine) stream)
            (round (- (sb-ext:get-bytes-consed) before) (length stream)))
          (format-count (/ (length stream)
                           (loop repeat 7
                                 minimize (let ((controller (fresh-timed-controller machine))
                                                (start (get-internal-run-time)))
                                            (play-timed-stream controller stream)
                                            (max 1 (- (get-internal-run-time) start))))
                           (/ 1d0 internal-time-units-per-second))))
    ;; ADVANCE alone: one long event planned ahead, then presented.
    (let* ((spec (define-long-event-spec 200))
           (machine (player:compile-spec spec))
           (items (let ((controller (fresh-timed-controller machine)))
                    (player:send-event controller 'long)
                    ;; Every item due, those the run has not fed the heap yet included.
                    (let ((count 0))
                      (player.control::map-agenda (lambda (item) (declare (ignore item)) (incf count))
                                          (player.control::timeline-agenda (player.control::controller-timeline controller)))
                      count))))
      ;; Planning happens in SEND-EVENT; FINISH-EVENTS only presents.
      (let ((per-item (/ (median (loop repeat 7
                                       collect (let ((controller (fresh-timed-controller machine)))
                                                 (player:send-event controller 'long)
                                                 (let ((start (now)))
                                                   (player:finish-events controller)
                                                   (- (now) start)))))
                         items)))
        (row (format nil "12. advance: seconds per item presented (~D items of one event, null presenter)" items)
             (format-seconds per-item) "< 1 us" (< per-item 1d-6)))
      (player:remove-spec (player:spec-name spec)))))

(defun define-long-event-spec (n)
  "A spec whose event LONG plays N ops, each setting one of N/10 booleans:
one event with many items, to time ADVANCE alone."
  (let ((variables (max 1 (floor n 10))))
    (player:define-spec 'bench-long-event
      (append (loop for i below variables
                    collect `(state-variable ,(intern (format nil "B~D" i) :player-user) boolean false))
              (loop for i below n
                    collect `(op ,(intern (format nil "O~D" i) :player-user)
                                 ,@(if (evenp i) '(:add) '(:sub)) ,(intern (format nil "B~D" (mod (floor i 2) variables)) :player-user)
                                 :duration 0.01))
              (list `(event long ,@(loop for i below n
                                          append `(:op ,(intern (format nil "O~D" i) :player-user))))))
      :package (find-package :player-user))))
