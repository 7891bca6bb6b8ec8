;;;; options.lisp -- the command line's vocabulary: the usage error (exit
;;;; status 2), option types (how a value is read, checked and described) and
;;;; the options several commands share, each declared once.

(in-package #:player.cli)

(define-condition usage-error (player-error-with-message)
  ()
  (:documentation "The command line itself is wrong: an unknown command or
option, a missing argument, or a value of the wrong form.  Exit status 2."))

(defun usage-fail (control &rest arguments)
  "Signal a USAGE-ERROR with a message from CONTROL and ARGUMENTS."
  (error 'usage-error :message (apply #'format nil control arguments)))

;;;# Options

(defstruct (option (:constructor %make-option))
  "One command-line option: its NAME (\"--fps\"), the TYPE its value is read
as (see READ-OPTION-VALUE; :flag takes no value), the METAVAR shown for the
value in help, the HELP text, and the DEFAULT value (already read; NIL for none)
with DEFAULT-TEXT, how help shows it."
  (name "" :type string)
  (type :string)
  (metavar "VALUE" :type string)
  (help "" :type string)
  (default nil)
  (default-text nil))

(defvar *options* (make-hash-table :test 'equal)
  "Options shared by several commands, by name.")

(defun make-option (name type metavar help &key default default-text)
  "An OPTION; DEFAULT-TEXT defaults to DEFAULT as written on the command line."
  (%make-option :name name :type type :metavar metavar :help help :default default
                :default-text (or default-text (and default (princ-to-string default)))))

(defun define-option (name type metavar help &rest keys &key default default-text)
  "Declare the shared option NAME (see MAKE-OPTION); commands name it in their :options."
  (declare (ignore default default-text))
  (setf (gethash name *options*) (apply #'make-option name type metavar help keys)))

(defun option-keyword (option)
  "The keyword OPTION's value is passed as: --initial is :INITIAL."
  (intern (string-upcase (string-left-trim "-" (option-name option))) :keyword))

(defun resolve-option (designator)
  "The OPTION DESIGNATOR gives: a shared option's name, a shared option's name
with overrides (\"--fps\" :default 24, :help \"...\"), or a full (NAME TYPE METAVAR HELP &key ...)."
  (destructuring-bind (name &rest rest) (ensure-list designator)
    (let ((shared (gethash name *options*)))
      (cond ((and shared (or (null rest) (keywordp (first rest))))
             (let ((option (copy-option shared)))
               (when rest
                 (destructuring-bind (&key (default nil default-p) default-text help) rest
                   (when default-p
                     (setf (option-default option) default
                           (option-default-text option) (or default-text (princ-to-string default))))
                   (when help
                     (setf (option-help option) help))))
               option))
            (rest (apply #'make-option name rest))
            (t (error "internal: no shared option ~A" name))))))

;;;# Reading values

(defun check-reader-limits (text what)
  "A USAGE-ERROR naming WHAT (\"the value\", \"--goal\") when the command-line
TEXT asks the Lisp reader for more than a data file may (READER-LIMIT-PROBLEM):
every command-line datum is checked so before it is read."
  (multiple-value-bind (position problem) (reader-limit-problem text)
    (when position
      (usage-fail "cannot read ~A ~A: ~A" what (bounded-lisp-text text 40) problem))))

(defun read-cli-form (text what)
  "The one datum the command-line TEXT holds, read as a data file's forms are
\(symbols in PLAYER-USER, doubles, no #. and no #S), never evaluated:
\(VALUES FORM T END), END where the datum ends, or NIL when TEXT holds no
datum, a datum that cannot be read, or more than one.  First a USAGE-ERROR
naming WHAT when TEXT asks the reader for more than a data file may:
#100000000A() took 10 s and 2 GB to read before it was refused."
  (check-reader-limits text what)
  (handler-case
      (with-standard-io-syntax
        (let ((*readtable* *data-readtable*)
              (*read-eval* nil)
              (*read-default-float-format* 'double-float)
              (*package* (find-package '#:player-user)))
          (multiple-value-bind (form end) (read-from-string text)
            (if (string= "" (string-trim '(#\Space #\Tab #\Newline) (subseq text end)))
                (values form t end)
                nil))))
    (error () nil)))

(defun read-cli-value (text)
  "The value TEXT denotes on the command line: a number, or a symbol in
PLAYER-USER, and nothing after it (READ-CLI-FORM).  Never evaluates
anything; a USAGE-ERROR when TEXT is not one number or name."
  (multiple-value-bind (value one end) (read-cli-form text "the value")
    (if (and one (= end (length text)) (or (realp value) (symbolp value)))
        value
        (usage-fail "cannot read the value ~S: give a number or a name" text))))

(defgeneric read-option-value (type text option)
  (:documentation "The value TEXT gives OPTION, whose type is TYPE (a keyword,
or a list whose first element is a keyword); a USAGE-ERROR naming OPTION when
TEXT does not fit."))

(defun bad-option-value (option text what)
  "Signal the USAGE-ERROR for OPTION given TEXT, which is not WHAT."
  (usage-fail "~A takes ~A, not ~S" (option-name option) what text))

(defmethod read-option-value ((type (eql :string)) text option)
  (when (string= text "") (bad-option-value option text "a non-empty text"))
  text)

(defmethod read-option-value ((type (eql :name)) text option)
  (unless (and (plusp (length text)) (every (lambda (c) (or (alphanumericp c) (find c "-_.+*"))) text))
    (bad-option-value option text "a name"))
  (intern (string-upcase text) '#:player-user))

(defmethod read-option-value ((type (eql :skeleton)) text option)
  ;; A path (it has a / or a file type: ./mine.skel) is given to LOAD-SKELETON
  ;; as a string, which reads the file; anything else names a shipped skeleton.
  (if (and (find-if (lambda (c) (find c "/.")) text) (notany #'control-character-p text))
      text
      (read-option-value :name text option)))

(defmethod read-option-value ((type (eql :names)) text option)
  (declare (ignore option))
  (split-list text))

(defun read-seconds-text (text)
  "TEXT as a number of seconds from 0 to *MAX-SECONDS*, or NIL: an exact
decimal (123456789012.000001, 1e15, 1.5E-3) read exactly, never through a
double, so times keep every microsecond; else any real Lisp reads (1/3)."
  (let ((value (or (parse-decimal-seconds text) (read-cli-value text))))
    (and (realp value) (finite-real-p value) (<= 0 value *max-seconds*)
         (if (floatp value) (to-double value) value))))

(defmethod read-option-value ((type (eql :timed-events)) text option)
  ;; EV or EV@SECONDS, comma-separated: names, and (NAME . SECONDS) for a timed
  ;; arrival.  Times may not decrease: a timed controller cannot go back.  Nor
  ;; may a timed arrival follow an untimed EV, sent once the events before it
  ;; have ended: when that is is known only by playing, so the whole list is
  ;; checked here, before anything plays, rather than failing halfway.
  (let ((latest 0d0) (untimed nil))
    (mapcar (lambda (part)
              (let ((at (position #\@ part)))
                (when (and at untimed)
                  (usage-fail "~A: ~A follows ~A, which is sent when the events before it have ended, a time known only by playing; give ~A a time too, or put the timed events first"
                              (option-name option) part untimed untimed))
                (if (null at)
                    (setf untimed part)
                    (let ((name (subseq part 0 at))
                          (time (read-seconds-text (subseq part (1+ at)))))
                      (when (or (string= name "") (null time))
                        (bad-option-value option part "EVENT@SECONDS, seconds a number from 0 (e.g. ev-sit@0.4)"))
                      (when (< time latest)
                        (usage-fail "~A: ~A comes before an earlier event's time ~A; times may not decrease"
                                    (option-name option) part (format-number latest)))
                      (setf latest time)
                      (cons name time)))))
            (split-list text))))

(defmethod read-option-value ((type (eql :seconds)) text option)
  (or (read-seconds-text text)
      (bad-option-value option text "a number of seconds from 0")))

(defmethod read-option-value ((type (eql :integer)) text option)
  (let ((value (read-cli-value text)))
    (unless (integerp value) (bad-option-value option text "an integer"))
    value))

(defmethod read-option-value ((type (eql :positive-integer)) text option)
  (let ((value (read-cli-value text)))
    (unless (and (integerp value) (plusp value)) (bad-option-value option text "a positive integer"))
    value))

(defparameter *max-frame-rate* 1000 "The highest frame rate --fps accepts.")

(defmethod read-option-value ((type (eql :frame-rate)) text option)
  (let ((value (read-cli-value text)))
    (unless (and (realp value) (< 0 value) (<= value *max-frame-rate*))
      (bad-option-value option text (format nil "a frame rate above 0 and at most ~D" *max-frame-rate*)))
    value))

(defmethod read-option-value ((type (eql :size)) text option)
  (multiple-value-bind (width height) (read-size text)
    (unless width
      (bad-option-value option text (format nil "WIDTHxHEIGHT, two integers from 1 to ~D (e.g. 640x480)"
                                            *max-image-side*)))
    (list width height)))

(defmethod read-option-value ((type cons) text option)
  ;; (:choice "a" "b"): one of the texts.
  (ecase (first type)
    (:choice (or (find text (rest type) :test #'string=)
                 (bad-option-value option text (format nil "one of ~{~A~^, ~}" (rest type)))))))

(defmethod read-option-value ((type (eql :assignments)) text option)
  ;; VAR=VALUE,... as an alist of PLAYER-USER symbols to values, each variable once.
  (let ((alist '()))
    (dolist (part (split-list text) (nreverse alist))
      (let ((equals (position #\= part)))
        (unless (and equals (plusp equals) (< equals (1- (length part))))
          (bad-option-value option part "var=value pairs"))
        (let ((name (intern (string-upcase (subseq part 0 equals)) '#:player-user)))
          (when (assoc name alist)
            (usage-fail "~A gives ~A twice" (option-name option) (string-downcase name)))
          (push (cons name (read-cli-value (subseq part (1+ equals)))) alist))))))

;;;# The options several commands share

(define-option "--spec" :string "NAME"
  "the spec to use, when SPEC-FILE defines several")
(define-option "--no-code" :flag ""
  "refuse a spec holding :code or :c++, so an untrusted spec file runs no code")
(define-option "--silent" :flag ""
  "play :say and :sound items silently: no sound, no beak (espeak-ng is then not needed)")
(define-option "--initial" :assignments "VAR=VALUE,..."
  "start from these values instead of the declared initial ones")
(define-option "--events" :timed-events "EV1,EV2@T,..."
  "the events to send, in order: EV when the previous ones have ended, EV@T arriving at T seconds, whatever is running (then its :when-busy policy decides)")
(defun policy-keyword (text)
  "The :when-busy policy keyword TEXT (one of --when-busy's choices) names, or NIL for NIL."
  (and text (when-busy-policy (intern (string-upcase text) :keyword))))

(defmethod read-option-value ((type (eql :policies)) text option)
  ;; POLICY,... as keywords of *WHEN-BUSY-POLICIES*.
  (mapcar (lambda (part)
            (or (find part *when-busy-policies* :key #'symbol-name :test #'string-equal)
                (bad-option-value option part (format nil "policies among ~{~(~A~)~^, ~}"
                                                      (mapcar #'symbol-name *when-busy-policies*)))))
          (split-list text)))

(define-option "--when-busy" (quote (:choice "queue" "preempt" "override" "interleave")) "POLICY"
  "what every event arriving while another plays does, instead of its own :when-busy policy")
(define-option "--at" :seconds "T"
  "stop the clock at T seconds, showing what happened until then (timers included)")
(define-option "--fps" :frame-rate "FPS"
  "frames per second of simulated time" :default 30)
(define-option "--seed" :integer "N"
  "the seed of the random drivers (blinks, saccades)" :default 0)
(define-option "--scripts" :string "FILE"
  "the script library to use instead of the spec's (:scripts FILE)")
(define-option "--body" :skeleton "NAME|FILE"
  "the skeleton to use instead of the spec's (:body NAME): a shipped one (humanoid, parrot) or a skeleton file's path")
(define-option "--size" :size "WxH"
  "the image size in pixels" :default '(640 480) :default-text "640x480")
