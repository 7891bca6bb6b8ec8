;;;; test-speech-recognition.lisp -- the round trip: espeak-ng speaks each
;;;; scripted utterance of the jukebox grammar to a WAV file, pocketsphinx
;;;; recognises it with that grammar.  Skips with a note when either library
;;;; is missing.

(in-package #:player-tests)

(def-suite* speech-recognition :in player-tests)

(defun pocketsphinx-available-p ()
  "Are pocketsphinx and its English model installed?"
  (handler-case (progn (player.speech::load-pocketsphinx-library) (player.speech::pocketsphinx-model-files) t)
    (player::speech-unavailable () nil)))

(defparameter *jukebox-grammar* (checkout-file "t/fixtures/jukebox.gram"))

(defparameter *jukebox-utterances*
  '("have you got anything by bonnie maple" "play something by johnny river next"
    "what do you have by the silver foxes" "have you got anything by ruby morgan"
    "play something by captain parrot" "have you got anything by miles carter"
    "what do you have by the copper kettles" "play something by lucy daniels after that"
    "have you got anything by ella harper" "play something by jasper green"
    "who wrote that" "what is playing" "thank you" "yes" "okay" "no")
  "What the round trip says: requests by artist (some with a time), questions,
thanks, yes and no.")

(test spoken-utterances-are-recognised
  (cond ((not (espeak-available-p))
         (skip "libespeak-ng is not installed (Debian libespeak-ng1): round trip not tested"))
        ((not (pocketsphinx-available-p))
         (skip "pocketsphinx or its model is not installed (Debian pocketsphinx, pocketsphinx-en-us): round trip not tested"))
        (t
         (let* ((grammar (alexandria:read-file-into-string *jukebox-grammar*))
                (misheard '()))
           (loop for text in *jukebox-utterances*
                 for k from 1
                 for wav = (speech-file (format nil "utterance-~D.wav" k))
                 do (player::write-wav wav (player::utterance-sound (player::synthesize-speech text)))
                    (let ((heard (player::recognize-wav wav :grammar grammar)))
                      (unless (equal heard text) (push (list text heard) misheard))))
           (is (<= (length misheard) 2) "~D of ~D misheard: ~S" (length misheard)
               (length *jukebox-utterances*) misheard)))))

(test recognising-an-unreadable-wav-is-a-clear-error
  (let ((grammar (alexandria:read-file-into-string *jukebox-grammar*))
        (text (speech-file "request.wav")))
    (write-octets text (map 'list #'char-code "not a sound"))
    (is (search (format nil "cannot read the WAV file ~A: it is not a RIFF WAVE file" text)
                (or (speech-error-text (lambda () (player::recognize-wav text :grammar grammar))) "")))
    (is (search "there is no such file"
                (or (speech-error-text (lambda () (player::recognize-wav (speech-file "nothing.wav") :grammar grammar))) "")))
    (signals player::argument-error (player::recognize-wav text :grammar "public <a> = yes;"))))

(test a-grammar-pocketsphinx-cannot-use-is-a-clear-error
  (if (not (pocketsphinx-available-p))
      (skip "pocketsphinx or its model is not installed (Debian pocketsphinx, pocketsphinx-en-us): grammars not tested")
      (let ((wav (speech-file "quiet.wav")))
        (write-wav wav (make-sound (make-array 8000 :element-type '(signed-byte 16) :initial-element 0) 16000))
        (is (search "pocketsphinx could not use the grammar"
                    (or (speech-error-text (lambda () (recognize-wav wav :grammar "#JSGF V1.0; grammar g; public <a> = thank you | (;")))
                        ""))))))

(test words-the-dictionary-lacks-are-learnt-from-espeak
  (cond ((not (and (espeak-available-p) (pocketsphinx-available-p)))
         (skip "libespeak-ng or pocketsphinx is not installed: learning words not tested"))
        (t
         (is (equal '("play" "by" "zorblax" "quintessa" "thank" "you")
                    (player.speech::grammar-words "#JSGF V1.0; /* a comment */ grammar g;
public <a> = play [<x>] by /2/ (zorblax quintessa) {artist} | thank you; // more
<x> = by;")))
         (is (equal "Z AO R B L AE K S" (player.speech::word-pronunciation "zorblax")))
         (let ((wav (speech-file "zorblax.wav"))
               (grammar "#JSGF V1.0; grammar g; public <a> = play something by (zorblax quintessa | bonnie maple) | thank you;"))
           (write-wav wav (utterance-sound (synthesize-speech "play something by zorblax quintessa")))
           (is (equal "play something by zorblax quintessa" (recognize-wav wav :grammar grammar)))))))
