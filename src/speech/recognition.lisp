;;;; recognition.lisp -- what is said in a WAV file, as a sentence of a JSGF
;;;; grammar: the sound read, made 16 kHz mono, and decoded by pocketsphinx
;;;; (Persona's Whisper, with a grammar of every legal sentence).
;;;; A grammar always finds its closest sentence, so every recognition is
;;;; scored: the same sound is decoded again by a loop of English phones,
;;;; the best any speech can score, and the SCORE is how much worse the
;;;; grammar's sentence fits, per 10 ms frame (0 is as good as any speech;
;;;; the more negative, the less the sound is like the sentence).  Below
;;;; *REJECTION-MARGIN*, or when its phones would each have to last longer
;;;; than *LONGEST-PHONE* frames, or when it passes over more than
;;;; *MOST-UNEXPLAINED-SPEECH* frames the phone loop hears as speech with
;;;; silence or noise, the sentence is rejected: speech outside the grammar
;;;; is nothing heard, never a command.  (A garbage loop inside the JSGF
;;;; grammar was tried and given up: sphinxbase's JSGF compiler joins the
;;;; loop to the grammar's sentences, and ignores its weight.)

(in-package #:player.speech)

(defvar *sphinx-decoder* nil
  "The decoder of whole utterances, made on first use: making one loads the
model (a few tenths of a second); grammars and learnt words are kept in it.")

(defvar *phone-loop-decoder* nil
  "A second decoder of whole utterances, searching the phone loop only, made
on first use.")

(defvar *listening-decoders* nil
  "The grammar's decoder and the phone loop's (a cons) that hear a microphone
side by side, made on first use.  Kept apart from the decoders of whole
utterances: a decoder fed a stream piece by piece normalises its cepstra by
a running mean from then on, which would make what a whole utterance is
heard as depend on what was heard before.")

(defparameter *rejection-margin* -28.0
  "The least SCORE (the grammar's acoustic score less the phone loop's, per
frame) a recognised sentence needs to be accepted.  On espeak-ng's voices
(t/fixtures/spoken-sentences.lisp) sentences of the jukebox grammar heard
right score -27 to 0, other English -46 to -18, so the margin alone cannot
part them; *LONGEST-PHONE* and *MOST-UNEXPLAINED-SPEECH* catch more.")

(defparameter *longest-phone* 17.0
  "The most frames (10 ms) of speech, as the phone loop hears it, a
recognised sentence may give each of its phones, on average, to be
accepted: the sentences of the grammar heard right take 4 to 14, while
speech a grammar can only match with a word or two stretches them further
(\"the cat sat on the mat\" heard as \"yeah\": 28).")

(defparameter *most-unexplained-speech* 10
  "The most frames (10 ms) the phone loop hears as speech that a recognised
sentence may cover with silence or noise, to be accepted.  A grammar
matches speech it has no sentence for with a short sentence and pauses
around it (\"the quick brown fox...\" as \"will you stop the a little\",
11 to 66 such frames); sentences of the grammar, heard right, leave at
most 9.  The three thresholds were chosen together, each midway in the
range that gets the most right, on the first two thirds of each set of
t/fixtures/spoken-sentences.lisp said by both voices (the last third held
out).")

(defparameter *longest-request* 30
  "The longest sound, in seconds, heard as one request: decoding takes about a
fifth of the sound's length, so a longer one is refused rather than decoded.")

(defun temporary-file (name)
  "The pathname NAME in the temporary directory ($TMPDIR, else /tmp)."
  (merge-pathnames name (let ((tmp (sb-ext:posix-getenv "TMPDIR")))
                          (if (and tmp (plusp (length tmp)))
                              (directory-pathname tmp)
                              #p"/tmp/"))))

(defun grammar-decoder (grammar &key listening)
  "The decoder of whole utterances (of a microphone's stream when LISTENING),
searching the JSGF text GRAMMAR, having learnt how espeak-ng says the
grammar's words its dictionary lacks, and how its accents say every word
(LEARN-ACCENTS).  A SPEECH-ERROR names the words it could learn no
pronunciation for."
  (let ((decoder (if listening
                     (car (listening-decoders))
                     (or *sphinx-decoder* (setf *sphinx-decoder* (make-sphinx-decoder))))))
    (unless (gethash grammar (sphinx-decoder-searches decoder))
      (let* ((words (grammar-words grammar))
             (unknown (remove-if (lambda (word) (sphinx-knows-word-p decoder word)) words)))
        (handler-case
            (progn
              (dolist (word unknown)
                (let ((phones (word-pronunciation word)))
                  (if phones
                      (sphinx-add-word decoder word phones)
                      (speech-fail "pocketsphinx's dictionary lacks ~A, and espeak-ng gives it no pronunciation" word))))
              (learn-accents decoder words))
          (speech-unavailable ()
            (when unknown
              (speech-fail "pocketsphinx's dictionary lacks ~{~A~^, ~}, and without espeak-ng (Debian libespeak-ng1) it cannot learn them"
                           unknown))))))
    (sphinx-use-grammar decoder grammar)
    decoder))

(defun learn-accents (decoder words)
  "Teach DECODER each of WORDS as the accents of *ACCENT-VOICES* say it, as
a variant (WORD(2), WORD(3)...) beside the pronunciations it has."
  (dolist (word words)
    (let ((known (sphinx-pronunciations decoder word)))
      (dolist (phones (accent-pronunciations word))
        (unless (member phones known :test #'string=)
          (sphinx-add-word decoder (format nil "~A(~D)" word (1+ (length known))) phones)
          (setf known (append known (list phones))))))))

(defun listening-decoders ()
  "*LISTENING-DECODERS*, made on first use: (GRAMMAR-DECODER . PHONE-LOOP-DECODER)."
  (or *listening-decoders*
      (let ((phones (make-sphinx-decoder)))
        (sphinx-use-phone-loop phones)
        (setf *listening-decoders* (cons (make-sphinx-decoder) phones)))))

(defun jsgf-text-p (x)
  "Is X a string that starts like a JSGF grammar (#JSGF)?"
  (and (stringp x) (let ((text (string-left-trim '(#\Space #\Tab #\Newline #\Return) x)))
                     (and (>= (length text) 5) (string= "#JSGF" text :end2 5)))))

(defun phone-loop-decoder ()
  "The decoder searching the phone loop, made on first use."
  (or *phone-loop-decoder*
      (let ((decoder (make-sphinx-decoder)))
        (sphinx-use-phone-loop decoder)
        (setf *phone-loop-decoder* decoder))))

(defun recognition-score (acoustic phone-acoustic frames)
  "The margin of a grammar's ACOUSTIC score over the phone loop's
PHONE-ACOUSTIC, per frame of FRAMES (see *REJECTION-MARGIN*)."
  (if (plusp frames) (/ (float (- acoustic phone-acoustic) 1.0) frames) 0.0))

(defun recognition-stretch (speech-frames phones)
  "The frames of speech (as the phone loop hears it) per phone of the
sentence a grammar heard: about 10 when the sentence is what was said.
When the phone loop, which can match any speech, hears none at all, the
sentence is made of noise: no stretch makes it acceptable."
  (if (and (plusp phones) (plusp speech-frames))
      (/ (float speech-frames 1.0) phones)
      most-positive-single-float))

(defun unexplained-speech (segments loop-segments)
  "The frames the phone loop's LOOP-SEGMENTS hear as speech that a grammar's
best path, SEGMENTS, spends in silence or noise (both as SPHINX-FINISH's
segments, (START END SPEECH-P), counted from the same first sample)."
  (let ((pauses (remove-if #'third segments)))
    (loop for (start end speech-p) in loop-segments
          when speech-p
            sum (loop for (pause-start pause-end) in pauses
                      sum (max 0 (1+ (- (min end pause-end) (max start pause-start))))))))

(defun judge-recognition (text score stretch &optional (unexplained 0))
  "What is heard as (VALUES TEXT SCORE SENTENCE STRETCH): TEXT (lower case)
when SCORE is at least *REJECTION-MARGIN*, STRETCH at most *LONGEST-PHONE*
and UNEXPLAINED (see UNEXPLAINED-SPEECH) at most *MOST-UNEXPLAINED-SPEECH*,
else NIL; SENTENCE is TEXT either way."
  (let ((sentence (and text (string-downcase text))))
    (values (and sentence (>= score *rejection-margin*) (<= stretch *longest-phone*)
                 (<= unexplained *most-unexplained-speech*) sentence)
            (and sentence score)
            sentence
            (and sentence stretch))))

(defun request-samples (sound)
  "SOUND as the recogniser hears it: 16 kHz, with 0.3 s of silence either
side (it needs to hear where speech starts and stops).  A SPEECH-ERROR when
it lasts longer than *LONGEST-REQUEST*."
  (when (> (sound-duration sound) *longest-request*)
    (speech-fail "a spoken request lasts at most ~D s, and this sound lasts ~,1F s: cut it into requests (e.g. sox IN OUT trim START LENGTH), or hear it with chat --listen"
                 *longest-request* (sound-duration sound)))
  (pad-samples (sound-samples (resample-sound sound *recognition-rate*))
               (round (* 0.3 *recognition-rate*))))

(defun recognize-sound (sound &key grammar)
  "The sentence of GRAMMAR (JSGF text) that pocketsphinx hears in SOUND, as
(VALUES TEXT SCORE SENTENCE): SENTENCE the grammar's closest sentence in
lower case (NIL when none matches), SCORE how well the sound fits it (see
*REJECTION-MARGIN*; NIL with no sentence), TEXT the SENTENCE unless
JUDGE-RECOGNITION rejects it, else NIL (speech outside the grammar).  Signals
SPEECH-UNAVAILABLE when pocketsphinx or its English model is missing, a
SPEECH-ERROR when SOUND is longer than *LONGEST-REQUEST* seconds."
  (check-argument 'recognize-sound 'sound sound #'sound-p "a sound (from read-wav or synthesize-speech)")
  (check-argument 'recognize-sound :grammar grammar #'jsgf-text-p
                  "a JSGF grammar's text (starting #JSGF V1.0;)")
  (let ((decoder (grammar-decoder grammar))
        (samples (request-samples sound)))
    (multiple-value-bind (text acoustic frames speech phones segments) (sphinx-decode decoder samples)
      (declare (ignore speech))
      (if (null text)
          (values nil nil nil nil)
          (multiple-value-bind (loop-text loop-acoustic loop-frames loop-speech loop-phones loop-segments)
              (sphinx-decode (phone-loop-decoder) samples)
            (declare (ignore loop-text loop-frames loop-phones))
            (judge-recognition text (recognition-score acoustic loop-acoustic frames)
                               (recognition-stretch loop-speech phones)
                               (unexplained-speech segments loop-segments)))))))

(defun pad-samples (samples count)
  "SAMPLES with COUNT zero samples before and after."
  (let ((out (make-samples (+ (length samples) (* 2 count)))))
    (replace out samples :start1 count)))

(defun recognize-wav (path &key grammar)
  "The sentence of GRAMMAR (JSGF text) that pocketsphinx hears in the WAV file
PATH (any rate, mono or not; 8 or 16-bit PCM), as RECOGNIZE-SOUND's (VALUES
TEXT SCORE SENTENCE): TEXT in lower case, or NIL when nothing in the grammar
matches well enough.  Signals a SPEECH-ERROR naming PATH when the
file is missing, unreadable or not such a WAV; SPEECH-UNAVAILABLE, naming the
Debian package, when pocketsphinx or pocketsphinx-en-us is missing."
  (check-argument 'recognize-wav 'path path #'pathname-designator-p *path-phrase*)
  (check-argument 'recognize-wav :grammar grammar #'jsgf-text-p
                  "a JSGF grammar's text (starting #JSGF V1.0;)")
  (let ((sound (read-request-wav path)))
    (recognize-sound sound :grammar grammar)))

(defun wav-header-duration (path)
  "How long the WAV file PATH says it lasts, in seconds, from its first 4 KB
only (a long recording is not read to learn it is too long), or NIL when the
header does not say.  A SPEECH-ERROR when PATH is missing or not a WAV file."
  (let* ((prefix (handler-case
                     ;; WITH-INPUT-FILE refuses a FIFO, device or folder before it could block.
                     (with-input-file (in path :element-type '(unsigned-byte 8))
                       (let ((octets (make-array (min 4096 (file-length in)) :element-type '(unsigned-byte 8))))
                         (read-sequence octets in)
                         octets))
                   (io-error (e) (wav-fail path "~A" (if (file-kind path) (io-error-reason e) "there is no such file")))))
         (chunks (riff-chunks prefix path))
         (fmt (assoc "fmt " chunks :test #'string=))
         (data (assoc "data" chunks :test #'string=)))
    (when (and fmt data (>= (third fmt) 16))
      (let* ((start (second fmt))
             (bytes-per-second (u32 prefix (+ start 8))))
        (and (plusp bytes-per-second)
             (/ (u32 prefix (- (second data) 4)) (float bytes-per-second 1d0)))))))

(defun read-request-wav (path)
  "The sound of the WAV file PATH, a spoken request: a SPEECH-ERROR naming it
when it is unreadable, empty, or (by its header, before it is read) longer
than *LONGEST-REQUEST* seconds, so a long recording costs neither the time
nor the memory of reading it."
  (let ((duration (wav-header-duration path)))
    (when (and duration (> duration *longest-request*))
      (wav-fail path "it lasts ~,1F s, and a spoken request at most ~D s: cut it into requests (e.g. sox IN OUT trim START LENGTH), or hear it with chat --listen"
                duration *longest-request*)))
  (let ((sound (read-wav path)))
    (when (zerop (length (sound-samples sound)))
      (wav-fail path "it holds no samples"))
    sound))
