;;;; mix.lisp -- an audio track: sounds placed at times, mixed into one mono
;;;; 16-bit sound.  Performances keep their speech, sound effects and music
;;;; as such clips, so the mix is a function of what played, like the
;;;; frames.  Music ducks under the voice: while a voice clip sounds, music
;;;; clips play at *DUCK-GAIN*, easing down and back over *DUCK-RAMP*.

(in-package #:player.speech)

(defparameter *track-rate* 22050
  "The sample rate of mixed tracks: espeak-ng's, so speech needs no resampling.")

(defparameter *duck-gain* 0.25d0
  "How loud music plays under a voice, as a fraction of its own level.")

(defparameter *duck-ramp* 0.08d0
  "Seconds music takes to duck before a voice and to come back after it.")

(defstruct (clip (:constructor make-clip (start sound &optional cut label kind)))
  "SOUND placed START seconds into a track, cut at CUT (seconds on the track)
when CUT is a number; LABEL says what it is (the text spoken, the file
played); KIND is :voice (a character speaking), :music (ducked under
voices) or NIL (a sound effect)."
  (start 0d0 :type double-float :read-only t)
  (sound nil :type sound :read-only t)
  (cut nil)
  (label nil :read-only t)
  (kind nil :type (member nil :voice :music) :read-only t))

(defun clip-end (clip)
  "Where CLIP stops on its track: the end of its sound or its CUT, whichever is first."
  (let ((natural (+ (clip-start clip) (sound-duration (clip-sound clip)))))
    (if (clip-cut clip) (min natural (clip-cut clip)) natural)))

(defun duck-gain (voices time)
  "The gain of music at TIME seconds given VOICES, ((START . END) ...): 1 far
from every voice, *DUCK-GAIN* inside one, a straight ramp over *DUCK-RAMP*
on either side."
  (let ((nearness (loop for (start . end) in voices
                        maximize (cond ((<= start time end) 1d0)
                                       ((< time start) (max 0d0 (- 1d0 (/ (- start time) *duck-ramp*))))
                                       (t (max 0d0 (- 1d0 (/ (- time end) *duck-ramp*))))))))
    (- 1d0 (* (- 1d0 *duck-gain*) nearness))))

(defun clip-heard-part (clip end)
  "The part of CLIP's sound that sounds before END on the track (a little
more, for the resampler's window): a long track cut early, or a ten-minute
WAV under a short render, is resampled only as far as it is heard."
  (let* ((sound (clip-sound clip))
         (seconds (- (min end (clip-end clip)) (clip-start clip)))
         (count (min (length (sound-samples sound))
                     (max 0 (ceiling (* (+ seconds 0.05d0) (sound-rate sound)))))))
    (if (= count (length (sound-samples sound)))
        sound
        (make-sound (subseq (sound-samples sound) 0 count) (sound-rate sound)))))

(defun mix-clips (clips &key (rate *track-rate*) end)
  "CLIPS mixed into one SOUND at RATE, from time 0 to END (default: the last
clip's end), each clip resampled to RATE and the sum clipped to 16 bits;
music clips duck under voice clips (see DUCK-GAIN).  NIL when there are no clips."
  (when clips
    (let* ((end (or end (reduce #'max clips :key #'clip-end)))
           (total (make-array (ceiling (* end rate)) :element-type 'fixnum :initial-element 0))
           (voices (loop for clip in clips
                         when (eq (clip-kind clip) :voice)
                           collect (cons (clip-start clip) (clip-end clip)))))
      (dolist (clip clips)
        (let* ((samples (sound-samples (resample-sound (clip-heard-part clip end) rate)))
               (offset (round (* (clip-start clip) rate)))
               (stop (min (length total) (round (* (clip-end clip) rate))))
               (ducked (and voices (eq (clip-kind clip) :music))))
          (loop for i from (max offset 0) below stop
                for k = (- i offset)
                while (< k (length samples))
                do (incf (aref total i)
                         (if ducked
                             (round (* (aref samples k) (duck-gain voices (/ i rate))))
                             (aref samples k))))))
      (make-sound (map 'samples #'clamp-sample total) rate))))
