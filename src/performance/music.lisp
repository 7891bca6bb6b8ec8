;;;; music.lisp -- music in a performance: a track put on the audio track
;;;; as music (ducked under the voices when mixed), the tempo it sets for
;;;; looping scripts of :beats (tempo.lisp), and stopping it.  The tempo is
;;;; a timeline, like the runs, so a replay from the start plays the same.

(in-package #:player.performance)

(defun performance-tempo (performance time)
  "The tempo, in beats a minute, of the music PERFORMANCE plays at TIME, or NIL."
  (cdr (find-if (lambda (entry) (<= (car entry) time)) (performance-tempi performance))))

(defun performance-set-tempo (performance tempo time)
  "From TIME on, PERFORMANCE's music has TEMPO beats a minute (NIL: no music).
A change before the time last shown replays from the start."
  (check-argument 'performance-set-tempo 'performance performance #'performance-p "a performance (from make-performance)")
  (check-argument 'performance-set-tempo 'tempo tempo (lambda (x) (or (null x) (and (realp x) (<= 30 x 300))))
                  "NIL or beats a minute, 30 to 300")
  (check-seconds 'performance-set-tempo 'time time)
  (let ((time (float time 1d0)))
    (setf (performance-tempi performance)
          (stable-sort (cons (cons time (and tempo (float tempo 1d0))) (performance-tempi performance))
                       #'> :key #'car))
    (when (and (performance-time performance) (< time (performance-time performance)))
      (setf (replay-stale performance) t))
    tempo))

(defun run-iteration-script (performance run begin)
  "The script RUN plays in its iteration beginning at BEGIN: a looping script
of :beats at the tempo then (SCRIPT-AT-TEMPO), any other as it is."
  (let ((script (script-run-script run)))
    (if (and (script-run-loop run) (script-beats script))
        (script-at-tempo script (performance-tempo performance begin))
        script)))

(defun performance-play-music (performance sound &key (at 0) tempo label body)
  "Put SOUND (a SOUND: a track, as TRACK-TUNE or READ-WAV gives) on
PERFORMANCE's audio track as music from AT seconds, ducked under the voices
when mixed, and make TEMPO (beats a minute, or NIL) the tempo looping
scripts of :beats follow from then.  LABEL says what it is (default
\"music\"), BODY as for PERFORMANCE-SAY.  Returns the SCRIPT-RUN playing it:
PERFORMANCE-STOP-MUSIC stops it.  A silent performance keeps the tempo and
plays no sound."
  (check-argument 'performance-play-music 'performance performance #'performance-p "a performance (from make-performance)")
  (check-argument 'performance-play-music 'sound sound #'sound-p "a sound (from track-tune or read-wav)")
  (check-seconds 'performance-play-music :at at :minimum 0)
  (when body (check-body-name 'performance-play-music performance body))
  (let* ((name (princ-to-string (or label "music")))
         (item (make-sound-item :at 0d0 :form (list :at 0 :sound name) :path (pathname name)
                                :sound sound :kind :music))
         (script (%make-script :name (make-symbol "MUSIC") :duration (sound-duration sound)
                               :items (list item) :form (list :music name))))
    (performance-set-tempo performance tempo at)
    (add-script-run performance (make-script-run script (float at 1d0) nil
                                                 (or body (performance-character performance)) nil))))

(defun performance-stop-music (performance run time)
  "Stop the music RUN (from PERFORMANCE-PLAY-MUSIC) at TIME: its sound is cut
there and the tempo ends."
  (stop-script-run performance run time)
  (performance-set-tempo performance nil time)
  run)
