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
