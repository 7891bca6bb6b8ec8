;;;; music.lisp -- a jukebox track as a sound: the WAV its catalogue names,
;;;; or a short tune of its own, made once per title and tempo by sox's
;;;; `synth` (Debian sox) and kept under build/music/.  The tune is two bars
;;;; of plucked eighth notes on a pentatonic scale over a bass note a beat,
;;;; chosen from the title, so each track sounds like itself every time;
;;;; its tempo (beats a minute) is the track's, for a foot to tap to.

(in-package #:player.speech)

(defparameter *music-cache-directory*
  (merge-pathnames "../../build/music/" #.(or *compile-file-truename* *load-truename*))
  "Where made tunes are kept, one WAV file per title and tempo.")

(defparameter *tune-seconds* 30
  "About how long a made tune plays: its two bars repeated to this length.")

(defparameter *pentatonic* #(0 2 4 7 9 12 14 16)
  "Semitones above the tune's key note that its melody steps through.")

(defun title-hash (title)
  "A number that TITLE (compared in lower case) gives on every Lisp and run."
  (loop with hash = 7
        for char across (string-downcase title)
        do (setf hash (mod (+ (* hash 31) (char-code char)) 1000003))
        finally (return hash)))

(defun title-tempo (title)
  "The tempo of a made tune for TITLE, in beats a minute: 80 to 140."
  (+ 80 (mod (title-hash title) 61)))

(defun tune-notes (title)
  "The melody of TITLE's tune: 16 eighth notes as semitones from A440 (a key
between F3 and D4, then steps of *PENTATONIC*), and its bass, 8 notes."
  (let* ((hash (title-hash title))
         (key (- (mod hash 10) 16))
         (state hash))
    (flet ((next (n) (setf state (mod (+ (* state 1103) 12345) 1000003)) (mod (floor state 7) n)))
      (values (loop for i below 16
                    collect (+ key (aref *pentatonic* (if (zerop (mod i 4)) (* 2 (next 3)) (next 8)))))
              (loop for beat below 8
                    collect (- key 24 (if (< beat 4) 0 (aref #(0 5 7) (next 3)))))))))

(defun tune-file (title tempo)
  "Where the tune of TITLE at TEMPO is kept."
  (merge-pathnames (format nil "~(~{~A~^-~}~)-~D.wav"
                           (or (remove "" (split-words title) :test #'string=) (list "track")) tempo)
                   *music-cache-directory*))

(defun split-words (text)
  "The runs of letters and digits in TEXT."
  (let ((words '()) (word '()))
    (loop for c across text
          do (if (alphanumericp c)
                 (push c word)
                 (when word (push (coerce (reverse word) 'string) words) (setf word '())))
          finally (when word (push (coerce (reverse word) 'string) words)))
    (nreverse words)))

(defun sox-synth-arguments (title tempo path)
  "The sox command line that writes TITLE's tune at TEMPO to PATH: one
channel a note, each delayed to its time, mixed down (remix -)."
  (multiple-value-bind (melody bass) (tune-notes title)
    (let* ((beat (/ 60d0 tempo))
           (eighth (/ beat 2))
           (bars (* 8 beat))
           (repeats (max 0 (1- (ceiling *tune-seconds* bars)))))
      (append (list "-n" "-r" "22050" "-b" "16" "-c" "1" (namestring path)
                    "synth" (format nil "~,4F" eighth))
              (loop for note in (append melody bass) append (list "pl" (format nil "%~D" note)))
              (list "delay")
              (loop for i below 16 collect (format nil "~,4F" (* i eighth)))
              (loop for i below 8 collect (format nil "~,4F" (* i beat)))
              (list "remix" "-" "norm" "-6" "repeat" (princ-to-string repeats))))))

(defun track-tune (title &key tempo)
  "The SOUND of TITLE's tune at TEMPO beats a minute (default TITLE-TEMPO),
made by sox once and kept under *MUSIC-CACHE-DIRECTORY*.  Signals
SPEECH-UNAVAILABLE when sox is missing, a SPEECH-ERROR when it fails."
  (check-argument 'track-tune 'title title (lambda (x) (and (stringp x) (< 0 (length x) 200)))
                  "a track's title, a string of 1 to 200 characters")
  (let* ((tempo (or tempo (title-tempo title)))
         (path (tune-file title tempo)))
    (check-real 'track-tune :tempo tempo :integer t :minimum 30 :maximum 300)
    (unless (probe-file path)
      (let ((sox (or (find-executable "sox")
                     (error 'speech-unavailable :package "sox"
                                                :message "making a track's tune needs sox: install the Debian package sox")))
            (partial (make-pathname :name (format nil "~A.part" (pathname-name path)) :defaults path)))
        (ensure-directories-exist path)
        (let ((process (sb-ext:run-program sox (sox-synth-arguments title tempo partial)
                                           :output nil :error nil :input nil)))
          (unless (and (zerop (sb-ext:process-exit-code process)) (probe-file partial))
            (speech-fail "sox could not make the tune of ~S (exit ~D)" title (sb-ext:process-exit-code process))))
        ;; Written aside, then renamed: a tune half made is never taken for one.
        (rename-file partial path)))
    (read-wav path)))
