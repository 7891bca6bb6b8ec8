;;;; scenes.lisp -- several Peedys in one scene (src/cast/): events per second
;;;; and simulated seconds per frame for 1, 10 and 50 members, which should
;;;; cost in proportion to the number of members.  Loaded by run.lisp.

(in-package #:player-bench)

(defparameter *cast-sizes* '(1 10 50) "How many Peedys the scene benchmarks cast.")

(defparameter *cast-events* '("all/ev-search" "all/ev-bad-speech" "all/ev-thanks" "all/ev-hop")
  "The addresses sent over and over: every member receives each.")

(defun scene-event-sender (spec count)
  "A thunk sending the next of *CAST-EVENTS* to every member of a COUNT-Peedy
scene of SPEC, each controller on a null presenter."
  (let ((ensemble (player:make-ensemble (player:replicate-cast spec count)
                                        :presenter (lambda (member)
                                                     (declare (ignore member))
                                                     (player:make-null-presenter))))
        (events (copy-list *cast-events*)))
    (setf (cdr (last events)) events)   ; a ring
    (lambda () (player:send-scene-event ensemble (pop events)))))

(defun scene-frame-seconds (spec count)
  "Seconds per frame of a COUNT-Peedy scene of SPEC that searched, at 30 fps:
every member's performance evaluated and gathered, frame after frame."
  (let* ((simulation (player:simulate-scene (player:replicate-cast spec count)
                                            :events '("all/ev-search" "all/ev-thanks") :fps 30))
         (frames (player::simulation-frame-count simulation))
         (start (now)))
    (dotimes (index frames)
      (player:simulation-scene-at simulation (player.performance::simulation-frame-time simulation index)))
    (/ (- (now) start) frames)))

(defun bench-scenes (spec)
  "Rows: member events per second, and seconds per simulated frame, for scenes
of 1, 10 and 50 Peedys; the cost per member should stay flat."
  (let ((per-event (loop for count in *cast-sizes*
                         collect (/ (seconds-per-call (scene-event-sender spec count) :batches 5) count)))
        (per-frame (loop for count in (progn (scene-frame-seconds spec 1) *cast-sizes*) ; warm-up first
                         do (format t "~&  scene of ~D Peedys...~%" count) (finish-output)
                         collect (scene-frame-seconds spec count))))
    ;; Linear: the cost per member stays flat from 10 to 50 members.  One
    ;; member alone is cheaper per member still -- its controller, body and
    ;; scene stay in the processor's caches -- so it is shown, not compared.
    (note "scenes: per-member cost compared between 10 and 50 members; 1 member alone fits in cache and is faster per member")
    (flet ((flat (costs) (let ((ratio (/ (car (last costs)) (second costs))))
                           (if (< ratio 1.5) "ok" (format nil "MISS (x~,1F)" ratio)))))
      (row "Peedys per scene, member events/s at 1 / 10 / 50"
           (format nil "~{~A~^ / ~}" (mapcar (lambda (s) (format-count (/ 1 s))) per-event))
           "linear (flat per member, 10 to 50)" (flat per-event))
      (row "Peedys per scene, simulated ms/frame at 1 / 10 / 50"
           (format nil "~{~,2F~^ / ~}" (mapcar (lambda (s) (* 1d3 s)) per-frame))
           "linear (10 to 50)" (flat (mapcar #'/ per-frame *cast-sizes*)))
      (row "50-Peedy scene, per frame (per member)"
           (format nil "~A (~A)" (format-seconds (car (last per-frame)))
                   (format-seconds (/ (car (last per-frame)) 50)))
           "< 33 ms (30 fps)" (< (car (last per-frame)) 1/30)))))
