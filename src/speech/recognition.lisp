;;;; recognition.lisp -- what is said in a WAV file, as a sentence of a JSGF
;;;; grammar: the sound read, made 16 kHz mono, and decoded by pocketsphinx
;;;; (Persona's Whisper, with a grammar of every legal sentence).

(in-package #:player.speech)

(defvar *sphinx-decoder* nil
  "The decoder, made on first use: making one loads the model (a few tenths of
a second); grammars and learnt words are kept in it.")

(defun temporary-file (name)
  "The pathname NAME in the temporary directory ($TMPDIR, else /tmp)."
  (merge-pathnames name (let ((tmp (sb-ext:posix-getenv "TMPDIR")))
                          (if (and tmp (plusp (length tmp)))
                              (directory-pathname tmp)
                              #p"/tmp/"))))

(defun grammar-decoder (grammar)
  "The decoder, searching the JSGF text GRAMMAR, having learnt how espeak-ng
says the grammar's words its dictionary lacks.  A SPEECH-ERROR names the
words it could learn no pronunciation for."
  (let ((decoder (or *sphinx-decoder* (setf *sphinx-decoder* (make-sphinx-decoder)))))
    (unless (gethash grammar (sphinx-decoder-searches decoder))
      (let ((unknown (remove-if (lambda (word) (sphinx-knows-word-p decoder word)) (grammar-words grammar))))
        (dolist (word unknown)
          (let ((phones (handler-case (word-pronunciation word)
                          (speech-unavailable ()
                            (speech-fail "pocketsphinx's dictionary lacks ~{~A~^, ~}, and without espeak-ng (Debian libespeak-ng1) it cannot learn them"
                                         unknown)))))
            (if phones
                (sphinx-add-word decoder word phones)
                (speech-fail "pocketsphinx's dictionary lacks ~A, and espeak-ng gives it no pronunciation" word))))))
    (sphinx-use-grammar decoder grammar)
    decoder))

(defun jsgf-text-p (x)
  "Is X a string that starts like a JSGF grammar (#JSGF)?"
  (and (stringp x) (let ((text (string-left-trim '(#\Space #\Tab #\Newline #\Return) x)))
                     (and (>= (length text) 5) (string= "#JSGF" text :end2 5)))))

(defun recognize-sound (sound &key grammar)
  "The sentence of GRAMMAR (JSGF text) that pocketsphinx hears in SOUND, in
lower case, or NIL when nothing in the grammar matches.  Signals
SPEECH-UNAVAILABLE when pocketsphinx or its English model is missing."
  (check-argument 'recognize-sound 'sound sound #'sound-p "a sound (from read-wav or synthesize-speech)")
  (check-argument 'recognize-sound :grammar grammar #'jsgf-text-p
                  "a JSGF grammar's text (starting #JSGF V1.0;)")
  (let ((decoder (grammar-decoder grammar))
        ;; A little silence either side: the recogniser needs to hear where speech starts and stops.
        (samples (pad-samples (sound-samples (resample-sound sound *recognition-rate*))
                              (round (* 0.3 *recognition-rate*)))))
    (let ((text (sphinx-decode decoder samples)))
      (and text (string-downcase text)))))

(defun pad-samples (samples count)
  "SAMPLES with COUNT zero samples before and after."
  (let ((out (make-samples (+ (length samples) (* 2 count)))))
    (replace out samples :start1 count)))

(defun recognize-wav (path &key grammar)
  "The sentence of GRAMMAR (JSGF text) that pocketsphinx hears in the WAV file
PATH (any rate, mono or not; 8 or 16-bit PCM), in lower case, or NIL when
nothing in the grammar matches.  Signals a SPEECH-ERROR naming PATH when the
file is missing, unreadable or not such a WAV; SPEECH-UNAVAILABLE, naming the
Debian package, when pocketsphinx or pocketsphinx-en-us is missing."
  (check-argument 'recognize-wav 'path path #'pathname-designator-p *path-phrase*)
  (check-argument 'recognize-wav :grammar grammar #'jsgf-text-p
                  "a JSGF grammar's text (starting #JSGF V1.0;)")
  (let ((sound (read-wav path)))
    (when (zerop (length (sound-samples sound)))
      (wav-fail path "it holds no samples"))
    (recognize-sound sound :grammar grammar)))
