;;;; speaking.lisp -- Persona's loop closed: a SPEAKER says each of Peedy's
;;;; replies on the body presenter's performance at the Player clock of the
;;;; moment he says it (so the beak moves and the audio track holds it), puts
;;;; the user's spoken requests on the same track, and holds the next turn's
;;;; animation back until the speech before it has ended.
;;;; It plugs into a conversation through *SAY-FUNCTION*.

(in-package #:player.dialogue)

(defstruct (speaker (:constructor %make-speaker))
  "Speaks a conversation on PERFORMANCE: espeak-ng's VOICE and RATE (NIL: the
defaults), PAUSE seconds of quiet after each speech, FREE-AT the time the
track is free again (the last speech's end plus PAUSE), and LINES, what was
said or heard, newest first, as (START END TEXT WHO), WHO :peedy or :user;
MUSIC the run of the music playing, or NIL."
  performance voice rate (pause 0.4d0 :type double-float) (free-at 0d0 :type double-float) (lines '())
  (music nil))

(defun make-speaker (performance &key voice rate (pause 0.4))
  "A SPEAKER saying a conversation on PERFORMANCE (a body presenter's
PRESENTER-PERFORMANCE) with espeak-ng's VOICE and RATE, leaving PAUSE seconds
between one speech and the next."
  (check-argument 'make-speaker 'performance performance #'performance-p "a performance (from make-performance)")
  (check-seconds 'make-speaker :pause pause :minimum 0)
  (%make-speaker :performance performance :voice voice :rate rate :pause (float pause 1d0)))

(defun speaker-start-time (speaker controller)
  "When SPEAKER can next speak: CONTROLLER's time (an untimed controller's
clock, which has run to the end of the events sent; a timed one's now), or
later when the track is still busy."
  (max (float (controller-time controller) 1d0) (speaker-free-at speaker)))

(defun speaker-add-line (speaker start duration text who)
  "Remember that WHO said TEXT from START for DURATION seconds; the track is free a pause after."
  (push (list start (+ start duration) text who) (speaker-lines speaker))
  ;; Rounded up to a hundredth of a second, so the trace's times stay readable.
  (setf (speaker-free-at speaker) (/ (fceiling (* 100 (+ start duration (speaker-pause speaker)))) 100))
  (+ start duration))

(defun speaker-say (speaker text controller)
  "Say TEXT on SPEAKER's performance at CONTROLLER's clock (after any speech
still sounding): the beak moves and the sound goes on the track, and each
gesture mark of TEXT (<!beat>, <!point>: GESTURE-MARKS) lands its gesture on
the word after it.  Returns the time the speech ends.  Signals what
SYNTHESIZE-SPEECH signals."
  (multiple-value-bind (plain gestures) (gesture-marks text)
    (let* ((start (speaker-start-time speaker controller))
           (duration (performance-say (speaker-performance speaker) plain :at start :gestures gestures
                                      :voice (speaker-voice speaker) :rate (speaker-rate speaker))))
      (speaker-add-line speaker start duration plain :peedy))))

(defun speaker-listen (speaker sound label controller)
  "Put the user's spoken request SOUND (LABEL: its file) on SPEAKER's track at
CONTROLLER's clock, after any speech still sounding, then hold CONTROLLER
until it has been heard.  Returns the time it ends."
  (let* ((start (speaker-start-time speaker controller))
         (duration (performance-play-sound (speaker-performance speaker) sound :at start :label label)))
    (prog1 (speaker-add-line speaker start duration (princ-to-string label) :user)
      (speaker-wait speaker controller))))

(defun speaker-wait (speaker controller)
  "Move CONTROLLER's clock on to when SPEAKER's track is free, so the next
turn's animation begins once Peedy has finished talking (a timed controller
advances there; an untimed one starts its next event there)."
  (let ((free (speaker-free-at speaker)))
    (when (> free (controller-time controller))
      (if (controller-timeline controller)
          (advance controller free)
          (setf (controller-clock controller) free)))
    free))

(defun speaker-end (speaker)
  "When SPEAKER's last speech ends (0 when nothing was said)."
  (reduce #'max (speaker-lines speaker) :key #'second :initial-value 0d0))

(defun speaker-say-function (speaker)
  "A function for *SAY-FUNCTION*: say each text on SPEAKER at the time the
conversation's controller has reached."
  (lambda (text conversation)
    (let ((controller (conversation-controller conversation)))
      (unless controller
        (dialogue-fail nil "a speaker needs a conversation with a Player controller (make-conversation :controller ...)"))
      (speaker-say speaker text controller))))

(defun speaker-play-music (speaker command track controller)
  "Play TRACK (COMMAND :play) or stop the music (:stop) on SPEAKER's
performance at CONTROLLER's time: the track's sound goes on the track as
music, ducked under the voices, and its tempo leads the scripts of :beats.
What played before stops there.  Signals what TRACK-SOUND signals."
  (let ((performance (speaker-performance speaker))
        (time (float (controller-time controller) 1d0)))
    (when (speaker-music speaker)
      (performance-stop-music performance (speaker-music speaker) time)
      (setf (speaker-music speaker) nil))
    (when (eq command :play)
      (multiple-value-bind (sound tempo) (track-sound track)
        (setf (speaker-music speaker)
              (performance-play-music performance sound :at time :tempo tempo
                                                        :label (track-title track)))))))

(defun speaker-set-mood (speaker mood controller)
  "Set the mood of SPEAKER's character to MOOD (an emotion's name: EMOTION-MOOD
gives its number; an unknown one is neutral) from CONTROLLER's time on."
  (performance-set-mood (speaker-performance speaker) mood
                        :at (float (controller-time controller) 1d0)))

(defmacro with-speaker ((speaker) &body body)
  "Run BODY with Peedy's replies said, and the music played, by SPEAKER (NIL: neither)."
  `(call-with-speaker ,speaker (lambda () ,@body)))

(defun call-with-speaker (speaker function)
  "Call FUNCTION with *SAY-FUNCTION*, *MUSIC-FUNCTION* and *MOOD-FUNCTION*
going through SPEAKER, when SPEAKER is not NIL."
  (if speaker
      (let ((*say-function* (speaker-say-function speaker))
            (*music-function* (lambda (command track conversation)
                                (let ((controller (conversation-controller conversation)))
                                  (when controller
                                    (speaker-play-music speaker command track controller)))))
            (*mood-function* (lambda (mood conversation)
                               (let ((controller (conversation-controller conversation)))
                                 (when controller
                                   (speaker-set-mood speaker mood controller))))))
        (funcall function))
      (funcall function)))
