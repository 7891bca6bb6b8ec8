;;;; budgets.lisp -- what one command may be asked to produce: frames of
;;;; simulated time.  A frame, and a second of a body's performance (its loops
;;;; and reflexes), cost time and memory whatever the input, so a command line
;;;; asking for more than *MAX-FRAMES* or *MAX-BODY-SECONDS* is refused up
;;;; front, with the counts, before anything plays (issue 31, item 3).

(in-package #:player.cli)

(defparameter *max-frames* 36000
  "The most frames simulate, record --frames, render and export produce: 20
minutes at 30 frames a second.")

(defparameter *max-body-seconds* 7200
  "The longest simulated time, in seconds, a body performs in one command (two hours).")

(defun frame-count (seconds fps)
  "How many frames cover SECONDS at FPS: the first at 0, the last at or after SECONDS."
  (1+ (ceiling (* seconds fps))))

(defun check-frame-budget (at fps)
  "A USAGE-ERROR when --at AT (seconds, or NIL) at FPS asks for more than
*MAX-FRAMES* frames, or a body to perform longer than *MAX-BODY-SECONDS*."
  (when (and at (> at *max-body-seconds*))
    (usage-fail "--at ~A s is longer than a body performs in one command (at most ~:D s)"
                (format-number at) *max-body-seconds*))
  (when (and at fps (> (frame-count at fps) *max-frames*))
    (usage-fail "--at ~A at ~A fps is ~:D frames; at most ~:D (lower --at or --fps)"
                (format-number at) (format-number fps) (frame-count at fps) *max-frames*)))

(defun check-simulation-budget (frames fps)
  "A PLAYER-ERROR when the scenario played needs FRAMES frames at FPS, more than
*MAX-FRAMES*: its ops run longer than frames can hold."
  (when (> frames *max-frames*)
    (error 'player-error-with-message
           :message (format nil "the scenario lasts ~A s, ~:D frames at ~A fps; at most ~:D (stop it with --at, or lower --fps)"
                            (format-number (/ (1- frames) fps)) frames (format-number fps) *max-frames*))))
