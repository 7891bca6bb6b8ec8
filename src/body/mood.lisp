;;;; mood.lisp -- how a body performs, as in SCOOT!'s "happily" or "sadly": the
;;;; body property MOOD, from -1 (sad, subdued) through 0 (neutral) to 1
;;;; (happy, lively), scales the amplitude and the speed of gestures within
;;;; limits; and the body properties a running breathing driver follows.

(in-package #:player.body)

(defparameter *mood-amplitude-range* 0.3d0
  "The most a mood of 1 (or -1) adds to (or takes from) a gesture's amplitude, as a fraction.")

(defparameter *mood-speed-range* 0.25d0
  "The most a mood of 1 (or -1) adds to (or takes from) a gesture's speed, as a fraction.")

(defparameter *emotion-moods*
  '((happy . 0.6) (excited . 0.9) (pleased . 0.4) (amused . 0.5) (neutral . 0)
    (calm . -0.2) (tired . -0.6) (sad . -0.6) (bored . -0.4) (annoyed . 0.2)
    (angry . 0.5) (nervous . 0.4))
  "A MOOD value for each emotion a dialogue may name.")

(defparameter *body-properties*
  '((mood :number 0d0) (breathing-rate :number 14d0) (breathing-depth :number 1d0))
  "Properties every body has besides a scene object's: (NAME TYPE INITIAL).
BREATHING-RATE is breaths a minute, BREATHING-DEPTH a multiple of the
:breathe call's depth; a script retunes breathing by setting them.")

(defun define-body-properties (body)
  "Give BODY the properties of *BODY-PROPERTIES* at their initial values."
  (loop for (name type value) in *body-properties*
        do (define-property body name type value)))

(defun emotion-mood (emotion)
  "The MOOD (a number from -1 to 1) for EMOTION (a symbol or string such as
HAPPY or SAD, compared by name); 0 for an emotion *EMOTION-MOODS* does not know."
  (check-argument 'emotion-mood 'emotion emotion #'string-designator-p "an emotion's name (a symbol or string)")
  (let ((entry (assoc (string emotion) *emotion-moods* :key #'string :test #'string-equal)))
    (if entry (to-double (cdr entry)) 0d0)))

(defun body-mood (body)
  "BODY's mood, clamped to [-1, 1]."
  (max -1d0 (min 1d0 (float (property-value body 'mood) 1d0))))

(defun mood-amplitude-scale (body)
  "How much BODY's mood scales a gesture's amplitude: 1 at a neutral mood,
1 +- *MOOD-AMPLITUDE-RANGE* at the extremes."
  (+ 1d0 (* *mood-amplitude-range* (body-mood body))))

(defun mood-speed-scale (body)
  "How much BODY's mood scales a gesture's speed (durations divide by it): 1
at a neutral mood, 1 +- *MOOD-SPEED-RANGE* at the extremes."
  (+ 1d0 (* *mood-speed-range* (body-mood body))))
