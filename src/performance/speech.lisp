;;;; speech.lisp -- speech and sound effects in a performance: a :say item
;;;; (or PERFORMANCE-SAY) moves the jaw through its utterance's visemes and
;;;; puts its sound on the audio track; a :sound item puts a WAV there.  The
;;;; track is what the replay played, mixed on demand, so it follows the
;;;; frames: a stopped script cuts its sounds where it stops.

(in-package #:player.performance)

(defun add-clip (performance run clip)
  "Put CLIP on PERFORMANCE's track, remembered by RUN so stopping RUN cuts it."
  (push clip (script-run-clips run))
  (push clip (replay-clips performance)))

(defun play-audio-item (performance item run time end body-name)
  "Play the :say or :sound ITEM of RUN at TIME on the body BODY-NAME, cut at END
\(or NIL): a :say moves the jaw and both put their sound on the track.  A
silent performance plays nothing."
  (unless (performance-silent performance)
    (etypecase item
      (say-item
       (let* ((utterance (say-item-utterance item))
              (body (performance-body performance body-name))
              (driver (make-driver (say-item-motor-call (utterance-visemes utterance)) body time :stop end)))
         (push driver (script-run-drivers run))
         (body-add-driver body driver)
         (add-clip performance run (make-clip time (utterance-sound utterance) end (utterance-text utterance) :voice))))
      (sound-item
       (add-clip performance run (make-clip time (sound-item-sound item) end
                                            (namestring (sound-item-path item)) (sound-item-kind item)))))))

(defparameter *word-gestures*
  '((:beat 0.15 (:beat :arm :right :times (0.15) :stroke 0.12 :retract 0.25))
    (:point 0.35 (:reach :arm :right :target :listener :duration 0.35 :hold t) 0.5))
  "(NAME LEAD FRAME [HOLD]): a gesture a dialogue template or PERFORMANCE-SAY
lands on a word.  FRAME starts LEAD seconds before the word, so a beat's
stroke or a point's arrival falls on it; with HOLD it lasts until HOLD
seconds after the word ends.  The target :LISTENER is the scene's USER
object, else its CAMERA, else a point ahead of the body.")

;;;# Saying something on a running performance

(defun performance-say (performance text &key (at 0) voice rate body gestures)
  "Make BODY (default: the first character) of PERFORMANCE say TEXT at AT
seconds: its jaw moves through the utterance's visemes and the sound goes on
the audio track, as a :say item does.  VOICE and RATE as for
SYNTHESIZE-SPEECH.  GESTURES, ((WORD GESTURE) ...), lands each GESTURE (a
name of *WORD-GESTURES*, :beat or :point) on a word of TEXT (its number from
1, or the word itself), as an item timed (:word WORD) does.  Returns the
seconds the speech lasts (0 when PERFORMANCE is silent) and the SCRIPT-RUN
playing it (STOP-SCRIPT-RUN cuts it short).  Signals what SYNTHESIZE-SPEECH
signals."
  (check-argument 'performance-say 'performance performance #'performance-p "a performance (from make-performance)")
  (check-argument 'performance-say 'text text (lambda (x) (and (stringp x) (<= 1 (length x) 2000)))
                  "a string of 1 to 2000 characters")
  (check-seconds 'performance-say :at at :minimum 0)
  (when body (check-body-name 'performance-say performance body))
  (check-argument 'performance-say :gestures gestures
                  (lambda (x) (and (alexandria:proper-list-p x)
                                   (every (lambda (g) (and (alexandria:proper-list-p g) (= 2 (length g))
                                                           (typep (first g) '(or (integer 1) string))
                                                           (assoc (second g) *word-gestures*)))
                                          x)))
                  "a list of (WORD GESTURE), WORD a word's number from 1 or the word, GESTURE :beat or :point")
  (let* ((silent (performance-silent performance))
         (duration (if silent
                       0d0
                       (utterance-duration (synthesize-speech text :voice (or voice *default-voice*)
                                                                   :rate (or rate *default-speech-rate*)))))
         (item (make-say-item :at 0d0 :form (list :at 0 :say text) :text text :voice voice :rate rate))
         (script (%make-script :name (make-symbol "SAY") :duration duration
                               :items (cons item (unless silent
                                                   (word-gesture-items performance item gestures body)))
                               :form (list :say text))))
    (values duration
            (add-script-run performance
                            (make-script-run script (float at 1d0) nil
                                             (or body (performance-character performance)) nil)))))

;;;# Gestures on words

(defun listener-target (performance)
  "Where a pointing gesture points in PERFORMANCE's scene: see *WORD-GESTURES*."
  (let ((scene (performance-scene performance)))
    (cond ((find-object scene 'user nil) '(:object user))
          ((find-object scene 'camera nil) '(:object camera))
          (t '(:point 0 1.2 1.5)))))

(defun word-gesture-items (performance say gestures body)
  "Motor items that land GESTURES, ((WORD GESTURE) ...), on the words of the
:say item SAY, each timed as (:at (:word WORD)) would be."
  (declare (ignore body))
  (loop for (word name) in gestures
        for (nil lead frame hold) = (assoc name *word-gestures*)
        for utterance = (say-item-utterance say)
        for (start end) = (multiple-value-list (utterance-word-time utterance word))
        when start
          collect (let* ((frame (subst (listener-target performance) :listener frame))
                         (at (max 0d0 (- start lead))))
                    (make-motor-item :at at :form (list :at (list :word word) :motor frame)
                                     :until (and hold (- (+ end hold) at))
                                     :frame frame :call (parse-motor-frame frame)))))

;;;# Playing a sound on a running performance

(defun performance-play-sound (performance sound &key (at 0) label body)
  "Put SOUND (a SOUND, as READ-WAV gives) on PERFORMANCE's audio track at AT
seconds, as a :sound item does; LABEL (a string or pathname, default
\"sound\") says what it is.  BODY as for PERFORMANCE-SAY.  Returns the seconds
SOUND lasts (0 when PERFORMANCE is silent).  What a dialogue puts on the
track for the user's spoken request."
  (check-argument 'performance-play-sound 'performance performance #'performance-p "a performance (from make-performance)")
  (check-argument 'performance-play-sound 'sound sound #'sound-p "a sound (from read-wav or synthesize-speech)")
  (check-seconds 'performance-play-sound :at at :minimum 0)
  (when body (check-body-name 'performance-play-sound performance body))
  (let* ((duration (if (performance-silent performance) 0d0 (sound-duration sound)))
         (item (make-sound-item :at 0d0 :form (list :at 0 :sound (princ-to-string (or label "sound")))
                                :path (pathname (or label "sound")) :sound sound))
         ;; A script as long as the sound, so the replay keeps the run until it is heard.
         (script (%make-script :name (make-symbol "SOUND") :duration duration :items (list item)
                               :form (list :sound (princ-to-string (or label "sound"))))))
    (add-script-run performance (make-script-run script (float at 1d0) nil
                                                 (or body (performance-character performance)) nil))
    duration))

;;;# The audio track

(defun performance-clips (performance &optional end)
  "The clips PERFORMANCE plays, oldest first, once it is played to END
seconds (default: as far as it has been played)."
  (check-argument 'performance-clips 'performance performance #'performance-p "a performance (from make-performance)")
  (when end
    (check-seconds 'performance-clips 'end end)
    (performance-frame performance end))
  (reverse (replay-clips performance)))

(defun performance-audio (performance end)
  "PERFORMANCE's audio track from 0 to END seconds, every clip that starts by
then mixed into one SOUND at *TRACK-RATE*; NIL when nothing sounds."
  (let ((clips (remove-if (lambda (clip) (>= (clip-start clip) end))
                          (performance-clips performance end))))
    (and clips (mix-clips clips :end end))))

(defparameter *audio-file-name* "speech.wav"
  "The file simulate and render write the audio track to, beside their frames.")

(defun write-performance-audio (performance end path)
  "Write PERFORMANCE's audio track from 0 to END seconds to the WAV file PATH
and return its truename; when nothing sounds, return NIL and leave PATH alone
\(it may be a file of the user's: nothing they did not name is deleted)."
  (let ((sound (performance-audio performance end)))
    (and sound (write-wav path sound))))
