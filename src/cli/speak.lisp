;;;; speak.lisp -- `player speak`: espeak-ng says a text into a WAV file.
;;;; What `make demo-dialogue` records the user's requests with, before chat
;;;; --wav hears them; handy for trying a recogniser too.

(in-package #:player.cli)

(define-command "speak" (text &key out voice rate)
    (:summary "say TEXT with espeak-ng into a WAV file"
     :description "Synthesises TEXT (one argument: quote a sentence) with espeak-ng (Debian
package libespeak-ng1), as a script's :say item does, and writes it as a
mono 16-bit PCM WAV file, which chat --wav can hear.  Prints its path and
length."
     :arguments ("TEXT")
     :options (("--out" :string "FILE.wav" "the WAV file to write" :default "speech.wav")
               ("--voice" :string "VOICE" "espeak-ng's voice" :default "en-us")
               ("--rate" :positive-integer "WPM" "words a minute, 80 to 450" :default 160))
     :output "the WAV file; its path and length on standard output")
  (when (string= (string-trim '(#\Space #\Tab) text) "")
    (usage-fail "speak needs a TEXT with words in it"))
  (unless (<= 80 rate 450)
    (usage-fail "--rate takes words a minute from 80 to 450, not ~D" rate))
  (let* ((utterance (synthesize-speech text :voice voice :rate rate))
         (path (write-wav (merge-pathnames out) (utterance-sound utterance))))
    (format t "; wrote ~A (~,2F s)~%" (namestring path) (utterance-duration utterance))))
