;;;; test-speech.lisp -- speech output: WAV files, the phonemes-to-visemes
;;;; table, mixing, :say and :sound in script libraries, and the beak moving
;;;; with espeak-ng's phoneme timeline, checked on the rendered jaw DOF.
;;;; Tests that need libespeak-ng skip with a note when it is missing.

(in-package #:player-tests)

(def-suite* speech :in player-tests)

(defun espeak-available-p ()
  "Can this machine synthesise speech (libespeak-ng and its data installed)?"
  (handler-case (progn (player.speech::ensure-espeak) t)
    (player::speech-unavailable () nil)))

(defmacro with-espeak (&body body)
  "Run BODY when libespeak-ng is installed; otherwise skip with a visible note."
  `(if (espeak-available-p)
       (progn ,@body)
       (skip "libespeak-ng is not installed (Debian libespeak-ng1): speech synthesis not tested")))

(defun speech-error-text (function)
  "The report of the SPEECH-ERROR or SCRIPT-ERROR FUNCTION signals, or NIL."
  (handler-case (progn (funcall function) nil)
    ((or player::speech-error player::script-error) (e) (princ-to-string e))))

(defun speech-file (name)
  "NAME in the speech tests' scratch directory of this test run, as a string."
  (namestring (ensure-directories-exist
               (format nil "/tmp/player-render-tests-~D/speech/~A" (sb-posix:getpid) name))))

(defun write-octets (path octets)
  "Write the bytes OCTETS to PATH."
  (with-open-file (out path :direction :output :if-exists :supersede :element-type '(unsigned-byte 8))
    (write-sequence (coerce octets '(vector (unsigned-byte 8))) out))
  path)

(defun samples (&rest values)
  "A sample vector of VALUES."
  (coerce values 'player.speech::samples))

;;; ---------------------------------------------------------------------------
;;; WAV files

(test wav-files-round-trip
  (let* ((path (speech-file "round.wav"))
         (sound (player::make-sound (samples 0 1 -1 32767 -32768 1234 -4321) 8000)))
    (player::write-wav path sound)
    (let ((read (player::read-wav path)))
      (is (= 8000 (player::sound-rate read)))
      (is (equalp (player::sound-samples sound) (player::sound-samples read))))
    (with-open-file (in path :element-type '(unsigned-byte 8))
      (is (= (+ 44 (* 2 7)) (file-length in)) "a 44-byte header and 16-bit samples"))))

(defun wav-octets (&key (tag 1) (channels 1) (rate 8000) (bits 16) data)
  "The bytes of a WAV file with these header fields and the sample bytes DATA."
  (flet ((le (n size) (loop for i below size collect (ldb (byte 8 (* 8 i)) n)))
         (tag (text) (map 'list #'char-code text)))
    (append (tag "RIFF") (le (+ 36 (length data)) 4) (tag "WAVE")
            (tag "fmt ") (le 16 4) (le tag 2) (le channels 2) (le rate 4)
            (le (* rate channels (floor bits 8)) 4) (le (* channels (floor bits 8)) 2) (le bits 2)
            (tag "data") (le (length data) 4) data)))

(test wav-reading-mixes-channels-and-widens-8-bit
  (let ((stereo (speech-file "stereo.wav"))
        (bytes (speech-file "bytes.wav")))
    ;; Two frames of (left right): (100 300) and (-200 -400).
    (write-octets stereo (wav-octets :channels 2 :data '(100 0 44 1 56 255 112 254)))
    (is (equalp (samples 200 -300) (player::sound-samples (player::read-wav stereo))))
    (write-octets bytes (wav-octets :bits 8 :data '(128 255 0)))
    (is (equalp (samples 0 (* 127 256) -32768) (player::sound-samples (player::read-wav bytes))))))

(test unreadable-wavs-get-a-clear-error
  (let ((text (speech-file "text.wav"))
        (float (speech-file "float.wav"))
        (short (speech-file "short.wav")))
    (write-octets text (map 'list #'char-code "just some text, not a sound"))
    (write-octets float (wav-octets :tag 3 :bits 32 :data '(0 0 0 0)))
    (write-octets short (subseq (wav-octets :data '(1 0)) 0 20))
    (loop for (path fragment) in (list (list text "it is not a RIFF WAVE file")
                                       (list float "it is not PCM (format tag 3)")
                                       (list short "it has no data chunk")
                                       (list (speech-file "missing.wav") "there is no such file"))
          do (let ((message (speech-error-text (lambda () (player::read-wav path)))))
               (is (search (format nil "cannot read the WAV file ~A: ~A" path fragment) (or message ""))
                   "~A: ~S" path message)))))

(test resampling-keeps-a-tone
  ;; A 440 Hz tone at 22050 Hz resampled to 16000 Hz: same length in time, same loudness.
  (let* ((tone (player::make-sound (coerce (loop for i below 22050 collect (round (* 10000 (sin (/ (* 2 pi 440 i) 22050)))))
                                           'player.speech::samples)
                                   22050))
         (down (player.speech::resample-sound tone 16000)))
    (is (= 16000 (length (player::sound-samples down))))
    (is (< 9000 (reduce #'max (player::sound-samples down) :start 1000 :end 15000) 10500))))

;;; ---------------------------------------------------------------------------
;;; Phonemes, visemes, mixing

(test every-phoneme-maps-to-a-known-viseme
  (loop for (viseme . phonemes) in player.speech::*phoneme-visemes*
        do (is (player.body::viseme-opening viseme) "~A is not in *visemes*" viseme)
           (dolist (phoneme phonemes)
             (is (eq viseme (player::phoneme-viseme phoneme)))))
  ;; Pauses close the beak; open vowels open it most; lips shut for m b p.
  (is (eq :rest (player::phoneme-viseme "_:")))
  (is (eq :aa (player::phoneme-viseme "aI")))
  (is (eq :mm (player::phoneme-viseme "b")))
  (is (eq :dd (player::phoneme-viseme "t#")) "marks are stripped")
  (is (eq :ih (player::phoneme-viseme "%%")) "unknown phonemes half open"))

(test clips-mix-at-their-times
  (let* ((a (player::make-sound (samples 1000 1000 1000 1000) 10))
         (b (player::make-sound (samples 30000 30000) 10))
         (mix (player::mix-clips (list (player::make-clip 0.2d0 a) (player::make-clip 0.4d0 b)
                                       (player::make-clip 0.7d0 a 0.8d0))
                                 :rate 10)))
    (is (equalp (samples 0 0 1000 1000 31000 31000 0 1000) (player::sound-samples mix))
        "A at 0.2 s, B over its end at 0.4 s, A again cut after 0.1 s: ~S" (player::sound-samples mix))
    (is (equalp (samples 32767) (player::sound-samples
                                 (player::mix-clips (list (player::make-clip 0d0 b) (player::make-clip 0d0 b))
                                                    :rate 10 :end 0.1)))
        "the sum is clipped to 16 bits")
    (is (null (player::mix-clips '())))))

;;; ---------------------------------------------------------------------------
;;; :say and :sound in script libraries

(test say-and-sound-items-are-checked-when-read
  (let ((snore (namestring (checkout-file "t/fixtures/snore.wav"))))
    (let ((library (player.performance::parse-script-library-forms
                    `((defscript talk (:duration 2) (:at 0.5 :say "Hello there" :rate 150 :voice "en-us"))
                      (defscript snore () (:at 0.25 :sound ,snore))))))
      (is (typep (first (player.performance::script-items (player::find-script library 'talk))) 'player.performance::say-item))
      (is (< 1.6 (player::script-duration (player::find-script library 'snore)) 1.7)
          "a sound's script lasts until the sound ends (0.25 s + 1.4 s)")))
  (loop for (item fragment) in '(((:at 0 :say 42) ":say takes the text to speak")
                                 ((:at 0 :say "") ":say takes the text to speak")
                                 ((:at 0 :say "hi" :rate 20) ":rate must be an integer from 80 to 450")
                                 ((:at 0 :say "hi" :pitch 3) "has no option :pitch")
                                 ((:at 0 :sound "no-such-file.wav") "cannot read the WAV file")
                                 ((:at 0 :sound 7) ":sound takes a WAV file's name"))
        do (let ((message (speech-error-text
                           (lambda () (player.performance::parse-script-library-forms `((defscript bad () ,item)))))))
             (is (search fragment (or message "")) "~S: ~S" item message))))

;;; ---------------------------------------------------------------------------
;;; Synthesis and the beak

(defparameter *spoken-line* "Hello, I have Bonnie Maple from nineteen ninety."
  "A line with a pause (the comma) inside it.")

(defun audible-span (sound &optional (fraction 0.02))
  "The first and last time (seconds) SOUND's samples exceed FRACTION of its peak."
  (let* ((samples (player::sound-samples sound))
         (threshold (* fraction (reduce #'max samples :key #'abs)))
         (first (position-if (lambda (x) (> (abs x) threshold)) samples))
         (last (position-if (lambda (x) (> (abs x) threshold)) samples :from-end t))
         (rate (float (player::sound-rate sound) 1d0)))
    (values (/ first rate) (/ last rate))))

(defun spoken-phonemes (utterance)
  "UTTERANCE's phonemes that are not pauses."
  (remove-if (lambda (p) (eq :rest (player::phoneme-viseme (first p)))) (player::utterance-phonemes utterance)))

(test phoneme-timeline-is-monotone-and-covers-the-audio
  (with-espeak
    (let* ((utterance (player::synthesize-speech *spoken-line*))
           (phonemes (player::utterance-phonemes utterance))
           (duration (player::utterance-duration utterance)))
      (is (= 22050 (player::sound-rate (player::utterance-sound utterance))))
      (is (< 2 duration 5) "~,2F s" duration)
      (is (< 25 (length phonemes)))
      (is (= 0 (second (first phonemes))))
      (is (loop for ((nil start end) next) on phonemes
                always (and (<= start end) (or (null next) (= end (second next)))))
          "each phoneme ends where the next starts")
      (is (< (abs (- duration (third (car (last phonemes))))) 1d-9))
      ;; Independently of the events: where the sound is audible.
      (multiple-value-bind (onset offset) (audible-span (player::utterance-sound utterance))
        (let ((spoken (spoken-phonemes utterance)))
          (is (< (abs (- onset (second (first spoken)))) 0.05) "speech starts at ~,3F, its first phoneme at ~,3F"
              onset (second (first spoken)))
          (is (< (abs (- offset (third (car (last spoken))))) 0.05) "speech ends at ~,3F, its last phoneme at ~,3F"
              offset (third (car (last spoken)))))))
    (is (eq (player::synthesize-speech *spoken-line*) (player::synthesize-speech *spoken-line*))
        "utterances are kept")
    (is (search "has no voice xx-nonesuch"
                (or (speech-error-text (lambda () (player::synthesize-speech "hi" :voice "xx-nonesuch"))) "")))))

(defun talking-performance (&key silent)
  "A parrot performance whose script TALK says *SPOKEN-LINE* 0.5 s in, started at 0."
  (let* ((library (player.performance::parse-script-library-forms
                   `((defscript talk (:duration 5) (:at 0.5 :say ,*spoken-line*)))))
         (performance (player::make-performance library '((polly parrot)) :silent silent)))
    (player::perform-script performance 'talk 0)
    performance))

(defun jaw-samples (performance end &optional (step 0.01d0))
  "The parrot's beak opening (the DOF's fraction of its range) in PERFORMANCE
every STEP seconds up to END, as a vector."
  (let* ((body (player::performance-body performance))
         (index (player::dof-index (player::body-skeleton body) 'beak 'open))
         (high (player.body::body-dof-max (nth-value 1 (player.body::skeleton-dof (player::body-skeleton body) index)))))
    (coerce (loop for time from 0d0 to end by step
                  collect (progn (player::performance-frame performance time)
                                 (/ (aref (player::body-pose (player::performance-body performance)) index) high)))
            'vector)))

(test the-beak-opens-in-vowels-and-closes-in-silences
  (with-espeak
    (let* ((performance (talking-performance))
           (utterance (player::synthesize-speech *spoken-line*))
           (jaw (jaw-samples performance 4.5))
           (pauses 0))
      (flet ((jaw-at (seconds) (aref jaw (round (+ seconds 0.5) 0.01))))
        (is (every (lambda (x) (< (abs x) 1d-6)) (subseq jaw 0 45)) "closed before speaking")
        (is (< (abs (jaw-at (+ (player::utterance-duration utterance) 0.2))) 0.01) "closed after speaking")
        (loop for (name start end) in (player::utterance-phonemes utterance)
              for viseme = (player::phoneme-viseme name)
              for middle = (/ (+ start end) 2)
              do (cond ((and (member viseme '(:aa :oh :ih)) (> (- end start) 0.06))
                        (is (> (jaw-at middle) 0.2) "vowel ~A at ~,2F s: the beak is only ~,2F open"
                            name middle (jaw-at middle)))
                       ((and (eq viseme :rest) (> (- end start) 0.12) (< end (player::utterance-duration utterance)))
                        (incf pauses)
                        (is (< (jaw-at middle) 0.05) "pause at ~,2F s: the beak is ~,2F open"
                            middle (jaw-at middle))))))
      (is (<= 1 pauses) "the comma makes a pause")
      (is (< 0.5 (reduce #'max jaw)) "the beak opens wide somewhere"))))

(test said-speech-is-on-the-audio-track
  (with-espeak
    (let* ((performance (talking-performance))
           (utterance (player::synthesize-speech *spoken-line*))
           (track (player::performance-audio performance 5))
           (offset (round (* 0.5 22050))))
      (is (= (* 5 22050) (length (player::sound-samples track))))
      (is (equalp (player::sound-samples (player::utterance-sound utterance))
                  (subseq (player::sound-samples track) offset
                          (+ offset (length (player::sound-samples (player::utterance-sound utterance))))))
          "the utterance's samples, 0.5 s in")
      (is (every #'zerop (subseq (player::sound-samples track) 0 offset))))
    ;; PERFORMANCE-SAY adds speech at a time; stopping its run cuts it.
    (let ((performance (talking-performance)))
      (multiple-value-bind (duration run) (player::performance-say performance "Thank you" :at 3)
        (is (< 0.4 duration 1.5))
        (let ((clips (player::performance-clips performance 5)))
          (is (equal '(0.5d0 3d0) (mapcar #'player.speech::clip-start clips)))
          (is (equal "Thank you" (player.speech::clip-label (second clips)))))
        (player::stop-script-run performance run 3.2d0)
        (is (= 3.2d0 (player.speech::clip-end (second (player::performance-clips performance 5)))))))
    ;; Silent: no sound, no beak.
    (let ((performance (talking-performance :silent t)))
      (is (null (player::performance-audio performance 5)))
      (is (every #'zerop (jaw-samples performance 3 0.1))))))

(test simulate-writes-speech-wav-beside-the-frames
  (with-espeak
    (let* ((out (scratch-directory "simulate-speech"))
           (simulation (player::simulate (player.cli::choose-spec (checkout-file "specs/peedy.lisp") nil)
                                         :events '("ev-bad-speech") :fps 10))
           (paths (player::write-simulation simulation :frames (format nil "~Aframes.txt" out)
                                                       :audio (format nil "~Aspeech.wav" out))))
      (is (equal (list "frames.txt" "speech.wav") (mapcar #'file-namestring paths)))
      (let ((sound (player::read-wav (second paths))))
        (is (< (abs (- (player::sound-duration sound) (player.performance::simulation-duration simulation))) 0.01))
        (is (some (lambda (x) (> (abs x) 1000)) (player::sound-samples sound)) "Peedy says huh"))
      ;; Silent: no file written, and an old one is left alone (issue 31: nothing
      ;; the user did not name is deleted).
      (is (null (player::write-simulation
                 (player::simulate (player.cli::choose-spec (checkout-file "specs/peedy.lisp") nil)
                                   :events '("ev-bad-speech") :fps 10 :silent t)
                 :audio (format nil "~Aspeech.wav" out))))
      (is (probe-file (format nil "~Aspeech.wav" out))))))

(test a-missing-espeak-is-one-clear-error-and-silence-still-works
  (let ((player.speech::*espeak-library-names* '("libespeak-ng-missing-for-a-test.so.1"))
        (player.speech::*espeak-rate* nil)
        (player.speech::*utterances* (make-hash-table :test #'equal)))
    (let ((condition (handler-case (progn (player::synthesize-speech "hello") nil)
                       (player::speech-unavailable (c) c))))
      (is (typep condition 'player::speech-unavailable))
      (let ((line (and condition (player.base::condition-line condition))))
        (is (search "install the Debian package libespeak-ng1" (or line "")) "~S" line)))
    ;; Peedy's huh? says something; silently it plays without espeak.
    (let ((simulation (player::simulate (player.cli::choose-spec (checkout-file "specs/peedy.lisp") nil)
                                        :events '("ev-bad-speech") :fps 10 :silent t)))
      (is (< 1 (player.performance::simulation-end simulation)))
      (is (null (player::write-simulation simulation :audio (speech-file "none.wav")))))))

(test speech-api-rejects-bad-arguments
  (flet ((rejects (function thunk)
           (let ((condition (handler-case (progn (funcall thunk) nil) (player::argument-error (c) c))))
             (is (and condition (eq function (player::argument-error-function condition)))
                 "~A accepted a bad argument" function))))
    (rejects 'synthesize-speech (lambda () (synthesize-speech 42)))
    (rejects 'synthesize-speech (lambda () (synthesize-speech "")))
    (rejects 'synthesize-speech (lambda () (synthesize-speech "hi" :rate 10000)))
    (rejects 'synthesize-speech (lambda () (synthesize-speech "hi" :voice '(en))))
    (rejects 'read-wav (lambda () (read-wav 42)))
    (rejects 'write-wav (lambda () (write-wav (speech-file "x.wav") "not a sound")))
    (rejects 'recognize-wav (lambda () (recognize-wav nil :grammar "#JSGF V1.0;")))
    (rejects 'recognize-wav (lambda () (recognize-wav (speech-file "x.wav") :grammar 42)))
    (rejects 'performance-say (lambda () (performance-say 42 "hello")))
    (rejects 'performance-say (lambda () (performance-say (talking-performance :silent t) "hello" :at -1)))
    (rejects 'performance-say (lambda () (performance-say (talking-performance :silent t) "hello" :body 'nobody)))))

;;; ---------------------------------------------------------------------------
;;; The command line: speech.wav, the video's sound, the viewer

(test simulate-and-render-commands-write-speech
  (with-espeak
    (let ((out (scratch-directory "speech-commands")))
      (multiple-value-bind (text err code)
          (player-command "simulate" (namestring (checkout-file "specs/peedy.lisp")) "--events" "ev-bad-speech"
                          "--fps" "10" "--frames" (format nil "~Aframes.txt" out))
        (is (= 0 code) "stderr: ~A" err)
        (is (search (format nil "; wrote ~Aspeech.wav" out) text) "~A" text))
      (if (not (player.base::find-executable "ffmpeg"))
          (skip "ffmpeg is not installed: the video's sound track not tested")
          (let ((video (format nil "~Ahuh.mp4" out)))
            (multiple-value-bind (text err code)
                (player-command "render" (namestring (checkout-file "specs/peedy.lisp")) "--events" "ev-bad-speech"
                                "--fps" "4" "--size" "32x24" "--out" out "--video" video)
              (is (= 0 code) "stderr: ~A" err)
              (is (search (format nil "; wrote ~Aspeech.wav" out) text) "~A" text)
              (is (search (format nil "; wrote ~A" video) text)))
            (let ((streams (with-output-to-string (s)
                             (sb-ext:run-program "ffprobe" (list "-v" "error" "-show_entries" "stream=codec_type"
                                                                 "-of" "csv=p=0" video)
                                                 :search t :output s))))
              (is (equal '("video" "audio") (lines streams)) "streams of the video: ~S" streams)))))))

(test the-viewer-plays-sound-or-says-once-it-cannot
  (with-espeak
    (with-window-programs ()
      (multiple-value-bind (out err code)
          (view-command (list (namestring (checkout-file "specs/peedy.lisp")) "--size" "64x48"
                              "--frames" "120" "--keys" "2@0"))
        (is (= 0 code) "exit ~D, stderr: ~A" code err)
        (let ((notes (count-if (lambda (line) (search "playing silently" line)) (lines out))))
          (if (player.speech::audio-playback-problem)
              (is (= 1 notes) "~D notes in ~A" notes out)
              (is (= 0 notes))))))))
