;;;; catalogue.lisp -- the music the jukebox knows: CDs with artist, year and
;;;; tracks.  A catalogue is data, written as (cd ID :title T :artist A :year Y
;;;; :tracks (TRACK...)) forms, a TRACK being a title or (TITLE [:composer C]
;;;; [:wav "FILE.wav"] [:tempo BPM]): :composer when someone other than the
;;;; CD's artist wrote it, :wav its sound (beside the file holding the form;
;;;; else a tune of its own is made, music.lisp), :tempo its beats a minute.  The forms may stand in
;;;; a defdialogue or in a catalogue file; queries over them are dialogue
;;;; actions (catalogue-actions.lisp).

(in-package #:player.dialogue)

(defstruct (cd (:constructor %make-cd))
  "A CD: its ID (a name), TITLE, ARTIST (strings), YEAR (an integer or NIL) and TRACKS."
  id title artist year (tracks '()))

(defstruct (track (:constructor %make-track))
  "A track: its TITLE, its COMPOSER (a string), the CD it is on, its WAV file
\(a pathname, or NIL for a made tune) and TEMPO (beats a minute, or NIL)."
  title composer cd wav tempo)

(defmethod print-object ((cd cd) stream)
  (print-unreadable-object (cd stream :type t) (write-string (cd-title cd) stream)))

(defmethod print-object ((track track) stream)
  (print-unreadable-object (track stream :type t) (write-string (track-title track) stream)))

(defun catalogue-form-p (form)
  "Is FORM a (cd ...) catalogue entry?"
  (and (consp form) (symbolp (first form)) (same-name-p (first form) "cd")))

(defun parse-cd (form)
  "The CD FORM, (cd ID :title T :artist A [:year Y] :tracks (TRACK...)), describes;
a DIALOGUE-ERROR naming FORM when it is malformed."
  (unless (and (alexandria:proper-list-p form) (symbolp (second form)) (second form)
               (evenp (length (cddr form))))
    (dialogue-fail form "expected (cd ID :title \"T\" :artist \"A\" [:year Y] :tracks (TRACK...))"))
  (destructuring-bind (&key title artist year tracks &allow-other-keys) (cddr form)
    (loop for (key) on (cddr form) by #'cddr
          unless (member key '(:title :artist :year :tracks))
            do (dialogue-fail form "unknown cd property ~A (known: :title :artist :year :tracks)" (lisp-text key)))
    (unless (and (stringp title) (stringp artist) (text-words title) (text-words artist))
      (dialogue-fail form "a cd needs a :title and an :artist, strings with words in them"))
    (unless (or (null year) (typep year '(integer 0 9999)))
      (dialogue-fail form ":year must be an integer, not ~A" (lisp-text year)))
    (unless (and (alexandria:proper-list-p tracks) tracks)
      (dialogue-fail form ":tracks must be a non-empty list of titles"))
    (let ((cd (%make-cd :id (second form) :title title :artist artist :year year)))
      (setf (cd-tracks cd) (mapcar (lambda (entry) (parse-track entry cd form)) tracks))
      cd)))

(defun parse-track (entry cd form)
  "The track ENTRY of CD describes: a title string, or (TITLE [:composer C]
[:wav \"FILE\"] [:tempo BPM]).  A DIALOGUE-ERROR naming FORM when it is
malformed or its WAV file does not exist."
  (flet ((bad ()
           (dialogue-fail form "a track is a title string or (\"TITLE\" [:composer \"NAME\"] [:wav \"FILE.wav\"] [:tempo BPM]), not ~A"
                          (bounded-lisp-text entry 80))))
    (unless (or (stringp entry)
                (and (alexandria:proper-list-p entry) (stringp (first entry)) (oddp (length entry))
                     (loop for (key) on (rest entry) by #'cddr always (member key '(:composer :wav :tempo)))))
      (bad))
    (destructuring-bind (title &key (composer (cd-artist cd)) wav tempo) (alexandria:ensure-list entry)
      (unless (and (text-words title) (stringp composer) (text-words composer)
                   (or (null wav) (and (stringp wav) (plusp (length wav))))
                   (or (null tempo) (and (integerp tempo) (<= 30 tempo 300))))
        (bad))
      (%make-track :title title :composer composer :cd cd :tempo tempo
                   :wav (and wav (track-wav-file wav title form))))))

(defun track-wav-file (file title form)
  "The WAV FILE of the track TITLE, beside the file holding FORM; a
DIALOGUE-ERROR naming FORM when it does not exist."
  (let* ((place (and (hash-table-p *form-places*) (gethash form *form-places*)))
         (path (merge-pathnames file (or (car place) *default-pathname-defaults*))))
    (or (probe-file path)
        (dialogue-fail form "track ~S: its WAV file ~A does not exist" title (namestring path)))))

(defun read-catalogue-file (file)
  "The CDs of the catalogue FILE, read as data: it may hold only in-package and
cd forms.  A DIALOGUE-ERROR names the file and line of a bad form."
  (let* ((entries (read-data-file file :what "catalogue file" :readtable *dialogue-readtable*
                                       :fail (lambda (position message &optional kind)
                                               (declare (ignore kind))
                                               (error 'dialogue-error :position (and position (cons file position))
                                                                      :spec nil :form nil :message message))))
         (places (make-hash-table :test 'eq))
         (truename (probe-file file)))
    (with-spec-context (:form-places places)
      (loop for (form position) in entries
            do (when (consp form) (setf (gethash form places) (cons truename position)))
               (unless (catalogue-form-p form)
                 (dialogue-fail form "a catalogue file holds only cd forms, not ~A" (bounded-lisp-text form 60)))
            collect (parse-cd form)))))

;;;# Looking things up

(defun catalogue-artists (catalogue)
  "Every artist and composer CATALOGUE (a list of CDs) names, without repeats."
  (remove-duplicates (loop for cd in catalogue
                           collect (cd-artist cd)
                           append (mapcar #'track-composer (cd-tracks cd)))
                     :test #'string-equal :from-end t))

(defun catalogue-titles (catalogue)
  "Every track title in CATALOGUE, without repeats."
  (remove-duplicates (loop for cd in catalogue append (mapcar #'track-title (cd-tracks cd)))
                     :test #'string-equal :from-end t))

(defun catalogue-albums (catalogue)
  "Every CD title in CATALOGUE."
  (mapcar #'cd-title catalogue))

(defun cds-by-artist (catalogue artist)
  "The CDs of CATALOGUE by ARTIST (a string), or holding a track ARTIST wrote."
  (remove-if-not (lambda (cd)
                   (or (string-equal (cd-artist cd) artist)
                       (find artist (cd-tracks cd) :key #'track-composer :test #'string-equal)))
                 catalogue))

(defun find-track (catalogue title)
  "The first track of CATALOGUE called TITLE, or NIL."
  (loop for cd in catalogue
        thereis (find title (cd-tracks cd) :key #'track-title :test #'string-equal)))
