;;;; scripts.lisp -- ReActor's scripts as data: motor calls, property bindings,
;;;; nested scripts and reparentings placed on a script's local timeline.
;;;; The header below is the reference for the whole script-library language;
;;;; directors.lisp parses DEFDIRECTOR, script-library.lisp reads library files.

(in-package #:player.performance)

;;; ---------------------------------------------------------------------------
;;; The script-library language
;;;
;;; A script library file holds top-level forms read as data (*READ-EVAL* NIL)
;;; in the package PLAYER-USER.  Names (of scripts, directors, objects, tags,
;;; critical times) are compared by name, case-insensitively.  Times are seconds.
;;;
;;;   (defscript NAME (&key duration loop critical beats documentation)
;;;     ITEM ...)
;;;
;;; NAME is a non-keyword symbol.  :BEATS N says the script spans N beats of
;;; music: looping, each iteration is stretched to N beats at the tempo of the
;;; music playing when it begins (tempo.lisp; Peedy's foot taps in time).
;;; :DURATION is a positive number of seconds;
;;; without it the script lasts until the latest end of its items: an item with
;;; :for D ends D after its start, a :play without :for when the nested script
;;; does, an :animate without :for at the last key of its control when that is
;;; a non-looping :keys control; any other item counts its start.  :LOOP T
;;; repeats the script every DURATION seconds until it is stopped.  :CRITICAL
;;; ((NAME . SECONDS) ...) names instants within [0, duration] that must be
;;; shown (the hammer hitting the nail), for items and directors to refer to.
;;;
;;; Each ITEM is (:at TIME KIND ...), TIME being seconds from the start of the
;;; script (of each iteration, when it loops) or the name of a critical time:
;;;
;;;   (:at T :motor FRAME [:for D])
;;;       Call a motor function of the character playing the script, e.g.
;;;       (:gaze :target (:object user)); the frame is checked when the library
;;;       is read.  The call lasts D seconds, or until the script ends.
;;;   (:at T :animate (OBJECT PROPERTY) CONTROL [:for D])
;;;       Bind a control (see PARSE-CONTROL) to a property of a scene object;
;;;       the control's time 0 is the item's start.  OBJECT :self is the
;;;       character playing the script.  Every object has POSITION (a vector),
;;;       ROTATION (a rotation) and VISIBLE (a boolean, which can only be :set);
;;;       DEFOBJECT declares others.
;;;   (:at T :set (OBJECT PROPERTY) VALUE)
;;;       Set a property once: VALUE is T or NIL for a boolean, else a control
;;;       value: a number, (:vec3 X Y Z), (:quat W X Y Z), (:euler X Y Z) in
;;;       radians, (:axis-angle (X Y Z) RADIANS).
;;;   (:at T :play SCRIPT [:for D])
;;;       Play another script of the library, its timeline starting at T.
;;;       Nested scripts may not form a cycle.
;;;   (:at T :attach OBJECT :to PARENT [:keep-world BOOLEAN])
;;;       Reparent OBJECT: PARENT is an object's name, (OBJECT JOINT-OR-ROLE)
;;;       for a joint of a body (a joint's name or a role such as :right-hand;
;;;       OBJECT may be :self), or NIL for the scene root.  With :keep-world T
;;;       (the default) OBJECT stays where it is in the world.
;;;   (:at T :say "TEXT" [:voice "VOICE"] [:rate WPM] [:as NAME] [:for D])
;;;       Speak TEXT (espeak-ng; VOICE default "en-us", RATE words a minute,
;;;       default 160): the jaw (a parrot's beak) moves through the visemes of
;;;       its phonemes, timed by the synthesiser, and the sound goes on the
;;;       performance's audio track.  Its length is known before it plays
;;;       (synthesised when the library is read), so the script's inferred
;;;       duration covers the whole sentence (without a speech library, only
;;;       its start).  Its words are sync points: a later item's TIME may be
;;;       (:word "WORD" [OFFSET]) or (:word N [OFFSET]), when the nearest :say
;;;       written before it says that word (the first spelt so, ignoring case
;;;       and punctuation) or its Nth word, plus OFFSET seconds; (:word NAME
;;;       "WORD" [OFFSET]) names the :say written :as NAME (word-sync.lisp).
;;;   (:at T :sound "FILE.wav" [:for D])
;;;       Play a sound effect (Persona's snore), a PCM WAV file named relative
;;;       to the library file, read when the library is.
;;;   (:at T :clip NAME [:loop B] [:speed S] [:fade SECONDS] [:weight W]
;;;        [:joints (JOINT-OR-ROLE ...)] [:root :in-place|:move] [:priority P] [:for D])
;;;       Play an animation clip of the library's model (see below): its
;;;       joints follow the file's keys (slerped), fading in over :fade
;;;       (default 0.2) from whatever lies under them, so two clips
;;;       cross-fade; :weight (0 to 1) how much of it shows; :joints masks it
;;;       (a role means its joints); it requests its channels at :priority
;;;       (default 10) like any motor call.  Without :loop it ends with the
;;;       clip, and its length counts for the script's inferred duration.
;;;   Speech and sounds play to their end, cut only by :for or a stop of
;;;   their script (an op cut short), not by the end of the script.
;;;
;;; No item may start after an explicit :duration, nor end after it with :for;
;;; every item ends at the latest with its script (with each iteration).
;;;
;;;   (defdirector NAME [DOCSTRING] [TRIGGER] STEP ...)
;;;
;;; A director starts scripts at times relative to its own start, taking its
;;; steps in order:
;;;   (:start SCRIPT [:as TAG] [:at WHEN])  start SCRIPT, known to later steps as
;;;                                         TAG (default: the script's name)
;;;   (:stop TAG [:at WHEN])                stop the script started as TAG
;;;   (:set (OBJECT PROPERTY) VALUE [:at WHEN])  set a property, as a :set item
;;;   (:send EVENT [:at WHEN])              send a Player event to the controller
;;; A TRIGGER, (:when EXPRESSION), (:on EVENT) or (:after DIRECTOR), makes
;;; it start by itself (reactions.lisp): when a state or property expression
;;; becomes true, a Player event is processed, or another director ends.
;;; WHEN is seconds after the director starts, or one of
;;;   (:start TAG [OFFSET])                 when TAG starts
;;;   (:critical TAG NAME [OFFSET])         when TAG reaches its critical time NAME
;;;   (:end TAG [OFFSET])                   when TAG ends, stopped or not
;;; plus OFFSET seconds (default 0; may be negative).  A step without :at comes
;;; when the script of the last :start before it ends (sequencing), the first
;;; step at 0.  A looping script never ends by itself: a step waiting for its
;;; end must come after a :stop of it.  A director lasts until the last of its
;;; scripts ends (for ever if one loops unstopped).
;;;
;;;   (defobject NAME &key kind parent position rotation properties documentation
;;;                        model texture height scale up)
;;;
;;; declares a scene object: KIND :prop (the default), :camera, :light or
;;; :group; PARENT as for :attach (default NIL); POSITION (X Y Z) metres
;;; relative to the parent; ROTATION (W X Y Z), a quaternion, or (:euler X Y Z)
;;; in DEGREES; PROPERTIES ((NAME TYPE VALUE) ...) with TYPE :number, :vector
;;; (X Y Z), :rotation (as ROTATION), :colour (R G B), each in [0, 1], or
;;; :boolean (T or NIL).
;;;
;;;   (model "FILE" &key texture height scale up roles clips limits)
;;;
;;; makes the character an imported model (glTF, FBX, COLLADA, .x, BVH...,
;;; through Assimp), in place of the spec's (:body NAME): see model-form.lisp
;;; and doc/models.md.  Each of its animations is a clip, named in lower case
;;; with other characters turned to -; :clips cuts more by frame range.
;;;
;;;   (poses "FILE")
;;;
;;; names the pose library the keyframe driver loads, relative to this file.
;;; The skeleton's shipped poses stay: yours override them by name.
;;;
;;; A script an op or autoscript plays that the library lacks plays a
;;; placeholder gesture for its op (placeholders.lisp), and `check` warns of
;;; it; a missing director is an error.

;;; ---------------------------------------------------------------------------
;;; Errors

(define-condition script-error (spec-error)
  ()
  (:report report-spec-error-safely)
  (:documentation "A script library is unreadable, malformed or inconsistent.
FORM is the offending item, step or definition; the position names the file."))

(defvar *script-context* nil
  "While a definition is parsed or checked: \"script NAME\" or \"director NAME\",
the prefix of every error message.")

(defvar *say-items* '()
  "While a script's items are parsed: the :say items parsed so far, newest
first, which a (:word ...) time refers to (word-sync.lisp).")

(defun script-fail (form control &rest arguments)
  "Signal a SCRIPT-ERROR about FORM, with a message from CONTROL and ARGUMENTS
prefixed by *SCRIPT-CONTEXT*."
  (error 'script-error :form form :spec nil
                       :message (format nil "~@[~A: ~]~?" *script-context* control arguments)))

(defun name= (a b)
  "Do the symbols or strings A and B name the same thing (case-insensitively)?"
  (string-equal (string a) (string b)))

(defun usable-name-p (thing)
  "Is THING a symbol that can name something: not NIL, not a keyword?"
  (and thing (symbolp thing) (not (keywordp thing))))

(defun parse-seconds (value form what &key positive)
  "VALUE, a real >= 0 (> 0 with POSITIVE) up to *MAX-SECONDS*, as a
double-float; else a SCRIPT-ERROR about FORM saying what WHAT must be."
  (unless (and (seconds-p value) (if positive (plusp value) (>= value 0)))
    (script-fail form "~A must be a ~:[non-negative~;positive~] number of seconds up to ~A, not ~A"
                 what positive (number-text *max-seconds*) (argument-value-text value)))
  (float value 1d0))

(defun check-options (form options allowed &optional (what "this form"))
  "OPTIONS (from FORM) if it is a plist of distinct keys among ALLOWED; else a SCRIPT-ERROR."
  (unless (and (alexandria:proper-list-p options) (evenp (length options)))
    (script-fail form "the options of ~A must be :keyword value pairs" what))
  (loop for (key) on options by #'cddr
        for rest on options by #'cddr
        do (cond ((not (member key allowed))
                  (script-fail form "~A has no option ~A~:[ (it takes none)~; (options: ~:*~{~A~^ ~})~]"
                               what (lisp-text key) (mapcar #'lisp-text allowed)))
                 ((loop for later in (cddr rest) by #'cddr thereis (eq later key))
                  (script-fail form "~A gives the option ~A twice" what (lisp-text key)))))
  options)

;;; ---------------------------------------------------------------------------
;;; Data

(defstruct (script (:constructor %make-script))
  "A script: ITEMS placed on a local timeline of DURATION seconds (inferred from
the items when not given, once the whole library is read), repeated when LOOP.
CRITICAL is an alist (NAME . SECONDS).  SOURCE is (FILE . POSITION) or NIL, FORM
the DEFSCRIPT form."
  (name nil :type symbol :read-only t)
  (duration nil :type (or null double-float))
  (loop nil :type boolean :read-only t)
  (critical '() :type list :read-only t)
  (beats nil :type (or null double-float) :read-only t)
  (items '() :type list :read-only t)
  (documentation nil :type (or null string) :read-only t)
  (source nil :read-only t)
  (form nil :read-only t))

(defmethod print-object ((script script) stream)
  (print-unreadable-object (script stream :type t)
    (format stream "~A~@[ ~As~]" (lisp-text (script-name script))
            (and (script-duration script) (format-number (script-duration script))))))

(defstruct (script-item (:constructor nil))
  "One timed item of a script: it starts AT seconds into the script and lasts
UNTIL seconds (the :for value), or, when UNTIL is NIL, until the script (the
iteration) ends.  FORM is the item as written.  (AT and UNTIL are written
only to a copy, when a script is played at a tempo: tempo.lisp.)"
  (at 0d0 :type double-float)
  (until nil :type (or null double-float))
  (form nil :read-only t))

(defstruct (motor-item (:include script-item))
  "A motor-function call: the checked MOTOR-CALL of FRAME."
  (frame nil :read-only t)
  (call nil :read-only t))

(defstruct (play-item (:include script-item))
  "The script named SCRIPT played with its timeline starting at the item's start."
  (script nil :type symbol :read-only t))

(defun script-item-end (item)
  "Where ITEM ends on its script's timeline when it has a :for, else NIL."
  (and (script-item-until item) (+ (script-item-at item) (script-item-until item))))

(defun script-critical-time (script name &optional (errorp t))
  "The seconds into SCRIPT of its critical time NAME.  Unknown names are a
SCRIPT-ERROR listing the known ones, or NIL without ERRORP."
  (check-argument 'script-critical-time 'script script #'script-p "a script (from find-script)")
  (check-argument 'script-critical-time 'name name #'string-designator-p "a critical time's name (a symbol or string)")
  (let ((entry (assoc name (script-critical script) :test #'name=)))
    (cond (entry (cdr entry))
          (errorp (script-fail name "unknown critical time ~A in script ~A (known: ~:[none~;~:*~{~A~^ ~}~])"
                               (lisp-text name) (lisp-text (script-name script))
                               (mapcar (lambda (entry) (lisp-text (car entry)))
                                       (script-critical script)))))))

;;; ---------------------------------------------------------------------------
;;; Parsing DEFSCRIPT

(defparameter *shortest-loop* 1d-3
  "The shortest duration, in seconds, of a looping script: a shorter one would
repeat too often to play.")

(defun parse-defscript (form &optional source)
  "The SCRIPT that FORM, (defscript NAME (&key ...) ITEM...), defines; SOURCE is
its (FILE . POSITION).  Nested scripts stay names and an omitted duration NIL
until the library resolves them.  Signals SCRIPT-ERROR naming the bad part."
  (unless (and (alexandria:proper-list-p form) (>= (length form) 3)
               (usable-name-p (second form)) (listp (third form)))
    (script-fail form "a script is written (defscript NAME (&key duration loop critical beats documentation) ITEM...)"))
  (destructuring-bind (name options &rest items) (rest form)
    (let ((*script-context* (format nil "script ~A" (lisp-text name))))
      (check-options form options '(:duration :loop :critical :beats :documentation) "defscript")
      (destructuring-bind (&key duration loop critical beats documentation) options
        (unless (or (null beats) (and (realp beats) (< 0 beats 1000)))
          (script-fail form ":beats must be a positive number of beats, not ~A" (argument-value-text beats)))
        (let* ((duration (and duration (parse-seconds duration form ":duration" :positive t)))
               (critical (parse-critical-times critical duration form)))
          (unless (member loop '(t nil))
            (script-fail form ":loop must be T or NIL, not ~A" (lisp-text loop)))
          (when (and loop duration (< duration *shortest-loop*))
            (script-fail form "a looping script must last some time (at least ~A s), not ~A"
                         (format-number *shortest-loop*) (argument-value-text duration)))
          (unless (typep documentation '(or null string))
            (script-fail form ":documentation must be a string"))
          (%make-script :name name :duration duration :loop loop :critical critical
                        :beats (and beats (float beats 1d0))
                        :items (let ((*say-items* '()))
                                 (loop for item in items
                                       for parsed = (parse-script-item item critical duration)
                                       ;; TYPEP, not SAY-ITEM-P: audio-items.lisp,
                                       ;; later, declares the record.
                                       when (typep parsed 'say-item) do (push parsed *say-items*)
                                       collect parsed))
                        :documentation documentation :source source :form form))))))

(defun parse-critical-times (critical duration form)
  "The alist (NAME . SECONDS) CRITICAL denotes, checked against DURATION (when known)."
  (unless (alexandria:proper-list-p critical)
    (script-fail form ":critical must be a list of (NAME . SECONDS)"))
  (loop for entry in critical
        for (name . time) = (if (consp entry) entry (list nil))
        for seconds = (if (and (consp time) (null (cdr time))) (first time) time)
        do (unless (usable-name-p name)
             (script-fail form "a critical time is written (NAME . SECONDS), not ~A" (lisp-text entry)))
           (when (find name parsed :key #'car :test #'name=)
             (script-fail form "critical time ~A is given twice" (lisp-text name)))
           (when (and duration (realp seconds) (> seconds duration))
             (script-fail form "critical time ~A (~A) lies after the script's duration ~A"
                          (lisp-text name) (lisp-text seconds) (format-number duration)))
        collect (cons name (parse-seconds seconds form (format nil "critical time ~A" (lisp-text name))))
          into parsed
        finally (return parsed)))

(defparameter *script-item-kinds* '(:motor :animate :set :play :attach :say :sound :clip)
  "The kinds of script item, each parsed by PARSE-<KIND>-ITEM.")

(defun parse-script-item (item critical duration)
  "The SCRIPT-ITEM ITEM, (:at TIME KIND ...), denotes in a script with CRITICAL
times and DURATION (NIL when inferred)."
  (unless (and (alexandria:proper-list-p item) (>= (length item) 3) (eq (first item) :at))
    (script-fail item "an item is written (:at TIME KIND ...) with KIND one of ~{~A~^ ~}"
                 (mapcar #'lisp-text *script-item-kinds*)))
  (destructuring-bind (time kind &rest arguments) (rest item)
    (let ((at (cond ((usable-name-p time)
                     (or (cdr (assoc time critical :test #'name=))
                         (script-fail item "unknown critical time ~A (known: ~:[none~;~:*~{~A~^ ~}~])"
                                      (lisp-text time) (mapcar (lambda (e) (lisp-text (car e))) critical))))
                    ((word-sync-form-p time) (word-sync-time item time))
                    (t (parse-seconds time item "an item's time (the name of a critical time, or (:word WORD))")))))
      (unless (member kind *script-item-kinds*)
        (script-fail item "unknown item kind ~A (known: ~{~A~^ ~})"
                     (lisp-text kind) (mapcar #'lisp-text *script-item-kinds*)))
      (when (and duration (> at duration))
        (script-fail item "the item starts at ~A, after the script's duration ~A"
                     (format-number at) (format-number duration)))
      (let ((parsed (funcall (ecase kind
                               (:motor #'parse-motor-item) (:animate #'parse-animate-item)
                               (:set #'parse-set-item) (:play #'parse-play-item)
                               (:attach #'parse-attach-item) (:say #'parse-say-item)
                               (:sound #'parse-sound-item) (:clip #'parse-clip-item))
                             item at arguments)))
        (when (and duration (script-item-end parsed) (> (script-item-end parsed) duration))
          (script-fail item "the item ends at ~A, after the script's duration ~A"
                       (format-number (script-item-end parsed)) (format-number duration)))
        parsed))))

(defun item-parts (item arguments count allowed)
  "ARGUMENTS of ITEM split into its COUNT leading arguments and its options
(keys among ALLOWED), returned as the list of leading arguments, the options and
the :for value as seconds or NIL."
  (let ((kind (third item)))
    (when (< (length arguments) count)
      (script-fail item "the ~A item is missing its arguments" (lisp-text kind)))
    (let ((options (check-options item (nthcdr count arguments) allowed
                                  (format nil "the ~A item" (lisp-text kind)))))
      (values (subseq arguments 0 count) options
              (and (getf options :for) (parse-seconds (getf options :for) item ":for" :positive t))))))

(defun parse-motor-item (item at arguments)
  "(:at T :motor FRAME [:for D]); a bad frame's MOTOR-ERROR becomes a SCRIPT-ERROR about ITEM."
  (multiple-value-bind (parts options until) (item-parts item arguments 1 '(:for))
    (declare (ignore options))
    (make-motor-item :at at :until until :form item :frame (first parts)
                     :call (handler-case (parse-motor-frame (first parts))
                             (spec-error (error)
                               (script-fail item "~A" (spec-error-message error)))))))

(defun parse-play-item (item at arguments)
  "(:at T :play SCRIPT [:for D]); the library checks that SCRIPT exists."
  (multiple-value-bind (parts options until) (item-parts item arguments 1 '(:for))
    (declare (ignore options))
    (unless (usable-name-p (first parts))
      (script-fail item ":play takes the name of a script, not ~A" (lisp-text (first parts))))
    (make-play-item :at at :until until :form item :script (first parts))))
