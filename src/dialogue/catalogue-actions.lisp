;;;; catalogue-actions.lisp -- the jukebox's application actions: queries on
;;;; the dialogue's music catalogue (Persona's getLastCD, genTracks, doSelect),
;;;; storing their results in context variables as the paper describes.
;;;; `lastRef` is the last referenced object (a CD or a track), which "Who
;;;; wrote that?" resolves; `cnt0` the number of results, which Figure 8's
;;;; rules test.

(in-package #:player.dialogue)

(defun refer-to (conversation object)
  "Make OBJECT the last referenced object of CONVERSATION."
  (setf (context-value conversation "lastRef") object))

(define-dialogue-action findCDs (conversation)
  "The CDs by the context variable `artist`: `cds` (all), `cnt0` (how many),
`cd` (the first, also the last referenced object)."
  (let* ((artist (context-value conversation "artist"))
         (cds (and (stringp artist)
                   (cds-by-artist (dialogue-catalogue (conversation-dialogue conversation)) artist))))
    (setf (context-value conversation "cds") cds
          (context-value conversation "cnt0") (length cds)
          (context-value conversation "cd") (first cds))
    (when cds (refer-to conversation (first cds)))))

(define-dialogue-action getLastCD (conversation)
  "Load the attributes of the last CD referred to into context: `Title`,
`Artist`, `Year` (Figure 9's getLastCD)."
  (let ((cd (let ((last (context-value conversation "lastRef")))
              (cond ((cd-p last) last)
                    ((track-p last) (track-cd last))
                    (t (context-value conversation "cd"))))))
    (when cd
      (setf (context-value conversation "cd") cd
            (context-value conversation "Title") (cd-title cd)
            (context-value conversation "Artist") (cd-artist cd)
            (context-value conversation "Year") (cd-year cd)))))

(define-dialogue-action genTracks (conversation)
  "Expand the current CD (`cd`) into the list of its tracks, `tracks` (Figure 7)."
  (let ((cd (context-value conversation "cd")))
    (setf (context-value conversation "tracks") (and (cd-p cd) (cd-tracks cd)))))

(define-dialogue-action doSelect (conversation)
  "Pick one of `tracks` at random (another than the current `track` when there
is a choice): it becomes `track` and the last referenced object (Figure 7)."
  (let* ((tracks (context-value conversation "tracks"))
         (current (context-value conversation "track"))
         (choices (or (remove current tracks) tracks)))
    (when choices
      (let ((track (nth (conversation-random conversation (length choices)) choices)))
        (setf (context-value conversation "track") track)
        (refer-to conversation track)))))

(define-dialogue-action whoWrote (conversation)
  "Who wrote the track named in `title` (which becomes the last referenced
object), else the last referenced object (\"Who wrote that?\"): `composer`,
and `cnt0` (1, or 0 when unknown)."
  (let* ((catalogue (dialogue-catalogue (conversation-dialogue conversation)))
         (title (context-value conversation "title"))
         (object (or (and (stringp title) (find-track catalogue title))
                     (context-value conversation "lastRef")))
         (composer (typecase object
                     (track (track-composer object))
                     (cd (cd-artist object)))))
    (setf (context-value conversation "composer") composer
          (context-value conversation "cnt0") (if composer 1 0))
    ;; A track named is now what "that" refers to.
    (when (and composer (not (eq object (context-value conversation "lastRef"))))
      (refer-to conversation object))))

(defun track-by-p (track artist)
  "Is TRACK by ARTIST (a string): its composer, or its CD's artist?"
  (or (string-equal (track-composer track) artist) (string-equal (cd-artist (track-cd track)) artist)))

(define-dialogue-action findTrack (conversation)
  "The track named by the context variable `title` (by `artist`, when that is
set too; Figure 4's \"play before you accuse me by clapton\"): `track`, its
`cd` and the CD's `tracks`, `cnt0` (1, or 0 when there is no such track)."
  (let* ((catalogue (dialogue-catalogue (conversation-dialogue conversation)))
         (title (context-value conversation "title"))
         (artist (context-value conversation "artist"))
         (track (and (stringp title)
                     (loop for cd in catalogue
                           thereis (find-if (lambda (track)
                                              (and (string-equal (track-title track) title)
                                                   (or (not (stringp artist)) (track-by-p track artist))))
                                            (cd-tracks cd))))))
    (setf (context-value conversation "cnt0") (if track 1 0))
    (when track
      (setf (context-value conversation "track") track
            (context-value conversation "cd") (track-cd track)
            (context-value conversation "tracks") (cd-tracks (track-cd track)))
      (refer-to conversation track))))

;;;# The queue: "after that" and "next" wait for the playing track

(define-dialogue-action queueTrack (conversation)
  "Put `track` at the end of the queue (`queue`, a list); `queued` counts it."
  (let ((queue (append (context-value conversation "queue") (list (context-value conversation "track")))))
    (setf (context-value conversation "queue") queue
          (context-value conversation "queued") (length queue))))

(define-dialogue-action playNext (conversation)
  "Take the first queued track off the queue: it becomes `track` and the last referenced object."
  (let ((queue (context-value conversation "queue")))
    (when queue
      (setf (context-value conversation "track") (first queue)
            (context-value conversation "queue") (rest queue)
            (context-value conversation "queued") (length (rest queue)))
      (refer-to conversation (first queue)))))

(define-dialogue-action clearQueue (conversation)
  "Forget the queued tracks (a new request, or the music stopped)."
  (setf (context-value conversation "queue") '()
        (context-value conversation "queued") 0))

;;;# The music: the jukebox plays the track

(defvar *music-function* nil
  "NIL, or a function of (COMMAND TRACK CONVERSATION) that plays the music:
COMMAND :play starts TRACK (stopping what played), :stop stops it (TRACK
NIL).  A SPEAKER binds it (speaking.lisp), so the music sounds on the
performance; without one the jukebox only says what it plays.")

(defun track-sound (track)
  "TRACK's sound and tempo: its WAV file when the catalogue names one, else
its own tune (TRACK-TUNE, made by sox once); the tempo is the catalogue's,
else the tune's.  Signals SPEECH-ERROR when the sound cannot be had."
  (let ((tempo (or (track-tempo track) (title-tempo (track-title track)))))
    (values (if (track-wav track)
                (read-wav (track-wav track))
                (track-tune (track-title track) :tempo tempo))
            tempo)))

(define-dialogue-action playMusic (conversation)
  "The jukebox plays `track` (what played before stops): `playing` is the
track now sounding."
  (let ((track (context-value conversation "track")))
    (when (track-p track)
      (setf (context-value conversation "playing") track)
      (when *music-function* (funcall *music-function* :play track conversation)))))

(define-dialogue-action stopMusic (conversation)
  "The jukebox stops: `playing` is unset."
  (setf (context-value conversation "playing") nil)
  (when *music-function* (funcall *music-function* :stop nil conversation)))
