;;;; test-music.lisp -- issue 28, item 6, music that plays: a track's tune
;;;; made once by sox and kept, the catalogue's :wav and :tempo, music ducked
;;;; under the voice in the mix, looping scripts of :beats at the music's
;;;; tempo, the jukebox playing and stopping on Peedy's performance, and a
;;;; dialogue naming a missing catalogue or WAV as one error line.

(in-package #:player-tests)

(def-suite* music :in player-tests)

(defmacro with-sox (&body body)
  "Run BODY when sox is installed; otherwise skip with a note."
  `(if (player.base::find-executable "sox")
       (progn ,@body)
       (skip "sox is not installed (Debian sox): made tunes not tested")))

(test a-track-tune-is-made-once-kept-and-sounds-like-itself
  (with-sox
    (let ((player.speech::*music-cache-directory* (pathname (scratch-directory "music-cache"))))
      (let* ((tune (player::track-tune "Angel From Montgomery" :tempo 120))
             (file (player.speech::tune-file "Angel From Montgomery" 120))
             (written (file-write-date file))
             (bars (* 8 (/ 60d0 120))))
        (is (probe-file file) "kept under the cache directory")
        ;; Whole bars of 8 beats at the tempo, repeated to about *tune-seconds*.
        (let ((repeats (/ (player::sound-duration tune) bars)))
          (is (< (abs (- repeats (round repeats))) 1d-3) "~,3F bars of 4 s" repeats)
          (is (<= 25 (player::sound-duration tune) 35)))
        (is (< 1000 (loudness tune 0 bars)) "it sounds")
        (sleep 1.1)
        (is (equalp (player::sound-samples tune)
                    (player::sound-samples (player::track-tune "Angel From Montgomery" :tempo 120))))
        (is (= written (file-write-date file)) "made once: the second call reads the kept file")
        (is (not (equalp (subseq (player::sound-samples tune) 0 44100)
                         (subseq (player::sound-samples (player::track-tune "Black Ocean" :tempo 120)) 0 44100)))
            "another title, another tune"))
      (is (<= 80 (player.speech::title-tempo "Black Ocean") 140))
      (signals player::argument-error (player::track-tune "" :tempo 120))
      (signals player::argument-error (player::track-tune "x" :tempo 1000)))))

(test catalogue-tracks-name-their-wav-and-tempo
  (let* ((snore (namestring (checkout-file "t/fixtures/snore.wav")))
         (cd (player.dialogue::parse-cd `(cd snores :title "Snores" :artist "Peedy"
                                             :tracks (("Deep Sleep" :wav ,snore :tempo 90) "Light Nap"))))
         (deep (first (player.dialogue::cd-tracks cd)))
         (light (second (player.dialogue::cd-tracks cd))))
    (is (equal (probe-file snore) (player.dialogue::track-wav deep)))
    (is (= 90 (player.dialogue::track-tempo deep)))
    (is (null (player.dialogue::track-wav light)))
    (multiple-value-bind (sound tempo) (player::track-sound deep)
      (is (< 1.3 (player::sound-duration sound) 1.5) "the WAV's own sound")
      (is (= 90 tempo))))
  (loop for (track fragment) in '((("Gone" :wav "t/fixtures/nonesuch.wav") "does not exist")
                                  (("Fast" :tempo 9000) "a track is")
                                  (("Odd" :wav) "a track is"))
        do (let ((text (handler-case (progn (player.dialogue::parse-cd
                                             `(cd x :title "X" :artist "Y" :tracks (,track)))
                                            nil)
                         (player::dialogue-error (e) (princ-to-string e)))))
             (is (and text (search fragment text)) "~S: ~A" track text))))

(test music-ducks-under-the-voice
  (let* ((rate 22050)
         (music (player::make-sound (coerce (loop for i below (* 4 rate) collect (round (* 8000 (sin (* i 0.06)))))
                                            'player.speech::samples)
                                    rate))
         (voice (player::make-sound (make-array rate :element-type '(signed-byte 16) :initial-element 0) rate))
         (mix (player::mix-clips (list (player::make-clip 0d0 music nil "music" :music)
                                       (player::make-clip 1.5d0 voice nil "silence" :voice))))
         (alone (loudness music 0.5 1.0)))
    (is (< (abs (- (loudness mix 0.5 1.0) alone)) 1) "far from the voice: as loud as it is")
    (is (< (abs (- (loudness mix 1.7 2.3) (* player.speech::*duck-gain* (loudness music 1.7 2.3)))) 1)
        "under the voice: at the ducked level")
    (is (< (* player.speech::*duck-gain* alone) (loudness mix 1.45 1.5) alone) "easing down before it")
    (is (< (abs (- (loudness mix 3.0 3.5) (loudness music 3.0 3.5))) 1) "back after it")
    ;; A sound effect is not music: it does not duck.
    (let ((mix (player::mix-clips (list (player::make-clip 0d0 music) (player::make-clip 1.5d0 voice nil "v" :voice)))))
      (is (< (abs (- (loudness mix 1.7 2.3) (loudness music 1.7 2.3))) 1)))))

(defun beat-library ()
  "A looping script of two beats that bends the right elbow to -60 on its first beat."
  (player.performance::parse-script-library-forms
   '((defscript tap (:duration 1 :loop t :beats 2)
       (:at 0 :motor (:keyframe :keys ((0 ((r_elbow x 0))) (0.5 ((r_elbow x -60))) (1 ((r_elbow x 0))))))))))

(defun right-elbow-at (performance time)
  "PERFORMANCE's right elbow flexion at TIME, in degrees."
  (player::performance-frame performance time)
  (let ((body (player::performance-body performance)))
    (aref (player::body-pose body) (player::dof-index (player::body-skeleton body) 'r_elbow :x))))

(test looping-scripts-of-beats-follow-the-music-s-tempo
  (let ((performance (player::make-performance (beat-library) '((bob humanoid)))))
    (player::perform-script performance 'tap 0 :loop t)
    (is (< (abs (- -60 (right-elbow-at performance 0.5))) 0.5) "no music: as written, the peak at 0.5 s")
    (is (< (abs (right-elbow-at performance 1.0)) 0.5)))
  ;; At 60 beats a minute two beats last 2 s: the peak comes at 1 s, and every 2 s.
  (let ((performance (player::make-performance (beat-library) '((bob humanoid)))))
    (player::performance-set-tempo performance 60 0)
    (player::perform-script performance 'tap 0 :loop t)
    (is (< (abs (- -60 (right-elbow-at performance 1.0))) 0.5) "at 60 bpm the peak is at 1 s: ~A" (right-elbow-at performance 1.0))
    (is (< (abs (right-elbow-at performance 2.0)) 0.5))
    (is (< (abs (- -60 (right-elbow-at performance 5.0))) 0.5) "and every 2 s after"))
  ;; A change of tempo takes effect from the next iteration.
  (let ((performance (player::make-performance (beat-library) '((bob humanoid)))))
    (player::perform-script performance 'tap 0 :loop t)
    (player::performance-set-tempo performance 240 2)
    (is (< (abs (- -60 (right-elbow-at performance 2.25))) 0.5) "at 240 bpm two beats last 0.5 s")
    (is (< (abs (- -60 (right-elbow-at performance 2.75))) 0.5))
    (is (< (abs (- -60 (right-elbow-at performance 1.5))) 0.5) "before the change, as written")))

(test the-jukebox-plays-the-track-and-stop-stops-it
  (if (not (and (espeak-available-p) (player.base::find-executable "sox")))
      (skip "libespeak-ng or sox is missing: the playing jukebox not tested")
      (multiple-value-bind (conversation speaker performance) (speaking-jukebox)
        (let ((controller (conversation-controller conversation)))
          (with-speaker (speaker)
            (conversation-hear conversation "hi")
            (speaker-wait speaker controller)
            (conversation-hear conversation "play something by madonna")
            (let* ((music (find :music (player::performance-clips performance (+ 1 (speaker-end speaker)))
                                :key #'player.speech::clip-kind))
                   (track (context-value conversation "playing")))
              (is-true music "the track is on the audio track as music")
              (is (player.dialogue::track-p track))
              (when music
                (is (string= (player.dialogue::track-title track) (player.speech::clip-label music)))
                (let ((answer (first (find "Here is" (speaker-lines speaker) :key #'third :test #'search))))
                  (is (and answer (<= 0 (- answer (player.speech::clip-start music)) 0.5))
                      "it starts when the CD is in, as Peedy answers (~A, ~A)" (player.speech::clip-start music) answer))
                (is (= (or (player.dialogue::track-tempo track) (player.speech::title-tempo (player.dialogue::track-title track)))
                       (player::performance-tempo performance (+ 0.1 (player.speech::clip-start music))))
                    "its tempo leads the tap-foot")
                (let ((tap (find "tap-foot" (player.performance::performance-runs performance)
                                 :key (lambda (run) (string (player.performance::script-name
                                                             (player.performance::script-run-script run))))
                                 :test #'string-equal))
                      (tempo (player::performance-tempo performance (+ 0.1 (player.speech::clip-start music)))))
                  (is-true tap "music-playing: Peedy taps his foot")
                  (when (and tap tempo)
                    (is (< (abs (- (/ 120d0 tempo)
                                   (player::script-duration
                                    (player.performance::run-iteration-script
                                     performance tap (+ 0.1 (player.speech::clip-start music))))))
                           1d-9)
                        "two taps a loop, at ~A beats a minute" tempo))))
              (speaker-wait speaker controller)
              (conversation-hear conversation "stop")
              (when music
                (is (<= 0 (- (first (first (speaker-lines speaker))) (player.speech::clip-end music)) 0.5)
                    "stop cuts it when Peedy has stopped the CD, as he says so (~A, ~A)"
                    (player.speech::clip-end music) (first (first (speaker-lines speaker))))
                (is (< (player.speech::clip-end music)
                       (+ (player.speech::clip-start music) (player::sound-duration (player.speech::clip-sound music))))
                    "before the track's end")
                (is (null (player::performance-tempo performance (+ 1 (player.speech::clip-end music)))))
                (let ((sound (player::performance-audio performance (+ 1 (player.speech::clip-end music)))))
                  (is (< 300 (loudness sound (+ 0.5 (player.speech::clip-start music))
                                       (+ 0.9 (player.speech::clip-start music))))
                      "the music sounds")))))))))

(test a-dialogue-naming-a-missing-catalogue-or-wav-is-one-error-line
  (let ((directory (scratch-directory "music-dialogues")))
    (flet ((write-dialogue (name catalogue-form)
             (let ((path (format nil "~A~A" directory name)))
               (with-open-file (out path :direction :output :if-exists :supersede)
                 (format out "(defdialogue bad-music (:player ~S) ~A (state s) (input ev) (utterance ev \"go\") (template t1 1 \"hi\"))~%"
                         (namestring (checkout-file "specs/peedy.lisp")) catalogue-form))
               path)))
      (loop for (file form fragment)
              in '(("no-catalogue.lisp" "(:catalogue \"nonesuch.lisp\")" "cannot open catalogue file")
                   ("no-wav.lisp" "(cd x :title \"X\" :artist \"Y\" :tracks ((\"Gone\" :wav \"gone.wav\")))"
                    "gone.wav does not exist"))
            do (multiple-value-bind (out err code)
                   (player-command-with-input "" "chat" (write-dialogue file form))
                 (declare (ignore out))
                 (is (= 1 code))
                 (is (= 1 (length (lines err))) "one line: ~S" err)
                 (is (and (alexandria:starts-with-subseq "player: error: " err) (search fragment err))
                     "~S" err))))))

(test a-long-track-is-mixed-only-as-far-as-it-is-heard
  (let* ((rate 22050)
         (long (player::make-sound (make-array (* 600 rate) :element-type '(signed-byte 16) :initial-element 1000) rate))
         (started (get-internal-real-time))
         (mix (player::mix-clips (list (player::make-clip 1d0 long nil "ten minutes" :music)) :end 3)))
    (is (= (* 3 rate) (length (player::sound-samples mix))))
    (is (= 1000 (aref (player::sound-samples mix) (* 2 rate))))
    (is (< (- (get-internal-real-time) started) (* 2 internal-time-units-per-second))
        "ten minutes of music under a 3 s track costs what 2 s of it do")))

(test the-viewer-silences-a-track-once-it-is-cut
  ;; A stand-in player that plays for 30 s: sh -c 'exec sleep 30' FILE.
  (let ((player.speech::*audio-players* '(("sh" "-c" "exec sleep 30")))
        (player.speech::*playing-clips* '())
        (clip (player::make-clip 0d0 (player::make-sound (make-array 100 :element-type '(signed-byte 16)
                                                                         :initial-element 0)
                                                         22050)
                                 nil "music" :music)))
    (let ((process (player.speech::play-clip-now clip)))
      (is (sb-ext:process-alive-p process))
      (player.speech::stop-cut-clips 5)
      (is (sb-ext:process-alive-p process) "not cut: it plays on")
      (setf (player.speech::clip-cut clip) 4d0)
      (player.speech::stop-cut-clips 5)
      (is (not (sb-ext:process-alive-p process)) "cut at 4 s: silenced at 5 s")
      (is (null player.speech::*playing-clips*)))))

(test the-viewer-ducks-the-music-under-a-voice
  (let* ((player.speech::*audio-players* '(("sh" "-c" "exec sleep 30")))
         (player.speech::*playing-clips* '())
         (rate 22050)
         (music (player::make-clip 0d0 (player::make-sound (make-array (* 10 rate) :element-type '(signed-byte 16)
                                                                                     :initial-element 8000)
                                                           rate)
                                   nil "music" :music))
         (voice (player::make-clip 2d0 (player::make-sound (make-array rate :element-type '(signed-byte 16)
                                                                            :initial-element 0)
                                                           rate)
                                   nil "hi" :voice))
         (first-process (player.speech::play-clip-now music)))
    (player.speech::play-clip-now voice)
    (let ((entry (find music player.speech::*playing-clips* :key #'first)))
      (is (not (sb-ext:process-alive-p first-process)) "the music restarted, ducked")
      (is-true entry)
      (when entry
        (let ((samples (player::sound-samples (player::read-wav (third entry)))))
          ;; It restarts at 2 s: its first half second is under the voice.
          (is (= (* 8 rate) (length samples)))
          (is (< (abs (- (aref samples (round (* 0.5 rate))) (* 8000 player.speech::*duck-gain*))) 2))
          (is (= 8000 (aref samples (* 2 rate))) "full again after the voice"))))
    (dolist (entry player.speech::*playing-clips*)
      (setf (player.speech::clip-cut (first entry)) 0d0))
    (player.speech::stop-cut-clips 1)
    (is (null player.speech::*playing-clips*))))

(defun op-line-times (text op)
  "The :start and :end of the trace line (:op OP ...) in TEXT, as two values."
  (let ((line (find-if (lambda (line) (alexandria:starts-with-subseq (format nil "(:op ~(~A~) " op) line))
                       (lines text))))
    (when line
      (let ((form (let ((*read-eval* nil) (*package* (find-package '#:keyword))) (read-from-string line))))
        (values (getf (cddr form) :start) (getf (cddr form) :end))))))

(test chat-render-puts-the-music-into-speech-wav
  (if (not (and (espeak-available-p) (player.base::find-executable "sox")))
      (skip "libespeak-ng or sox is missing: the rendered music not tested")
      (let ((out (speech-file "chat-music/")))
        (multiple-value-bind (text err code)
            (player-command-with-input (format nil "hi~%play something by madonna~%stop~%")
                                       "chat" "specs/peedy-dialogue.lisp" "--render" out "--fps" "4" "--size" "64x48")
          (is (= 0 code) "~A" err)
          (multiple-value-bind (play-start play-end) (op-line-times text 'play-cd)
            (multiple-value-bind (stop-start stop-end) (op-line-times text 'stop-cd)
              (is (and play-end stop-end) "~A" text)
              (when (and play-end stop-end)
                (let ((sound (read-wav (format nil "~Aspeech.wav" out))))
                  (is (< (loudness sound play-start (- play-end 0.1)) 50) "no music while the CD goes in")
                  (is (< 1000 (loudness sound (+ stop-start 0.1) (- stop-end 0.1)))
                      "the music plays while he reaches for stop")
                  ;; The render ends after his last words ("OK, the music is off."):
                  ;; had the music not stopped, it would sound there.
                  (let ((end (player::sound-duration sound)))
                    (is (< (loudness sound (- end 0.15) end) 50) "and stops with the CD"))))))))))
