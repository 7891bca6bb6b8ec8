;;;; pocketsphinx.lisp -- pocketsphinx 0.8 (Debian's 5prealpha API) and
;;;; sphinxbase bound in two layers: the raw %-named C functions, then one
;;;; decoder of the en-us model that takes JSGF grammars as searches, learns
;;;; words its dictionary lacks, and decodes a whole utterance at once.
;;;; (pocketsphinx_continuous splits a file where the speaker pauses, and a
;;;; piece of a sentence does not match the grammar; one utterance does.)

(in-package #:player.speech)

;;;# Raw bindings (pocketsphinx.h, cmd_ln.h, err.h)

(cffi:defcfun ("ps_args" %ps-args) :pointer)
(cffi:defcfun ("cmd_ln_parse_r" %cmd-ln-parse-r) :pointer
  (config :pointer) (definitions :pointer) (argc :int32) (argv :pointer) (strict :int32))
(cffi:defcfun ("cmd_ln_free_r" %cmd-ln-free-r) :int (config :pointer))
(cffi:defcfun ("ps_init" %ps-init) :pointer (config :pointer))
(cffi:defcfun ("ps_free" %ps-free) :int (decoder :pointer))
(cffi:defcfun ("ps_start_stream" %ps-start-stream) :int (decoder :pointer))
(cffi:defcfun ("ps_start_utt" %ps-start-utt) :int (decoder :pointer))
(cffi:defcfun ("ps_process_raw" %ps-process-raw) :int
  (decoder :pointer) (data :pointer) (count :size) (no-search :int) (full-utterance :int))
(cffi:defcfun ("ps_end_utt" %ps-end-utt) :int (decoder :pointer))
(cffi:defcfun ("ps_get_hyp" %ps-get-hyp) :pointer (decoder :pointer) (score :pointer))
(cffi:defcfun ("err_set_logfp" %err-set-logfp) :void (file :pointer))
(cffi:defcfun ("ps_lookup_word" %ps-lookup-word) :pointer (decoder :pointer) (word :string))
(cffi:defcfun ("ps_add_word" %ps-add-word) :int (decoder :pointer) (word :string) (phones :string) (update :int))
(cffi:defcfun ("ps_set_jsgf_string" %ps-set-jsgf-string) :int (decoder :pointer) (name :string) (jsgf :string))
(cffi:defcfun ("ps_set_search" %ps-set-search) :int (decoder :pointer) (name :string))
(cffi:defcfun ("ckd_free" %ckd-free) :void (pointer :pointer))
(cffi:defcfun ("ps_set_allphone_file" %ps-set-allphone-file) :int (decoder :pointer) (name :string) (path :string))
(cffi:defcfun ("ps_get_in_speech" %ps-get-in-speech) :uint8 (decoder :pointer))
(cffi:defcfun ("ps_seg_iter" %ps-seg-iter) :pointer (decoder :pointer))
(cffi:defcfun ("ps_seg_next" %ps-seg-next) :pointer (segment :pointer))
(cffi:defcfun ("ps_seg_free" %ps-seg-free) :void (segment :pointer))
(cffi:defcfun ("ps_seg_word" %ps-seg-word) :string (segment :pointer))
(cffi:defcfun ("ps_seg_frames" %ps-seg-frames) :void (segment :pointer) (start :pointer) (end :pointer))
(cffi:defcfun ("ps_seg_prob" %ps-seg-prob) :int32
  (segment :pointer) (acoustic :pointer) (language :pointer) (backoff :pointer))

;;;# Dither

(defconstant +dither-seed+ 1
  "The state the dither's generator starts every utterance from.")

(defun dither-samples (samples end out state)
  "Write into OUT the SAMPLES below END, each raised by one step with odds
of 1 in 4 (sphinxbase's dither), the odds drawn from a xorshift generator
in STATE (a nonzero 32-bit integer); returns the generator's next state.
Synthesised speech and the silence padded around it hold runs of exact
zeros, whose log energy breaks the features (\"hello\" was heard as
\"no\"); the generator is ours, started from +DITHER-SEED+ at each
utterance, so an utterance is always dithered the same."
  (declare (type (simple-array (signed-byte 16) (*)) samples out)
           (type (unsigned-byte 32) state)
           (type fixnum end))
  (dotimes (i end state)
    (setf state (logxor state (ldb (byte 32 0) (ash state 13)))
          state (logxor state (ash state -17))
          state (logxor state (ldb (byte 32 0) (ash state 5))))
    (setf (aref out i) (if (zerop (ldb (byte 2 7) state))
                           (min 32767 (1+ (aref samples i)))
                           (aref samples i)))))

;;;# Decoders

(defparameter *pocketsphinx-model* #p"/usr/share/pocketsphinx/model/en-us/"
  "The directory of pocketsphinx-en-us's acoustic model (en-us/) and dictionary (cmudict-en-us.dict).")

(defparameter *recognition-rate* 16000 "The sample rate the en-us acoustic model was trained at.")

(defun pocketsphinx-model-files ()
  "The acoustic model directory and the dictionary, as two namestrings;
SPEECH-UNAVAILABLE naming pocketsphinx-en-us when they are missing."
  (let ((hmm (merge-pathnames "en-us/" *pocketsphinx-model*))
        (dict (merge-pathnames "cmudict-en-us.dict" *pocketsphinx-model*)))
    (unless (and (probe-file hmm) (probe-file dict))
      (error 'speech-unavailable :package "pocketsphinx-en-us"
                                 :message (format nil "pocketsphinx's English model is not in ~A: install the Debian package pocketsphinx-en-us"
                                                  (namestring *pocketsphinx-model*))))
    (values (namestring hmm) (namestring dict))))

(defun make-sphinx-config (arguments)
  "A sphinxbase configuration parsed from ARGUMENTS, a list of strings as on
pocketsphinx's command line; a SPEECH-ERROR when they are refused."
  (let ((argv (cffi:foreign-alloc :pointer :count (1+ (length arguments))))
        (strings (mapcar #'cffi:foreign-string-alloc arguments)))
    (unwind-protect
         (progn
           (loop for s in strings for i from 0 do (setf (cffi:mem-aref argv :pointer i) s))
           (setf (cffi:mem-aref argv :pointer (length arguments)) (cffi:null-pointer))
           (let ((config (with-speech-traps-masked
                           (%cmd-ln-parse-r (cffi:null-pointer) (%ps-args) (length arguments) argv 1))))
             (when (cffi:null-pointer-p config)
               (speech-fail "pocketsphinx refused its configuration ~{~A~^ ~}" arguments))
             config))
      (mapc #'cffi:foreign-string-free strings)
      (cffi:foreign-free argv))))

(defstruct (sphinx-decoder (:constructor %make-sphinx-decoder (handle config)))
  "A pocketsphinx decoder (HANDLE) and its configuration (CONFIG), both foreign,
with the JSGF grammars it has been given as searches (text -> name), and the
state of the generator dithering the utterance it hears (see DITHER-SAMPLES)."
  handle config
  (searches (make-hash-table :test #'equal))
  (dither +dither-seed+ :type (unsigned-byte 32)))

(defun make-sphinx-decoder ()
  "A decoder of the en-us model and its dictionary, with no search yet.
Signals SPEECH-UNAVAILABLE when pocketsphinx or its model is missing."
  (load-pocketsphinx-library)
  (multiple-value-bind (hmm dict) (pocketsphinx-model-files)
    (%err-set-logfp (cffi:null-pointer))    ; its log is long and says nothing to a user
    ;; No dither of pocketsphinx's own: its noise comes from one generator per
    ;; process, which every decoder made re-seeds and every frame any decoder
    ;; hears advances, so what one utterance is heard as would depend on all
    ;; that was heard before.  SPHINX-FEED dithers instead (DITHER-SAMPLES).
    (let* ((config (make-sphinx-config (list "-hmm" hmm "-dict" dict "-dither" "no" "-allphone_ci" "yes")))
           (handle (with-speech-traps-masked (%ps-init config))))
      (when (cffi:null-pointer-p handle)
        (%cmd-ln-free-r config)
        (speech-fail "pocketsphinx could not load its model from ~A" hmm))
      (%make-sphinx-decoder handle config))))

(defun free-sphinx-decoder (decoder)
  "Free DECODER's foreign decoder; DECODER must not be used after."
  (with-speech-traps-masked (%ps-free (sphinx-decoder-handle decoder)))
  (setf (sphinx-decoder-handle decoder) nil))

(defun sphinx-knows-word-p (decoder word)
  "Is WORD in DECODER's dictionary?"
  (let ((phones (%ps-lookup-word (sphinx-decoder-handle decoder) word)))
    (unless (cffi:null-pointer-p phones)
      (%ckd-free phones)
      t)))

(defun sphinx-pronunciations (decoder word)
  "The pronunciations DECODER's dictionary gives WORD (its own, then WORD(2),
WORD(3)...), each CMU phones separated by spaces."
  (loop for k from 1
        for phones = (%ps-lookup-word (sphinx-decoder-handle decoder)
                                      (if (= k 1) word (format nil "~A(~D)" word k)))
        until (cffi:null-pointer-p phones)
        collect (prog1 (string-trim " " (cffi:foreign-string-to-lisp phones))
                  (%ckd-free phones))))

(defun sphinx-add-word (decoder word phones)
  "Teach DECODER WORD, pronounced PHONES (CMU phones separated by spaces, such
as \"HH AH L OW\"); a SPEECH-ERROR when it refuses them."
  (when (minusp (with-speech-traps-masked (%ps-add-word (sphinx-decoder-handle decoder) word phones 1)))
    (speech-fail "pocketsphinx refused the word ~A pronounced ~A" word phones)))

(defun sphinx-use-grammar (decoder grammar)
  "Make the JSGF text GRAMMAR DECODER's search (parsed once, then kept).  A
SPEECH-ERROR when pocketsphinx cannot use it."
  (let* ((searches (sphinx-decoder-searches decoder))
         (name (or (gethash grammar searches)
                   (let ((name (format nil "grammar-~D" (hash-table-count searches))))
                     (unless (zerop (with-speech-traps-masked
                                      (%ps-set-jsgf-string (sphinx-decoder-handle decoder) name grammar)))
                       (speech-fail "pocketsphinx could not use the grammar (is it JSGF, with a public rule?)"))
                     (setf (gethash grammar searches) name)))))
    (unless (zerop (%ps-set-search (sphinx-decoder-handle decoder) name))
      (speech-fail "pocketsphinx could not switch to the grammar ~A" name))))

(defun sphinx-use-phone-loop (decoder)
  "Make DECODER's search the en-us phone loop (any sequence of phones, weighed
by en-us-phone.lm.bin): the best any speech can score, which a grammar's
best is measured against.  A SPEECH-ERROR when pocketsphinx cannot load it."
  (let ((searches (sphinx-decoder-searches decoder)))
    (unless (gethash :phone-loop searches)
      (let ((path (namestring (merge-pathnames "en-us-phone.lm.bin" *pocketsphinx-model*))))
        (unless (and (probe-file path)
                     (zerop (with-speech-traps-masked
                              (%ps-set-allphone-file (sphinx-decoder-handle decoder) "phone-loop" path))))
          (speech-fail "pocketsphinx could not load its phone model ~A (Debian pocketsphinx-en-us)" path)))
      (setf (gethash :phone-loop searches) "phone-loop"))
    (unless (zerop (%ps-set-search (sphinx-decoder-handle decoder) "phone-loop"))
      (speech-fail "pocketsphinx could not switch to its phone loop"))))

(defun filler-word-p (word)
  "Is WORD a silence or noise of the decoder's (<sil>, [NOISE], SIL, +BREATH+), not speech?"
  (or (zerop (length word)) (find (char word 0) "<[+") (string= word "SIL")))

(defun word-phone-count (handle word)
  "How many phones HANDLE's dictionary gives WORD (1 for a word it lacks: a phone loop's phone)."
  (let ((phones (%ps-lookup-word handle word)))
    (if (cffi:null-pointer-p phones)
        1
        (prog1 (1+ (count #\Space (string-trim " " (cffi:foreign-string-to-lisp phones))))
          (%ckd-free phones)))))

(defun sphinx-acoustic-score (handle)
  "The acoustic score (log base 1.0001) of the words HANDLE's best path
holds, summed, the frames they span, the frames of speech among them (not
silence or noise), the phones of its words, and its segments as (START END
SPEECH-P), frames from the utterance's start: (VALUES SCORE FRAMES
SPEECH-FRAMES PHONES SEGMENTS)."
  (let ((score 0) (first-frame nil) (last-frame 0) (speech 0) (phones 0) (segments '()))
    (cffi:with-foreign-objects ((acoustic :int32) (language :int32) (backoff :int32) (start :int) (end :int))
      (do ((segment (%ps-seg-iter handle) (%ps-seg-next segment)))
          ((cffi:null-pointer-p segment))
        (%ps-seg-prob segment acoustic language backoff)
        (%ps-seg-frames segment start end)
        (incf score (cffi:mem-ref acoustic :int32))
        (let ((word (%ps-seg-word segment)))
          (push (list (cffi:mem-ref start :int) (cffi:mem-ref end :int) (not (filler-word-p word))) segments)
          (unless (filler-word-p word)
            (incf speech (1+ (- (cffi:mem-ref end :int) (cffi:mem-ref start :int))))
            (incf phones (word-phone-count handle word))))
        (setf first-frame (or first-frame (cffi:mem-ref start :int))
              last-frame (cffi:mem-ref end :int))))
    (values score (if first-frame (max 1 (1+ (- last-frame first-frame))) 0) speech phones (nreverse segments))))

(defun sphinx-start-stream (decoder)
  "Begin a new stream of sound in DECODER: it forgets the noise level its
noise removal and voice-activity detection learnt from the sound before,
which would otherwise change how the next utterance is heard."
  (unless (>= (with-speech-traps-masked (%ps-start-stream (sphinx-decoder-handle decoder))) 0)
    (speech-fail "pocketsphinx could not start a stream")))

(defun sphinx-start (decoder)
  "Begin an utterance in DECODER, its dither started from the same seed."
  (setf (sphinx-decoder-dither decoder) +dither-seed+)
  (unless (>= (with-speech-traps-masked (%ps-start-utt (sphinx-decoder-handle decoder))) 0)
    (speech-fail "pocketsphinx could not start an utterance")))

(defun sphinx-feed (decoder samples &key (end (length samples)) whole)
  "Give DECODER the SAMPLES (16 kHz) below END, dithered (DITHER-SAMPLES):
WHOLE when they are the whole utterance, else a piece of a stream (whose
speech and silence its voice-activity detection tells apart).  Returns
whether it hears speech now."
  (let ((handle (sphinx-decoder-handle decoder))
        (dithered (make-samples end)))
    (setf (sphinx-decoder-dither decoder)
          (dither-samples samples end dithered (sphinx-decoder-dither decoder)))
    (with-speech-traps-masked
      (cffi:with-pointer-to-vector-data (data dithered)
        (when (minusp (%ps-process-raw handle data end 0 (if whole 1 0)))
          (speech-fail "pocketsphinx could not process the audio")))
      (plusp (%ps-get-in-speech handle)))))

(defun sphinx-finish (decoder)
  "End DECODER's utterance: (VALUES TEXT ACOUSTIC-SCORE FRAMES SPEECH-FRAMES
PHONES SEGMENTS), TEXT the sentence heard (NIL for none), the acoustic score
of its best path, the frames (10 ms) it spans, those of speech, its phones,
and its segments (see SPHINX-ACOUSTIC-SCORE)."
  (let ((handle (sphinx-decoder-handle decoder)))
    (with-speech-traps-masked
      (%ps-end-utt handle)
      (cffi:with-foreign-object (score :int32)
        (let* ((hypothesis (%ps-get-hyp handle score))
               (text (and (not (cffi:null-pointer-p hypothesis)) (cffi:foreign-string-to-lisp hypothesis))))
          (multiple-value-bind (acoustic frames speech phones segments) (sphinx-acoustic-score handle)
            (values (and text (plusp (length text)) text) acoustic frames speech phones segments)))))))

(defun sphinx-decode (decoder samples)
  "The sentence DECODER hears in SAMPLES (16 kHz, one utterance), or NIL when
it matches nothing in its search, as SPHINX-FINISH's (VALUES TEXT
ACOUSTIC-SCORE FRAMES SPEECH-FRAMES PHONES SEGMENTS): a function of SAMPLES
and the search alone, whatever DECODER or any other heard before."
  (sphinx-start-stream decoder)
  (sphinx-start decoder)
  (sphinx-feed decoder samples :whole t)
  (sphinx-finish decoder))
