;;;; espeak.lisp -- libespeak-ng bound in two layers: the raw %-named C
;;;; functions and the event struct of speak_lib.h (API revision 12), then a
;;;; Lisp layer that initialises once, checks every status and signals
;;;; SPEECH-ERRORs.  Synthesis is synchronous: the callback runs inside
;;;; espeak_Synth on this thread, handing over samples and events in chunks.

(in-package #:player.speech)

;;;# Raw bindings (speak_lib.h)

(defconstant +espeak-event-list-terminated+ 0 "espeakEVENT_LIST_TERMINATED: the end of an event list.")
(defconstant +espeak-event-word+ 1 "espeakEVENT_WORD: a word starts (text_position and length say which).")
(defconstant +espeak-event-phoneme+ 7 "espeakEVENT_PHONEME: a phoneme starts (with espeakINITIALIZE_PHONEME_EVENTS).")
(defconstant +espeak-event-msg-terminated+ 6 "espeakEVENT_MSG_TERMINATED: the text is all spoken.")
(defconstant +audio-output-synchronous+ 2 "AUDIO_OUTPUT_SYNCHRONOUS: espeak_Synth returns when done, samples via the callback.")
(defconstant +espeak-initialize-phoneme-events+ #x0001 "espeakINITIALIZE_PHONEME_EVENTS.")
(defconstant +espeak-initialize-dont-exit+ #x8000 "espeakINITIALIZE_DONT_EXIT: report errors instead of exiting.")
(defconstant +espeak-chars-utf8+ 1 "espeakCHARS_UTF8: the text is UTF-8.")
(defconstant +espeak-pos-character+ 1 "POS_CHARACTER.")
(defconstant +espeak-rate+ 1 "espeakRATE: words a minute, 80 to 450.")
(defconstant +ee-ok+ 0 "EE_OK.")

;;; espeak_EVENT: 40 bytes on x86-64 (checked against the header with g++):
;;; type 0, unique_identifier 4, text_position 8, length 12, audio_position 16,
;;; sample 20, user_data 24, id (a union of int, char* and char[8]) 32.
(cffi:defcstruct (%espeak-event :size 40)
  (type :int :offset 0)
  (unique-identifier :unsigned-int :offset 4)
  (text-position :int :offset 8)
  (length :int :offset 12)
  (audio-position :int :offset 16)       ; milliseconds from the start of the text
  (sample :int :offset 20)
  (user-data :pointer :offset 24)
  (id :char :count 8 :offset 32))        ; for a phoneme: its name, NUL-padded

(cffi:defcfun ("espeak_Initialize" %espeak-initialize) :int
  (output :int) (buffer-length :int) (path :pointer) (options :int))
(cffi:defcfun ("espeak_SetSynthCallback" %espeak-set-synth-callback) :void (callback :pointer))
(cffi:defcfun ("espeak_SetVoiceByName" %espeak-set-voice-by-name) :int (name :string))
(cffi:defcfun ("espeak_SetParameter" %espeak-set-parameter) :int (parameter :int) (value :int) (relative :int))
(cffi:defcfun ("espeak_Synth" %espeak-synth) :int
  (text :pointer) (size :size) (position :unsigned-int) (position-type :int)
  (end-position :unsigned-int) (flags :unsigned-int) (unique-identifier :pointer) (user-data :pointer))
(cffi:defcfun ("espeak_Synchronize" %espeak-synchronize) :int)

;;;# The callback

(defvar *synthesis-sink* nil
  "While espeak_Synth runs: a function of a sample vector chunk and the list of
events that arrived with it, each (:phoneme NAME MILLISECONDS) or (:word
POSITION LENGTH MILLISECONDS), POSITION the word's first character (1-based)
in the text and LENGTH its characters.")

(defun espeak-event-name (event)
  "The phoneme name in the id field of the espeak_EVENT at the pointer EVENT."
  (let ((id (cffi:foreign-slot-pointer event '(:struct %espeak-event) 'id)))
    (coerce (loop for i below 8
                  for code = (cffi:mem-aref id :unsigned-char i)
                  until (zerop code)
                  collect (code-char code))
            'string)))

(defun espeak-events (events)
  "The phoneme and word events in the list the callback got at EVENTS, as
\(:phoneme NAME MILLISECONDS) and (:word POSITION LENGTH MILLISECONDS)."
  (flet ((slot (event name) (cffi:foreign-slot-value event '(:struct %espeak-event) name)))
    (loop for i from 0
          for event = (cffi:mem-aptr events '(:struct %espeak-event) i)
          for type = (slot event 'type)
          until (= type +espeak-event-list-terminated+)
          when (= type +espeak-event-phoneme+)
            collect (list :phoneme (espeak-event-name event) (slot event 'audio-position))
          when (= type +espeak-event-word+)
            collect (list :word (slot event 'text-position) (slot event 'length) (slot event 'audio-position)))))

(cffi:defcallback espeak-synth-callback :int ((wav :pointer) (count :int) (events :pointer))
  ;; A null WAV with the events of the end; returning 0 goes on, 1 aborts.
  (handler-case
      (let ((chunk (make-samples (if (cffi:null-pointer-p wav) 0 (max 0 count)))))
        (dotimes (i (length chunk))
          (setf (aref chunk i) (cffi:mem-aref wav :short i)))
        (when *synthesis-sink*
          (funcall *synthesis-sink* chunk (espeak-events events)))
        0)
    (error () 1)))

;;;# The Lisp layer

(defvar *espeak-rate* nil
  "The sample rate espeak_Initialize reported, once initialised (22050 for espeak-ng's voices).")

(defun ensure-espeak ()
  "Load and initialise espeak-ng once, for synchronous synthesis with phoneme
events; returns its sample rate.  Signals SPEECH-UNAVAILABLE when the library
or its data (espeak-ng-data) is missing."
  (or *espeak-rate*
      (progn
        (load-espeak-library)
        (let ((rate (with-speech-traps-masked
                      (%espeak-initialize +audio-output-synchronous+ 0 (cffi:null-pointer)
                                          (logior +espeak-initialize-phoneme-events+
                                                  +espeak-initialize-dont-exit+)))))
          (unless (plusp rate)
            (error 'speech-unavailable :package "espeak-ng-data"
                                       :message "espeak-ng could not start (its voices are missing?): install the Debian package espeak-ng-data"))
          (%espeak-set-synth-callback (cffi:callback espeak-synth-callback))
          (setf *espeak-rate* rate)))))

(defun espeak-set-voice (voice)
  "Make VOICE (a name such as \"en-us\") espeak-ng's voice; a SPEECH-ERROR when it has none such."
  ;; An MBROLA voice (mb-en1, mb/mb-en1) runs the mbrola program, whose
  ;; absence espeak-ng reports in eight lines on stderr: refused before.
  (when (or (eql 0 (search "mb-" voice :test #'char-equal)) (eql 0 (search "mb/" voice :test #'char-equal)))
    (speech-fail "~A is an MBROLA voice, which Player does not use (try en, en-us, en-gb; `espeak-ng --voices` lists them)" voice))
  (unless (= +ee-ok+ (with-speech-traps-masked (%espeak-set-voice-by-name voice)))
    (speech-fail "espeak-ng has no voice ~A (try en, en-us, en-gb; `espeak-ng --voices` lists them)" voice)))

(defun espeak-set-rate (rate)
  "Set espeak-ng's speed to RATE words a minute; a SPEECH-ERROR when it refuses."
  (unless (= +ee-ok+ (%espeak-set-parameter +espeak-rate+ rate 0))
    (speech-fail "espeak-ng refused the rate ~A words a minute (80 to 450)" rate)))

(defun espeak-speak (text sink)
  "Synthesise TEXT, calling SINK with each chunk of samples and its phoneme
and word events (see *SYNTHESIS-SINK*), and return when all is spoken.  A SPEECH-ERROR
when espeak-ng fails."
  (let* ((octets (sb-ext:string-to-octets text :external-format :utf-8 :null-terminate t))
         (status (cffi:with-pointer-to-vector-data (pointer octets)
                   (let ((*synthesis-sink* sink))
                     (with-speech-traps-masked
                       (prog1 (%espeak-synth pointer (length octets) 0 +espeak-pos-character+ 0
                                             +espeak-chars-utf8+ (cffi:null-pointer) (cffi:null-pointer))
                         (%espeak-synchronize)))))))
    (unless (= status +ee-ok+)
      (speech-fail "espeak-ng could not speak ~S (status ~D)" (truncate-text text 60) status))))
