;;;; speech.lisp -- speech's speed: espeak-ng synthesis and pocketsphinx
;;;; recognition, each in seconds of work per second of speech (below 1 is
;;;; faster than real time).  Loaded by run.lisp.

(in-package #:player-bench)

(defparameter *bench-sentences*
  '("have you got anything by bonnie maple" "play something by johnny river next"
    "what do you have by the silver foxes" "who wrote that" "thank you")
  "What is spoken and recognised: sentences of t/fixtures/jukebox.gram.")

(defun bench-speech ()
  "Rows: synthesis and recognition time per second of speech (targets: 0.1 and 0.5)."
  (handler-case
      (let* ((grammar (alexandria:read-file-into-string
                       (merge-pathnames "../t/fixtures/jukebox.gram" *bench-directory*)))
             (speech (reduce #'+ *bench-sentences*
                             :key (lambda (text) (player:utterance-duration (player:synthesize-speech text)))))
             (synthesis (seconds-per-call
                         (lambda ()
                           ;; A fresh cache each time, or nothing would be synthesised.
                           (let ((player.speech::*utterances* (make-hash-table :test #'equal)))
                             (mapc #'player:synthesize-speech *bench-sentences*)))
                         :batches 5 :batch-seconds 0.1d0 :max-seconds 10))
             (sounds (mapcar (lambda (text) (player:utterance-sound (player:synthesize-speech text)))
                             *bench-sentences*))
             (recognition (seconds-per-call
                           (lambda () (dolist (sound sounds) (player:recognize-sound sound :grammar grammar)))
                           :batches 3 :batch-seconds 0.1d0 :max-seconds 15)))
        (row (format nil "speech synthesis (espeak-ng, ~,1F s of speech)" speech)
             (format nil "~,3F s per s of speech" (/ synthesis speech)) "< 0.1" (< (/ synthesis speech) 0.1))
        (row "speech recognition (pocketsphinx, JSGF grammar)"
             (format nil "~,3F s per s of speech" (/ recognition speech)) "< 0.5" (< (/ recognition speech) 0.5)))
    (player:speech-error (e)
      (row "speech" (format nil "not run: ~A" e) "-" ""))))
