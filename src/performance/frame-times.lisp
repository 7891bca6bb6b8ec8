;;;; frame-times.lisp -- when a simulation's frames fall: the regular grid of
;;;; the frame rate, with the nearest frame moved onto each critical time.
;;;;
;;;; Critical times are "times at which frames must be displayed" (Pantomime:
;;;; the hammer hitting the nail).  On a grid of 1/FPS a strike at 0.55 s
;;;; falls between frames at 10 fps (0.5, 0.6) and at 4 fps (0.5, 0.75), so
;;;; it was never shown though its sound lands then.  Each critical time that
;;;; falls between two frames moves the nearer of the two onto it: the frame
;;;; count and every other frame stay as the grid has them, so a BVH's frame
;;;; time and a video's rate still hold (a moved frame is early or late by
;;;; at most half a frame).  The first and last frames never move (the
;;;; starting pose, the settled one).  When both neighbours already show a
;;;; critical time -- three within one frame interval -- a frame is added
;;;; there instead, so every critical time has its frame at every rate.

(in-package #:player.performance)

(defparameter *critical-time-epsilon* 1d-9
  "Seconds within which a critical time counts as on a grid frame.")

(defun grid-frame-count (end fps)
  "How many frames of the grid of 1/FPS cover 0 to END seconds: the first at
0 and the last at or after END."
  (1+ (ceiling (* end fps))))

(defun critical-frame-times (end fps critical-times)
  "The frame times, a vector of double-floats, covering 0 to END seconds at
FPS: the grid I/FPS with, for each of CRITICAL-TIMES (seconds, any order)
after the first frame and before the last, a frame exactly at it -- the
nearer grid frame moved there (see the top of this file)."
  (let* ((count (grid-frame-count end fps))
         (times (make-array count :element-type 'double-float))
         (claimed (make-array count :element-type 'bit :initial-element 0))
         (extra '()))
    (dotimes (i count)
      (setf (aref times i) (/ i (float fps 1d0))))
    (setf (aref claimed 0) 1
          (aref claimed (1- count)) 1)
    (let* ((inside (remove-if-not (lambda (time) (< 0 time (aref times (1- count))))
                                  (sort (remove-duplicates (mapcar (lambda (x) (float x 1d0)) critical-times))
                                        #'<)))
           (between '()))
      ;; Those on the grid first: each pins its frame, which no other may move.
      (dolist (time inside)
        (let* ((position (* time fps))
               (nearest (round position)))
          (if (< (abs (- position nearest)) (* fps *critical-time-epsilon*))
              (setf (aref times nearest) time
                    (aref claimed nearest) 1)
              (push time between))))
      ;; Then each between two frames moves the nearer one still free.
      (dolist (time (nreverse between))
        (let* ((position (* time fps))
               (below (floor position))
               (candidates (if (< (- position below) 0.5d0)
                               (list below (1+ below))
                               (list (1+ below) below)))
               (free (find-if (lambda (i) (zerop (aref claimed i))) candidates)))
          (if free
              (setf (aref times free) time
                    (aref claimed free) 1)
              (push time extra)))))
    (if extra
        (sort (concatenate '(vector double-float) times extra) #'<)
        times)))

(defun script-run-critical-times (run end)
  "The times, up to END seconds, at which top-level script RUN reaches a
critical time of its script: once, or in every iteration of a loop, never
after the run was stopped."
  (let* ((script (script-run-script run))
         (critical (and (script-p script) (script-critical script)))
         (start (script-run-start run))
         (stop (or (script-run-stop run) end))
         (period (and (script-run-loop run) (script-duration script))))
    (when critical
      (loop for offset = 0d0 then (+ offset period)
            while (< (+ start offset) (min stop end))
            nconc (loop for (nil . at) in critical
                        for time = (+ start offset at)
                        when (<= time (min stop end)) collect time)
            while (and period (plusp period))))))

(defun performance-critical-times (performance end)
  "Every time, up to END seconds, at which a script PERFORMANCE started
reaches one of its script's critical times, earliest first."
  (sort (loop for run in (performance-runs performance)
              nconc (script-run-critical-times run end))
        #'<))

(defun performance-critical-time-between (performance from to)
  "The earliest critical time a script PERFORMANCE started reaches after FROM
and at or before TO seconds, or NIL: where a live viewer's next frame goes
instead of TO, so that it shows the instant (the frame after catches up)."
  (let ((earliest nil))
    (dolist (run (performance-runs performance) earliest)
      (when (<= (script-run-start run) to)
        (dolist (time (script-run-critical-times run to))
          (when (and (> time from) (or (null earliest) (< time earliest)))
            (setf earliest time)))))))
