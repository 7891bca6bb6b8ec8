;;;; mix.lisp -- an audio track: sounds placed at times, mixed into one mono
;;;; 16-bit sound.  Performances keep their speech and sound effects as such
;;;; clips, so the mix is a function of what played, like the frames.

(in-package #:player.speech)

(defparameter *track-rate* 22050
  "The sample rate of mixed tracks: espeak-ng's, so speech needs no resampling.")

(defstruct (clip (:constructor make-clip (start sound &optional cut label)))
  "SOUND placed START seconds into a track, cut at CUT (seconds on the track)
when CUT is a number; LABEL says what it is (the text spoken, the file played)."
  (start 0d0 :type double-float :read-only t)
  (sound nil :type sound :read-only t)
  (cut nil)
  (label nil :read-only t))

(defun clip-end (clip)
  "Where CLIP stops on its track: the end of its sound or its CUT, whichever is first."
  (let ((natural (+ (clip-start clip) (sound-duration (clip-sound clip)))))
    (if (clip-cut clip) (min natural (clip-cut clip)) natural)))

(defun mix-clips (clips &key (rate *track-rate*) end)
  "CLIPS mixed into one SOUND at RATE, from time 0 to END (default: the last
clip's end), each clip resampled to RATE and the sum clipped to 16 bits.
NIL when there are no clips."
  (when clips
    (let* ((end (or end (reduce #'max clips :key #'clip-end)))
           (total (make-array (ceiling (* end rate)) :element-type 'fixnum :initial-element 0)))
      (dolist (clip clips)
        (let* ((samples (sound-samples (resample-sound (clip-sound clip) rate)))
               (offset (round (* (clip-start clip) rate)))
               (stop (min (length total) (round (* (clip-end clip) rate)))))
          (loop for i from (max offset 0) below stop
                for k = (- i offset)
                while (< k (length samples))
                do (incf (aref total i) (aref samples k)))))
      (make-sound (map 'samples #'clamp-sample total) rate))))
