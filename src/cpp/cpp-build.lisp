;;;; cpp-build.lisp -- compile generated C++ with a trace-printing driver and
;;;; run it: `bin/player run --backend c++`. Builds are cached by content.

(in-package #:player.cpp)

(defparameter *c++-flags* '("-std=c++17" "-O2" "-Wall" "-Wextra" "-Werror" "-pedantic")
  "How generated code is compiled; it must build cleanly with these.")

(defparameter *c++-compiler* "g++"
  "The compiler command, looked up on PATH.")

(defun c++-cache-root ()
  "Where compiled drivers are kept: $XDG_CACHE_HOME/player/c++/ or ~/.cache/player/c++/."
  (let ((xdg (sb-ext:posix-getenv "XDG_CACHE_HOME")))
    (merge-pathnames "player/c++/"
                     (if (and xdg (plusp (length xdg)))
                         (directory-pathname xdg)
                         (merge-pathnames ".cache/" (user-homedir-pathname))))))

(defun content-key (&rest texts)
  "A hex digest of TEXTS, naming a cache entry."
  (let ((digest (sb-md5:md5sum-string (format nil "~{~A~^~%--~%~}" texts))))
    (format nil "~{~(~2,'0X~)~}" (coerce digest 'list))))

(defun run-program-capturing (program arguments &key directory)
  "Run PROGRAM (searched on PATH) with ARGUMENTS; (VALUES EXIT-CODE STDOUT STDERR),
or NIL when the program cannot be started."
  ;; RUN-CHILD: an interrupt kills the compiler or the driver with us.
  (handler-case (run-child-output program arguments :search t :directory directory)
    (error () nil)))

(defun write-build-files (directory name header source driver)
  "Write NAME.hpp, NAME.cpp and NAME_main.cpp into DIRECTORY; return the sources to compile."
  (let ((main (concatenate 'string name "_main")))
    (write-text-file (output-file directory name "hpp") header)
    (write-text-file (output-file directory name "cpp") source)
    (write-text-file (output-file directory main "cpp") driver)
    (list (file-namestring (output-file directory name "cpp"))
          (file-namestring (output-file directory main "cpp")))))

(defun build-c++-driver (machine &key timed)
  "Generate MACHINE's C++ (with TIMED, its timed layer too) with a driver and
compile it (once per content);
return the executable's pathname. Each build runs in a directory of its own and
only the finished executable is renamed into place, so processes sharing the
cache never run, or write into, another's half-written files."
  (let* ((name (c++-safe-identifier (spec-name (machine-spec machine))))
         ;; Prefixed, so no spec name can collide with the C library's globals.
         (namespace (concatenate 'string "player_" name)))
    (multiple-value-bind (header source) (c++-sources machine name namespace :timed timed)
      (let* ((driver (driver-source name namespace :timed timed))
             (directory (merge-pathnames (format nil "~A/" (content-key header source driver *c++-flags*))
                                         (c++-cache-root))))
        ;; A private cache; the driver is verified against its digest before it runs.
        (call-with-cached-build
         directory
         (lambda (work)
           (handler-bind ((player-error
                            (lambda (e)
                              (declare (ignore e))
                              ;; Keep the sources that failed where the message says.
                              (write-build-files directory name header source driver))))
             (compile-c++ work (write-build-files work name header source driver) "driver"
                          :shown-directory directory))))))))

(defun compile-c++ (directory sources output &key (shown-directory directory))
  "Compile SOURCES in DIRECTORY into OUTPUT with *C++-FLAGS*; clear errors if
not, naming SHOWN-DIRECTORY as where the sources are."
  (multiple-value-bind (code out err)
      (run-program-capturing *c++-compiler* (append *c++-flags* sources (list "-o" output))
                             :directory (namestring directory))
    (declare (ignore out))
    (cond ((null code)
           (error 'player-error-with-message
                  :message (format nil "~A is not installed; install the Debian package g++"
                                   *c++-compiler*)))
          ((/= code 0)
           (error 'player-error-with-message
                  :message (format nil "g++ failed on the generated code in ~A: ~A"
                                   (namestring shown-directory)
                                   (truncate-text (substitute #\Space #\Newline err) 600)))))))

(defun initial-state-arguments (spec overrides)
  "OVERRIDES as the driver's arguments: their count, then each variable and its
value as Player prints them, values checked and canonical."
  (let ((pairs (loop for (var . value) in (initial-assignments spec overrides)
                     when (assoc (name-key (var-name var)) overrides
                                 :key #'name-key :test #'string=)
                       do (when (and (eq (var-kind var) :number) (eq (var-type var) :integer))
                            (check-c++-int64 spec var value "initial value"))
                       and collect (list (lisp-text (var-name var))
                                         (if (plannable-p var)
                                             (value-text var value)
                                             (let ((*read-default-float-format* 'double-float))
                                               (prin1-to-string value)))))))
    (cons (princ-to-string (length pairs)) (reduce #'append pairs :initial-value '()))))

(defun event-index (spec event)
  "The position of EVENT (a symbol or a name string) in SPEC's events; UNKNOWN-EVENT if none."
  (let ((key (if (stringp event) (string-upcase event) (name-key event))))
    (or (position key (spec-events spec) :key (lambda (e) (name-key (event-name e))) :test #'string=)
        (error 'unknown-event :name event :known (mapcar #'event-name (spec-events spec))))))

(defun split-at-nul (text)
  "The NUL-terminated lines of TEXT."
  (loop for start = 0 then (1+ end)
        for end = (position (code-char 0) text :start start)
        while end
        collect (subseq text start end)))

(defun seconds-argument (seconds)
  "SECONDS as the driver reads it: its whole microseconds (SECONDS-VALUE->MICROS)
as an exact decimal, which the driver reads exactly."
  (format-micros (seconds-value->micros seconds)))

(defun check-timed-scenario (events until)
  "Signal an ARGUMENT-ERROR of RUN-C++-TRACE unless EVENTS are scenario entries
(NAME or (NAME . SECONDS)) none of which arrives after UNTIL."
  (unless (every #'event-entry-p events)
    (argument-fail 'run-c++-trace :events events
                   "a list of event names and (NAME . SECONDS) conses, seconds from 0"))
  (when until
    (check-seconds 'run-c++-trace :until until)
    (dolist (entry events)
      (when (and (consp entry) (> (cdr entry) until))
        (argument-fail 'run-c++-trace :until until
                       (format nil "a time no earlier than the events' (~A arrives at ~A)"
                               (lisp-text (car entry)) (format-number (cdr entry))))))))

(defun scenario-arguments (spec events until when-busy)
  "A timed scenario as the timed driver's arguments: UNTIL (or -), WHEN-BUSY's
number (0 for none), then each entry as INDEX or INDEX@SECONDS."
  (list* (if until (seconds-argument until) "-")
         (if when-busy (princ-to-string (policy-number when-busy)) "0")
         (mapcar (lambda (entry)
                  (if (consp entry)
                      (format nil "~D@~A" (event-index spec (car entry)) (seconds-argument (cdr entry)))
                      (princ-to-string (event-index spec entry))))
                events)))

(defun run-c++-trace (machine &key initial-state events until when-busy)
  "Build MACHINE's C++ driver and run EVENTS from INITIAL-STATE (an alist);
return the trace as a list of lines.  Events are names (symbols or strings),
sent one after another as whole events.  A timed scenario -- an entry
(NAME . SECONDS), or UNTIL given -- plays on the timed layer as PLAY-EVENTS
does on (MAKE-CONTROLLER MACHINE :TIMED T): each NAME when the events before
it have ended, each (NAME . SECONDS) at that time whatever runs; then the clock
advances to UNTIL, or until no event runs or waits.  WHEN-BUSY (a policy
keyword), if given, overrides the policy of every timed entry, as PLAY-EVENTS'
does."
  (check-argument 'run-c++-trace 'events events #'proper-form-list-p "a list of event names")
  (let ((timed (timed-scenario-p events until))
        (when-busy (and when-busy
                        (or (and (symbolp when-busy) (when-busy-policy when-busy))
                            (argument-fail 'run-c++-trace :when-busy when-busy
                                           (format nil "one of ~{~A~^, ~}"
                                                   (mapcar #'lisp-text *when-busy-policies*)))))))
    (when timed (check-timed-scenario events until))
    (let* ((machine (ensure-machine machine 'run-c++-trace))
           (spec (machine-spec machine))
           (arguments (append (initial-state-arguments spec initial-state)
                              (if timed
                                  (scenario-arguments spec events until when-busy)
                                  (mapcar (lambda (event) (princ-to-string (event-index spec event))) events))))
           (executable (build-c++-driver machine :timed timed)))
      (multiple-value-bind (code out err) (run-program-capturing (namestring executable) arguments)
        (unless (eql code 0)
          (error 'player-error-with-message
                 :message (format nil "the generated C++ controller failed (exit ~A): ~A" code err)))
        (split-at-nul out)))))
