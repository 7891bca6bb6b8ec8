;;;; recording.lisp -- a recorded scenario as data: what was played (the
;;;; header: spec, initial state, events, clock stop, policy, frame rate) and
;;;; what came out (the trace lines as `player run` prints them, and with
;;;; frames the body frames as `player simulate --frames` writes them).

(in-package #:player.traces)

(defstruct (recording (:constructor %make-recording))
  "A recorded scenario.  SPEC-NAME names the spec played; SPEC-FILE is its
file as recorded (relative to the recording file when it was written there,
or NIL).  INITIAL is the alist of starting values, EVENTS the scenario
entries (NAME or (NAME . SECONDS)), AT the time the clock stopped (or NIL),
WHEN-BUSY the policy overriding every event's (a keyword or NIL).  FRAMES-P
says whether body frames were recorded, at FPS frames per second with the
random drivers' SEED, the script library SCRIPTS (a path or NIL for the
spec's own) on the skeleton BODY (a name or NIL).  LINES are the trace lines
as text; FRAMES the frame forms.  FILE is the file it was read from (or NIL),
LINE-NUMBERS and FRAME-LINE-NUMBERS the file lines of each line and frame."
  spec-name spec-file (initial '()) (events '()) at when-busy
  frames-p (fps 30) (seed 0) scripts body
  (lines '()) (frames '())
  file (line-numbers '()) (frame-line-numbers '()))

(defparameter *recording-version* 1
  "The version of the recording format WRITE-RECORDING writes and READ-RECORDING reads.")

;;;# Names, as a recording stores them

(defun recorded-name (name)
  "NAME (a symbol or string) as the PLAYER-USER symbol a recording stores, so
it reads back whatever package it came from.  Keywords, T and NIL stay."
  (cond ((or (keywordp name) (member name '(t nil))) name)
        ((symbolp name) (intern (name-key name) '#:player-user))
        (t (intern (string-upcase name) '#:player-user))))

(defun recorded-event (entry)
  "A scenario ENTRY as recorded: NAME, or (NAME . SECONDS) with SECONDS a double."
  (if (consp entry)
      (cons (recorded-name (car entry)) (to-double (cdr entry)))
      (recorded-name entry)))

(defun recorded-initial (initial)
  "The initial-state alist INITIAL with its variables, and symbolic values, as recorded."
  (mapcar (lambda (pair)
            (cons (recorded-name (car pair))
                  (if (symbolp (cdr pair)) (recorded-name (cdr pair)) (cdr pair))))
          initial))

;;;# The header

(defun recording-header (recording)
  "The (:recording ...) form that opens RECORDING's file."
  (list :recording :version *recording-version*
        :spec (recording-spec-name recording) :spec-file (recording-spec-file recording)
        :initial (recording-initial recording) :events (recording-events recording)
        :at (recording-at recording) :when-busy (recording-when-busy recording)
        :frames (recording-frames-p recording) :fps (recording-fps recording)
        :seed (recording-seed recording) :scripts (recording-scripts recording)
        :body (recording-body recording)))

(defparameter *recording-header-fields*
  `((:version ,(lambda (x) (eql x *recording-version*))
              ,(format nil "~D, the version this Player reads" *recording-version*))
    (:spec ,(lambda (x) (and x (symbolp x) (not (keywordp x)))) "a spec's name")
    (:spec-file ,(lambda (x) (or (null x) (and (stringp x) (plusp (length x))))) "NIL or a file name in a string")
    (:initial initial-state-p "an alist ((variable . value) ...)")
    (:events ,(lambda (x) (and (proper-list-p x) (every #'event-entry-p x)))
             "a list of event names and (name . seconds) pairs")
    (:at ,(lambda (x) (or (null x) (and (seconds-p x) (>= x 0)))) "NIL or a number of seconds from 0")
    (:when-busy ,(lambda (x) (or (null x) (member x *when-busy-policies*)))
                ,(format nil "NIL or one of ~{~(~S~)~^, ~}" *when-busy-policies*))
    (:frames ,(lambda (x) (member x '(t nil))) "T or NIL")
    (:fps ,(lambda (x) (and (realp x) (< 0 x) (<= x *max-fps*))) "a frame rate above 0")
    (:seed integerp "an integer")
    (:scripts ,(lambda (x) (or (null x) (and (stringp x) (plusp (length x))))) "NIL or a file name in a string")
    (:body ,(lambda (x) (and (symbolp x) (not (keywordp x)))) "NIL or a skeleton's name"))
  "Each header field of a recording: its key, a predicate its value must
satisfy, and how an error describes what it should be.")

(defun check-header-fields (plist file line)
  "Signal a RECORDING-ERROR about FILE at LINE for the first field of the
header plist PLIST that is missing, unknown or of the wrong kind."
  (unless (and (proper-list-p plist) (evenp (length plist)))
    (recording-fail file line "the header (:recording ...) must be followed by keys and values"))
  (loop for (key) on plist by #'cddr
        unless (assoc key *recording-header-fields*)
          do (recording-fail file line "the header has an unknown field ~A (known: ~{~(~S~)~^ ~})"
                             (bounded-lisp-text key 40) (mapcar #'first *recording-header-fields*)))
  (loop for (key predicate expected) in *recording-header-fields*
        for tail = (member key plist)
        do (cond ((and (null tail) (member key '(:version :spec)))
                  (recording-fail file line "the header has no ~(~S~) field" key))
                 ((and tail (not (funcall predicate (second tail))))
                  (recording-fail file line "the header's ~(~S~) must be ~A, not ~A"
                                  key expected (bounded-lisp-text (second tail) 80))))))

(defun header-recording (form file line)
  "The RECORDING the header FORM, (:recording KEY VALUE ...), describes, its
lines and frames still empty; a RECORDING-ERROR about FILE at LINE when FORM
is no header or a field is wrong."
  (unless (and (consp form) (eq (first form) :recording))
    (recording-fail file line "a recording begins with its header (:recording :version ~D ...), not ~A"
                    *recording-version* (bounded-lisp-text form 80)))
  (let ((plist (rest form)))
    (check-header-fields plist file line)
    (%make-recording :spec-name (getf plist :spec) :spec-file (getf plist :spec-file)
                     :initial (getf plist :initial)
                     :events (mapcar (lambda (entry)
                                       (if (consp entry) (cons (car entry) (to-double (cdr entry))) entry))
                                     (getf plist :events))
                     :at (and (getf plist :at) (to-double (getf plist :at)))
                     :when-busy (getf plist :when-busy)
                     :frames-p (getf plist :frames) :fps (getf plist :fps 30)
                     :seed (getf plist :seed 0) :scripts (getf plist :scripts)
                     :body (getf plist :body) :file file)))
