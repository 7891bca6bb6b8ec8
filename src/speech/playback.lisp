;;;; playback.lisp -- sounds played live on the machine's audio device, for
;;;; the viewer: each clip written to a temporary WAV and handed to aplay
;;;; (alsa-utils) or sox's play, which run beside Player.  Without a device
;;;; or either program, nothing plays and the caller says so once.

(in-package #:player.speech)

(defparameter *audio-players* '(("aplay" "-q") ("play" "-q"))
  "Programs that play a WAV file given last, with their arguments, tried in order.")

(defun audio-player ()
  "The first of *AUDIO-PLAYERS* installed, as (PATH ARGUMENT...), or NIL."
  (loop for (name . arguments) in *audio-players*
        for path = (find-executable name)
        when path return (cons (namestring path) arguments)))

(defun audio-device-p ()
  "Has this machine a sound card that plays (an ALSA playback device, /dev/snd/pcm*p)?"
  (and (directory #p"/dev/snd/pcm*p") t))

(defun audio-playback-problem ()
  "Why sounds cannot be played here, as a phrase, or NIL when they can."
  (cond ((not (audio-device-p)) "no audio device")
        ((not (audio-player)) "no audio player (install the Debian package alsa-utils or sox)")))

(defvar *playback-counter* 0 "Numbers the temporary files of sounds played.")

(defun play-sound-now (sound)
  "Start playing SOUND on the audio device and return at once (the process
plays on).  Returns the process, or NIL when there is no player."
  (let ((player (audio-player)))
    (when player
      ;; In a private folder of its own (mode 0700, made exclusively): a
      ;; link planted in /tmp cannot redirect the write.
      (let* ((folder (make-private-folder (temporary-file "") "player-sound"))
             (path (merge-pathnames (format nil "sound-~D.wav" (incf *playback-counter*)) folder)))
        (unregister-cleanup folder)     ; the player's shell removes it when played
        (write-wav path sound)
        (sb-ext:run-program "/bin/sh"
                            ;; sh -c 'PLAYER ARGS FILE; rm -r FOLDER': the folder goes when played.
                            (append (list "-c" "\"$@\"; rm -rf \"$0\"" (sb-ext:native-namestring folder))
                                    player (list (namestring path)))
                            :wait nil :output nil :error nil :input nil)))))

;;;# Clips that can be cut while they play (music the user stops)

(defvar *playing-clips* '()
  "Clips played by PLAY-CLIP-NOW that may still sound: (CLIP PROCESS PATH).")

(defun play-clip-now (clip)
  "Start playing CLIP's sound on the audio device and return at once; unlike
PLAY-SOUND-NOW, the player runs as its own process, so STOP-CUT-CLIPS can
silence it when CLIP is cut (\"stop the music\").  A voice clip ducks the
music playing (DUCK-PLAYING-MUSIC).  Returns the process, or NIL when there
is no player."
  (when (eq (clip-kind clip) :voice)
    (duck-playing-music clip))
  (start-clip-process clip (clip-sound clip)))

(defun start-clip-process (clip sound)
  "Play SOUND for CLIP in a player process of its own, remembered in *PLAYING-CLIPS*."
  (let ((player (audio-player)))
    (when player
      (let ((path (temporary-file (format nil "player-~D-~D.wav" (sb-posix:getpid) (incf *playback-counter*)))))
        (write-wav path sound)
        (let ((process (sb-ext:run-program (first player) (append (rest player) (list (namestring path)))
                                           :wait nil :output nil :error nil :input nil)))
          (push (list clip process path) *playing-clips*)
          process)))))

(defun duck-playing-music (voice)
  "Duck the music clips playing under the VOICE clip starting now: each is
restarted from where it is, quieter while VOICE sounds (DUCK-GAIN), as the
mix of a render has it.  (A player process cannot change its volume.)"
  (loop for entry in *playing-clips*
        for (clip process path) = entry
        when (and (eq (clip-kind clip) :music) (sb-ext:process-alive-p process))
          do (let* ((sound (clip-sound clip))
                    (rate (sound-rate sound))
                    (from (max 0 (round (* (- (clip-start voice) (clip-start clip)) rate))))
                    (voices (list (cons (clip-start voice) (clip-end voice))))
                    (rest (subseq (sound-samples sound) (min from (length (sound-samples sound))))))
               (dotimes (i (length rest))
                 (setf (aref rest i)
                       (round (* (aref rest i) (duck-gain voices (+ (clip-start clip) (/ (+ from i) (float rate 1d0))))))))
               (ignore-errors (sb-ext:process-kill process 15))
               (ignore-errors (sb-ext:process-wait process))
               (ignore-errors (delete-file path))
               (setf *playing-clips* (remove entry *playing-clips*))
               (start-clip-process clip (make-sound rest rate)))))

(defun stop-cut-clips (time)
  "Silence each clip PLAY-CLIP-NOW started whose cut comes by TIME (seconds on
its track), and forget those that have finished, removing their files."
  (setf *playing-clips*
        (loop for entry in *playing-clips*
              for (clip process path) = entry
              for cut = (and (clip-cut clip) (<= (clip-cut clip) time))
              do (when (and cut (sb-ext:process-alive-p process))
                   (ignore-errors (sb-ext:process-kill process 15)))
              if (or cut (not (sb-ext:process-alive-p process)))
                do (ignore-errors (sb-ext:process-wait process))
                   (ignore-errors (delete-file path))
              else collect entry)))
