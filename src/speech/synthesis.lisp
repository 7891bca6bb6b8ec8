;;;; synthesis.lisp -- text to an UTTERANCE: the sound espeak-ng makes,
;;;; the phoneme timeline its phoneme events give and the word timeline its
;;;; word events give (words.lisp).  Synthesis is
;;;; deterministic, so utterances are kept by text, voice and rate.

(in-package #:player.speech)

(defparameter *default-voice* "en-us" "The espeak-ng voice SYNTHESIZE-SPEECH uses unless told otherwise.")
(defparameter *default-speech-rate* 160
  "Words a minute SYNTHESIZE-SPEECH speaks unless told otherwise: a little
slower than espeak-ng's 175, which pocketsphinx also hears better.")

(defstruct (utterance (:constructor make-utterance (text voice rate sound phonemes &optional words)))
  "TEXT spoken by VOICE at RATE words a minute: its SOUND and PHONEMES, a list
of (NAME START END) in seconds from the start of the sound, in order and
covering it (NAME is espeak-ng's mnemonic, \"_:\" and the like for pauses);
WORDS, a list of (WORD START END), each word of TEXT as written (without
the punctuation around it) and when it is spoken."
  (text "" :type string :read-only t)
  (voice "" :type string :read-only t)
  (rate 0 :type integer :read-only t)
  (sound nil :type sound :read-only t)
  (phonemes '() :type list :read-only t)
  (words '() :type list :read-only t))

(defun utterance-duration (utterance)
  "How long UTTERANCE lasts, in seconds."
  (sound-duration (utterance-sound utterance)))

(defvar *utterances* (make-hash-table :test #'equal)
  "Utterances already synthesised, by (TEXT VOICE RATE).")

(defun synthesize-speech (text &key (voice *default-voice*) (rate *default-speech-rate*))
  "TEXT spoken by espeak-ng's VOICE at RATE words a minute (80 to 450), as an
UTTERANCE kept in memory: 16-bit samples at espeak-ng's rate (22050 Hz) and
the phoneme and word timelines from its events.  The same arguments give the
same utterance, synthesised once.  Signals SPEECH-UNAVAILABLE when
libespeak-ng (Debian libespeak-ng1) is missing, a SPEECH-ERROR for an unknown
voice, an ARGUMENT-ERROR for arguments of the wrong kind."
  (check-argument 'synthesize-speech 'text text (lambda (x) (and (stringp x) (<= 1 (length x) 2000)))
                  "a string of 1 to 2000 characters")
  (check-argument 'synthesize-speech :voice voice (lambda (x) (and (stringp x) (< 0 (length x) 40)
                                                                   (every #'graphic-char-p x)))
                  "a voice's name, such as \"en-us\"")
  (check-real 'synthesize-speech :rate rate :integer t :minimum 80 :maximum 450)
  (let ((key (list text voice rate)))
    (or (gethash key *utterances*)
        (setf (gethash key *utterances*) (speak-utterance text voice rate)))))

(defun speak-utterance (text voice rate)
  "A fresh UTTERANCE of TEXT by VOICE at RATE from espeak-ng."
  (let ((sample-rate (ensure-espeak))
        (chunks '()) (events '()))
    (espeak-set-voice voice)
    (espeak-set-rate rate)
    (espeak-speak text (lambda (chunk chunk-events)
                         (push chunk chunks)
                         (setf events (revappend chunk-events events))))
    (setf events (nreverse events))
    (let* ((samples (apply #'concatenate 'samples (reverse chunks)))
           (sound (make-sound samples sample-rate))
           (phonemes (phoneme-timeline (loop for (kind name ms) in events
                                             when (eq kind :phoneme) collect (cons name ms))
                                       (sound-duration sound))))
      (make-utterance text voice rate sound phonemes
                      (word-timeline text (remove :phoneme events :key #'first) phonemes)))))

(defun phoneme-timeline (events duration)
  "The phonemes of EVENTS, (NAME . MILLISECONDS) in order, as (NAME START END):
each lasts until the next starts, the last until DURATION; a pause fills any
time before the first.  Events out of order are clamped so the timeline is
monotone."
  (let ((starts (loop with last = 0d0
                      for (name . ms) in events
                      for start = (min duration (max last (/ ms 1000d0)))
                      collect (cons name start)
                      do (setf last start))))
    (append (when (and starts (plusp (cdr (first starts))))
              (list (list "_" 0d0 (cdr (first starts)))))
            (loop for ((name . start) next) on starts
                  collect (list name start (if next (cdr next) duration))))))
