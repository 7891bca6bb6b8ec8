;;;; test-speech-rejection.lisp -- issue 28, item 3: every recognition is
;;;; scored, and speech outside the grammar is rejected.  The sentences are
;;;; t/fixtures/spoken-sentences.lisp, written before the rejection was
;;;; tuned; each is spoken by espeak-ng's default voice (British, "en") and
;;;; by "en-us", heard with the jukebox dialogue's grammar and played as a
;;;; turn.  Skips with a note when libespeak-ng or pocketsphinx is missing.

(in-package #:player-tests)

(def-suite* speech-rejection :in player-tests)

(defun spoken-sentence-set (name)
  "The sentences of the set NAME (in-grammar or out-of-domain) of the fixture."
  (with-open-file (in (checkout-file "t/fixtures/spoken-sentences.lisp"))
    (let ((*read-eval* nil))
      (loop for form = (read in nil in)
            until (eq form in)
            when (string-equal (symbol-name (first form)) name) return (rest form)))))

(defun spoken-sound (text voice)
  "TEXT said by espeak-ng's VOICE at Player's speech rate, by the espeak-ng
program: a process of its own starts from espeak-ng's initial state each
time, so the sound is always the same.  (The library carries its state,
such as its pitch flutter's phase, from one sentence to the next: the same
text sounds a little different after other sentences, enough to change
what is heard.)"
  (let ((wav (speech-file "spoken-sentence.wav")))
    (sb-ext:run-program "espeak-ng" (list "-v" voice "-s" (princ-to-string player.speech::*default-speech-rate*)
                                          "-w" wav text)
                        :search t)
    (read-wav wav)))

(defun spoken-turn-event (dialogue text voice)
  "The input event and slots a turn takes when VOICE says TEXT (SPOKEN-SOUND)
and the jukebox grammar hears it, rejection included, and the recognition's
score: (VALUES EVENT SLOTS SCORE HEARD)."
  (multiple-value-bind (heard score sentence)
      (recognize-sound (spoken-sound text voice) :grammar (dialogue-jsgf dialogue))
    (let ((turn (conversation-hear (make-conversation dialogue) heard)))
      (values (turn-event turn) (turn-slots turn) score sentence))))

(defparameter *tuning-sentences* 13
  "How many sentences at the start of each set of the fixture the rejection
was tuned on (two thirds); the rest are held out, and reported apart.")

(defun spoken-set-results (set voice)
  "For each sentence of SET said by VOICE: (TEXT RIGHT-P HEARD SCORE
HELD-OUT-P), RIGHT-P when the turn reaches the input typing it gives
(in-grammar) or is evBadSpeech (out-of-domain), HELD-OUT-P when it is not
among the *TUNING-SENTENCES*."
  (let* ((dialogue (jukebox))
         (sentences (spoken-sentence-set set))
         (held-out (nthcdr *tuning-sentences* sentences)))
    (loop for text in (sweep-sample sentences 7)
          collect (multiple-value-bind (event slots score heard) (spoken-turn-event dialogue text voice)
                    (let ((typed (conversation-hear (make-conversation dialogue) text)))
                      (list text
                            (if (string-equal set "out-of-domain")
                                (player.dialogue::same-name-p event "evBadSpeech")
                                (and (player.dialogue::same-name-p event (turn-event typed)) (equal slots (turn-slots typed))))
                            heard score (and (member text held-out :test #'string=) t)))))))

(defun split-counts (results)
  "\"R of N (tuning R of N, held out R of N)\" for RESULTS."
  (flet ((counts (list) (list (count-if #'second list) (length list))))
    (format nil "~{~D of ~D~} (tuning ~{~D of ~D~}, held out ~{~D of ~D~})"
            (counts results) (counts (remove-if #'fifth results)) (counts (remove-if-not #'fifth results)))))

(defun nine-in-ten-p (results)
  "Are at least 9 in 10 of RESULTS right (the issue's target)?  The fast
tier's sample of 7 sentences per set only checks the machinery, all but two
right: the sample takes the sets' last sentences, where the misses are."
  (<= (count-if-not #'second results) (sweep-count (max 1 (floor (length results) 10)) 2)))

(defmacro with-espeak-program ((what) &body body)
  "Run BODY when espeak-ng (library and program) and pocketsphinx are
installed; otherwise skip, saying WHAT is not tested."
  `(with-speech-libraries (,what)
     (if (probe-file "/usr/bin/espeak-ng")
         (progn ,@body)
         (skip "the espeak-ng program is not installed (Debian espeak-ng): ~A not tested" ,what))))

(defun recognition-of (text voice grammar)
  "All RECOGNIZE-SOUND says of TEXT said by VOICE, heard with GRAMMAR."
  (multiple-value-list (recognize-sound (utterance-sound (synthesize-speech text :voice voice)) :grammar grammar)))

(test recognition-does-not-depend-on-what-was-heard-before
  ;; Same sound, same grammar: same sentence and score, whatever was decoded
  ;; before, by these decoders or others (pocketsphinx's dither generator is
  ;; one per process, its noise estimate one per decoder).
  (with-speech-libraries ("recognition's independence of history")
    (let* ((grammar (dialogue-jsgf (jukebox)))
           (first (recognition-of "play something by madonna" "en" grammar)))
      (recognition-of "what is the weather like today" "en-us" grammar)
      (recognition-of "hello" "en" grammar)
      (is (equal first (recognition-of "play something by madonna" "en" grammar)))
      ;; New decoders hear it as the old ones did.
      (let ((player.speech::*sphinx-decoder* nil)
            (player.speech::*phone-loop-decoder* nil))
        (unwind-protect (is (equal first (recognition-of "play something by madonna" "en" grammar)))
          (dolist (decoder (list player.speech::*sphinx-decoder* player.speech::*phone-loop-decoder*))
            (when decoder (player.speech::free-sphinx-decoder decoder))))))))

(test out-of-domain-speech-is-bad-speech
  (with-espeak-program ("rejecting out-of-domain speech")
    (let ((british (spoken-set-results "out-of-domain" "en"))
          (us (spoken-set-results "out-of-domain" "en-us")))
      (format t "~&; out-of-domain speech rejected: en ~A, en-us ~A~%" (split-counts british) (split-counts us))
      ;; The issue's target, 9 in 10, for each voice.
      (is (nine-in-ten-p british) "en accepted as commands: ~S" (remove-if #'second british))
      (is (nine-in-ten-p us) "en-us accepted as commands: ~S" (remove-if #'second us)))))

(test in-grammar-speech-reaches-its-input
  (with-espeak-program ("in-grammar speech with rejection")
    (let ((us (spoken-set-results "in-grammar" "en-us"))
          (british (spoken-set-results "in-grammar" "en")))
      (format t "~&; in-grammar speech right: en-us ~A, en ~A~%" (split-counts us) (split-counts british))
      ;; The issue's target, 9 in 10, for each voice: the British one is
      ;; heard through the accent variants of the grammar's words
      ;; (pronunciation.lisp).
      (is (nine-in-ten-p us) "en-us wrong: ~S" (remove-if #'second us))
      (is (nine-in-ten-p british) "en wrong: ~S" (remove-if #'second british)))))

(test every-recognition-carries-a-score
  (with-speech-libraries ("recognition scores")
    (let ((grammar (dialogue-jsgf (jukebox))))
      (multiple-value-bind (text score sentence)
          (recognize-sound (utterance-sound (synthesize-speech "stop the music")) :grammar grammar)
        (is (equal "stop the music" text))
        (is (equal text sentence))
        (is (realp score))
        (is (>= score player::*rejection-margin*)))
      ;; A margin no sentence reaches rejects everything, and says so.
      (let ((player::*rejection-margin* 1000.0))
        (multiple-value-bind (text score sentence)
            (recognize-sound (utterance-sound (synthesize-speech "stop the music")) :grammar grammar)
          (is (null text))
          (is (realp score))
          (is (equal "stop the music" sentence)))))))

(test chat-wav-prints-the-score-and-rejects
  (with-speech-libraries ("chat --wav's scores")
    (let ((good (speech-file "score-good.wav"))
          (bad (speech-file "score-bad.wav")))
      (write-wav good (utterance-sound (synthesize-speech "stop the music")))
      (write-wav bad (utterance-sound (synthesize-speech "how do you spell necessary")))
      (multiple-value-bind (out err code) (player-command "chat" "specs/peedy-dialogue.lisp" "--wav" (format nil "~A,~A" good bad))
        (is (= 0 code) "~A" err)
        (let ((heard (chat-lines-starting "heard: " out)))
          (is (= 2 (length heard)) "~S" out)
          (is (search "heard: \"stop the music\" (score " (first heard)))
          (is (not (search "rejected" (first heard))))
          (is (or (search "heard: nothing" (second heard)) (search ", rejected)" (second heard))) "~S" heard))
        (is (equal '("input: evStop" "input: evBadSpeech (not understood)") (chat-lines-starting "input: " out)))))))

(test other-rates-and-channels-are-converted-and-long-wavs-refused
  (with-speech-libraries ("WAVs of other rates")
    (let* ((sound (utterance-sound (synthesize-speech "stop the music")))
           (stereo (speech-file "stereo-44k.wav")))
      ;; 44.1 kHz stereo through sox, as a user's recorder writes it.
      (write-wav (speech-file "mono.wav") sound)
      (sb-ext:run-program "sox" (list (speech-file "mono.wav") "-r" "44100" "-c" "2" stereo) :search t)
      (is (equal "stop the music" (recognize-wav stereo :grammar (dialogue-jsgf (jukebox)))))))
  ;; Ten minutes of silence: refused from its header, at once, before it is read.
  (let ((long (speech-file "ten-minutes.wav")))
    (write-wav long (make-sound (make-array (* 600 8000) :element-type '(signed-byte 16) :initial-element 0) 8000))
    (let ((start (get-internal-real-time)))
      (is (search "it lasts 600.0 s, and a spoken request at most 30 s"
                  (or (speech-error-text (lambda () (recognize-wav long :grammar (dialogue-jsgf (jukebox))))) "")))
      (is (< (- (get-internal-real-time) start) (* 2 internal-time-units-per-second))))
    (check-cli-error 1 "it lasts 600.0 s" "chat" "specs/peedy-dialogue.lisp" "--wav" long)))

;;; ---------------------------------------------------------------------------
;;; Push-to-talk: the viewer's key handler, pressed and released by hand

(test holding-enter-records-a-request
  (cond ((not (probe-file "/usr/bin/arecord"))
         (skip "arecord is not installed (Debian alsa-utils): push-to-talk not tested"))
        (t
         (with-speech-libraries ("push-to-talk")
           (let* ((home (file-microphone-home '("what do you have by debussy")))
                  (old (sb-posix:getenv "HOME"))
                  (conversation (jukebox-conversation :controller nil))
                  (turns '())
                  (handler (player.cli::make-push-to-talk
                            conversation (dialogue-jsgf (jukebox)) :device "wavin"
                            :turn (lambda (conversation text explain)
                                    (declare (ignore explain))
                                    (push (conversation-hear conversation text) turns))))
                  (out (make-string-output-stream)))
             (unwind-protect
                  (let ((*standard-output* out))
                    (sb-posix:setenv "HOME" (string-right-trim "/" home) 1)
                    (is-true (funcall handler nil player.render:+glfw-key-enter+ player.render:+glfw-press+))
                    (sleep 1)
                    (is-true (funcall handler nil player.render:+glfw-key-enter+ player.render:+glfw-release+))
                    ;; Other keys are the viewer's.
                    (is-false (funcall handler nil 65 player.render:+glfw-press+)))
               (sb-posix:setenv "HOME" old 1))
             (is (= 1 (length turns)))
             (is (equal '(("ARTIST" . "Claude Debussy")) (turn-slots (first turns))))
             (is (search "heard: \"what do you have by debussy\"" (get-output-stream-string out))))))))

;;; ---------------------------------------------------------------------------
;;; A microphone without hardware: an ALSA `file` PCM whose infile holds the
;;; requests (raw 16 kHz samples), named in a temporary HOME's .asoundrc.

(defun file-microphone-home (texts)
  "A temporary HOME whose .asoundrc defines the ALSA device `wavin`, reading
TEXTS spoken by espeak-ng, a second of silence after each."
  (let* ((home (speech-file "alsa-home/"))
         (raw (speech-file "alsa-home/requests.raw")))
    (ensure-directories-exist home)
    (with-open-file (out raw :direction :output :element-type '(unsigned-byte 8) :if-exists :supersede)
      (dolist (text texts)
        (let ((samples (sound-samples (player.speech::resample-sound (utterance-sound (synthesize-speech text)) 16000))))
          (loop for sample across (concatenate 'vector samples (make-array 16000 :initial-element 0))
                do (write-byte (ldb (byte 8 0) sample) out)
                   (write-byte (ldb (byte 8 8) sample) out)))))
    (with-open-file (out (format nil "~A.asoundrc" home) :direction :output :if-exists :supersede)
      (format out "pcm.wavin {~%  type file~%  slave.pcm \"null\"~%  file \"/dev/null\"~%  infile \"~A\"~%  format \"raw\"~%}~%" raw))
    home))

(test chat-listens-to-a-file-backed-microphone
  (cond ((not (probe-file "/usr/bin/arecord"))
         (skip "arecord is not installed (Debian alsa-utils): listening not tested"))
        (t
         (with-speech-libraries ("listening")
           (let ((home (file-microphone-home '("stop the music" "what do you have by debussy"))))
             (multiple-value-bind (out err code)
                 (let ((old (sb-posix:getenv "HOME")))
                   (unwind-protect (progn (sb-posix:setenv "HOME" (string-right-trim "/" home) 1)
                                          (player-command "chat" "specs/peedy-dialogue.lisp" "--listen"
                                                          "--device" "wavin" "--seconds" "8"))
                     (sb-posix:setenv "HOME" old 1)))
               (is (= 0 code) "~A" err)
               (is (search "; listening to wavin for 8 s" out))
               (is (equal '("input: evStop" "input: evHaveYouGot artist=\"Claude Debussy\"")
                          (chat-lines-starting "input: " out))
                   "~A" out)
               (is (= 2 (length (chat-lines-starting "heard: " out))))))
           (check-cli-error 1 "cannot open the microphone no-such-device: arecord says"
                            "chat" "specs/peedy-dialogue.lisp" "--listen" "--device" "no-such-device")
           (check-cli-error 2 "--wav and --listen are two sources" "chat" "specs/peedy-dialogue.lisp" "--listen" "--wav" "x.wav")
           (check-cli-error 2 "--device and --seconds say how to --listen" "chat" "specs/peedy-dialogue.lisp" "--seconds" "3")))))
