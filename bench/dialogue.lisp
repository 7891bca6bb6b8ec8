;;;; dialogue.lisp -- issue 15's figure: one turn of Peedy's jukebox dialogue,
;;;; from the typed sentence to the Player events it sends (matching, the
;;;; input's query, choosing the transition, templates, episodic memory and
;;;; Peedy's controller on a null presenter), without audio.  Two turns are
;;;; paraphrases, scored against every pattern (issue 28).

(in-package #:player-bench)

(defparameter *dialogue-file* (merge-pathnames "../specs/peedy-dialogue.lisp" *bench-directory*))

(defparameter *dialogue-turns*
  '("hello" "have you got anything by bonnie raitt" "sure" "no" "who wrote that" "yes"
    "mumble" "stop the music" "play something by andrew lloyd webber after that" "thanks"
    "let's see, i think i'd like to hear a little debussy" "play before you accuse me by clapton")
  "A conversation that visits every state; the benchmark plays it again and again.")

(defun play-dialogue-round (dialogue machine)
  "One conversation of *DIALOGUE-TURNS*, with a fresh memory and controller."
  (let ((conversation (player:make-conversation
                       dialogue :controller (player:make-controller
                                             machine :presenter (player:make-null-presenter)
                                                     :initial-state (player:dialogue-player-initial dialogue)))))
    (dolist (text *dialogue-turns*)
      (player:conversation-hear conversation text))))

(defun bench-dialogue ()
  "The row for a dialogue turn: text to Player events."
  (let* ((dialogue (first (player:load-dialogue *dialogue-file*)))
         (machine (player:compile-spec (player:dialogue-player-spec dialogue)))
         (per-turn (/ (seconds-per-call (lambda () (play-dialogue-round dialogue machine)))
                      (length *dialogue-turns*))))
    (row "11. dialogue turn, typed text to Player events (jukebox, null presenter)"
         (format-seconds per-turn) "< 1 ms" (< per-turn 1d-3))
    (note "dialogue turn: a conversation of ~D turns, a fresh memory and controller each time"
          (length *dialogue-turns*))))

;;;# Spoken turns (issue 28): a WAV heard and played as a turn, and a microphone's latency

(defparameter *spoken-turns*
  '("have you got anything by bonnie raitt" "sure" "who wrote that" "stop the music")
  "What is said, by espeak-ng's en-us voice, for the spoken rows.")

(defun spoken-dialogue ()
  "The jukebox dialogue and a conversation of it on a null presenter."
  (let ((dialogue (first (player:load-dialogue *dialogue-file*))))
    (values dialogue
            (player:make-conversation
             dialogue :controller (player:make-controller (player:compile-spec (player:dialogue-player-spec dialogue))
                                                          :presenter (player:make-null-presenter)
                                                          :initial-state (player:dialogue-player-initial dialogue))))))

(defun bench-spoken-turn ()
  "The row for a spoken turn: recognition with its rejection pass, then the
turn, per second of speech."
  (multiple-value-bind (dialogue conversation) (spoken-dialogue)
    (let* ((grammar (player:dialogue-jsgf dialogue))
           (sounds (mapcar (lambda (text) (player:utterance-sound (player:synthesize-speech text))) *spoken-turns*))
           (speech (reduce #'+ sounds :key #'player:sound-duration))
           (seconds (seconds-per-call (lambda ()
                                        (dolist (sound sounds)
                                          (player:conversation-hear conversation (player:recognize-sound sound :grammar grammar))))
                                      :batches 3 :batch-seconds 0.1d0 :max-seconds 15)))
      (row "spoken turn: WAV heard (grammar and phone loop) and played (jukebox)"
           (format nil "~,3F x real time" (/ seconds speech)) "< 0.3 x" (< (/ seconds speech) 0.3)))))

(defun file-microphone (texts directory)
  "Write DIRECTORY/.asoundrc defining the ALSA device `wavin`, a file PCM
whose infile holds TEXTS said by espeak-ng, a second of silence after each."
  (let ((raw (merge-pathnames "requests.raw" directory)))
    (ensure-directories-exist directory)
    (with-open-file (out raw :direction :output :element-type '(unsigned-byte 8) :if-exists :supersede)
      (dolist (text texts)
        (let ((samples (player:sound-samples (player.speech::resample-sound
                                              (player:utterance-sound (player:synthesize-speech text)) 16000))))
          (loop for sample across (concatenate 'vector samples (make-array 16000 :initial-element 0))
                do (write-byte (ldb (byte 8 0) sample) out) (write-byte (ldb (byte 8 8) sample) out)))))
    (with-open-file (out (merge-pathnames ".asoundrc" directory) :direction :output :if-exists :supersede)
      (format out "pcm.wavin { type file slave.pcm \"null\" file \"/dev/null\" infile \"~A\" format \"raw\" }~%"
              (namestring raw)))))

(defun bench-microphone ()
  "The row for a microphone's latency: from the moment the voice-activity
detection hears an utterance end to the turn's Player events sent (the next
frame draws them), the worst of *SPOKEN-TURNS* read from a file-backed ALSA
device.  The half second of silence that ends an utterance comes before."
  (multiple-value-bind (dialogue conversation) (spoken-dialogue)
    (let ((directory (merge-pathnames (format nil "player-bench-mic-~D/" (sb-posix:getpid)) #p"/tmp/"))
          (home (sb-posix:getenv "HOME"))
          (worst 0d0) (heard 0))
      (file-microphone *spoken-turns* directory)
      (unwind-protect
           (progn
             (sb-posix:setenv "HOME" (string-right-trim "/" (namestring directory)) 1)
             (let ((capture (player:open-capture :device "wavin")))
               (unwind-protect
                    (player:listen-for-requests
                     capture (player:dialogue-jsgf dialogue)
                     (lambda (text score sentence heard-at)
                       (declare (ignore score sentence))
                       (player:conversation-hear conversation text)
                       (incf heard)
                       (setf worst (max worst (/ (- (get-internal-real-time) heard-at)
                                                 (float internal-time-units-per-second 1d0))))
                       nil)
                     :seconds (+ 2 (* 4 (length *spoken-turns*))))
                 (player:close-capture capture))))
        (sb-posix:setenv "HOME" home 1))
      (row (format nil "microphone: utterance end to Peedy's events (worst of ~D, file-backed ALSA)" heard)
           (format-seconds worst) "< 300 ms" (< worst 0.3d0)))))

(defun bench-speaking-dialogue ()
  "The spoken rows, or one saying why they were not run."
  (handler-case (progn (bench-spoken-turn) (bench-microphone))
    (player:speech-error (e)
      (row "spoken turn and microphone" (format nil "not run: ~A" e) "-" ""))))
