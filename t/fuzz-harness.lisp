;;;; fuzz-harness.lisp -- running one fuzz case, protected: the run's
;;;; directories and marker file, the registry and side-effect checks, runs
;;;; and their summaries (see fuzz.lisp).

(in-package #:player-tests)

;;; ---------------------------------------------------------------------------
;;; The run: a temporary directory, the marker file, the emit directory

(defstruct (fz-run (:conc-name fzrun-))
  "Where one fuzzing run writes: DIRECTORY holds the case files and the
companion files; EMIT the directory given to EMIT-C++; MARKER the file the
payloads would create."
  directory emit marker
  (expected '())                        ; namestrings of the files that belong in DIRECTORY
  (symbols nil)                         ; PLAYER-USER's symbols when the run began
  (cwd-files '())                       ; the working directory's files when the run began
  (timeout 10)
  (patience nil)                        ; seconds of silence before a child counts as hung (default from TIMEOUT)
  (emit-every 5)                        ; emit C++ for every Nth case (and every hostile rename)
  (play-every 10)                       ; play every Nth accepted library on a body
  (emit-hook nil))                      ; called with the case and the emitted files, before they go

(defvar *fz-run-counter* 0)

(defun fz-open-run (&key (timeout 10) (emit-every 5) (play-every 10))
  "A fresh run directory under /tmp with the companion files copied in."
  (let* ((directory (pathname (format nil "/tmp/player-fuzz-~D-~D-~D/" (sb-posix:getpid)
                                      (get-universal-time) (incf *fz-run-counter*))))
         (run (make-fz-run :directory directory :emit (merge-pathnames "emit/" directory)
                           :marker (merge-pathnames "marker" directory) :timeout timeout
                           :emit-every emit-every :play-every play-every)))
    (ensure-directories-exist (fzrun-emit run))
    (dolist (path *fz-companion-files*)
      (let ((to (merge-pathnames (file-namestring path) directory)))
        (alexandria:copy-file (checkout-file path) to)
        (push (namestring to) (fzrun-expected run))))
    (setf (fzrun-symbols run) (fz-package-symbols)
          (fzrun-cwd-files run) (mapcar #'namestring (directory (merge-pathnames "*.*" *default-pathname-defaults*)
                                                                :resolve-symlinks nil)))
    run))

(defun fz-close-run (run)
  "Delete RUN's directory."
  (uiop:delete-directory-tree (fzrun-directory run) :validate (lambda (p) (search "/tmp/player-fuzz-" (namestring p)))
                                                     :if-does-not-exist :ignore))

(defun fz-package-symbols ()
  "The symbols present in PLAYER-USER, as an EQ set."
  (let ((set (make-hash-table :test 'eq)) (package (find-package '#:player-user)))
    (do-symbols (symbol package)
      (when (eq (symbol-package symbol) package) (setf (gethash symbol set) t)))
    set))

(defun fz-forget-new-symbols (run)
  "Unintern the symbols cases interned in PLAYER-USER since RUN began, so a
long run does not grow without bound."
  (let ((package (find-package '#:player-user)) (new '()) (old (fzrun-symbols run)))
    (do-symbols (symbol package)
      (when (and (eq (symbol-package symbol) package) (not (gethash symbol old)))
        (push symbol new)))
    (dolist (symbol new) (unintern symbol package))))

(defun fz-case-file (case run)
  "Where CASE's file goes in RUN."
  (merge-pathnames (if (eq (fzc-target case) :spec) "fuzz-case.lisp" "fuzz-library.lisp")
                   (fzrun-directory run)))

(defun fz-case-file-text (case run)
  "CASE's text with the marker file's name filled in."
  (fz-replace-all (fzc-text case) *fz-marker-placeholder* (namestring (fzrun-marker run))))

(defun fz-write-case-file (text path)
  "Write TEXT to PATH as UTF-8, each raw-byte stand-in as its byte."
  (with-open-file (out path :direction :output :if-exists :supersede :element-type '(unsigned-byte 8))
    (let ((start 0))
      (flet ((flush (end)
               (when (< start end)
                 (write-sequence (sb-ext:string-to-octets text :external-format :utf-8 :start start :end end) out))))
        (loop for i from 0 below (length text)
              for code = (char-code (char text i))
              when (<= #xE000 code #xE0FF)
                do (flush i) (write-byte (- code #xE000) out) (setf start (1+ i)))
        (flush (length text)))))
  path)

;;; ---------------------------------------------------------------------------
;;; Child processes (the command line and g++ run as these)

(defun fz-make-directory (prefix)
  "A fresh directory /tmp/PREFIX-PID-N/."
  (let ((directory (pathname (format nil "/tmp/~A-~D-~D-~D/" prefix (sb-posix:getpid)
                                     (get-universal-time) (incf *fz-run-counter*)))))
    (ensure-directories-exist directory)
    directory))

(defun fz-delete-tree (directory)
  "Delete DIRECTORY, one of ours under /tmp."
  (uiop:delete-directory-tree directory :validate (lambda (p) (search "/tmp/player-fuzz" (namestring p)))
                                        :if-does-not-exist :ignore))

(defparameter *fz-build-line* "player: building Player once"
  "The line bin/player prints on stderr while it builds its core (allowed).")

(defun fz-file-text (path &optional (limit 20000))
  "The first LIMIT characters of the file PATH (bytes that are not UTF-8 replaced), or \"\"."
  (or (ignore-errors
       (with-open-file (in path :external-format '(:utf-8 :replacement #\?))
         (let* ((buffer (make-string limit))
                (end (read-sequence buffer in)))
           (subseq buffer 0 end))))
      ""))

(defun fz-run-process (program arguments directory timeout)
  "Run PROGRAM with ARGUMENTS in DIRECTORY, its output and error output into
files there. Returns (VALUES EXIT-CODE STDOUT STDERR STATUS), EXIT-CODE :TIMEOUT when
it was still running after TIMEOUT seconds (then it is killed); STATUS is
:EXITED, :SIGNALED (EXIT-CODE is then the signal's number) or :TIMEOUT."
  (let* ((out (merge-pathnames "stdout.txt" directory))
         (err (merge-pathnames "stderr.txt" directory))
         (process (sb-ext:run-program program arguments :search nil :wait nil :input nil
                                      :output out :if-output-exists :supersede
                                      :error err :if-error-exists :supersede
                                      :directory (namestring directory)))
         (deadline (+ (get-internal-real-time) (* timeout internal-time-units-per-second))))
    (loop while (and (eq (sb-ext:process-status process) :running)
                     (< (get-internal-real-time) deadline))
          do (sleep 0.005))
    (let* ((status (if (eq (sb-ext:process-status process) :running)
                       (progn (sb-ext:process-kill process 9)
                              (sb-ext:process-wait process)
                              :timeout)
                       (sb-ext:process-status process)))
           (code (if (eq status :timeout) :timeout (sb-ext:process-exit-code process))))
      (sb-ext:process-close process)
      (multiple-value-prog1 (values code (fz-file-text out) (fz-file-text err) status)
        (ignore-errors (delete-file out))
        (ignore-errors (delete-file err))))))

;;; ---------------------------------------------------------------------------
;;; Running one case, protected

(defvar *fz-phase* nil "What the case is doing: :load, :compile, :send-event...")
(defvar *fz-warnings* 0 "Warnings signalled during the case.")
(defvar *fz-violations* nil "Side effects found during the case.")

(defun fz-protected (thunk timeout)
  "Call THUNK with the debugger and the terminal out of reach and a time limit.
Returns (VALUES OUTCOME CONDITION): :OK and THUNK's value, :PLAYER-ERROR,
:ESCAPED (any other serious condition, or any condition given to ERROR that
nobody handled) or :TIMEOUT."
  (let ((tag (list :fz-escape))
        (null-output (make-broadcast-stream)))
    (catch tag
      (flet ((escape (condition hook)
               (declare (ignore hook))
               (throw tag (values :escaped condition))))
        (handler-case
            (let ((*debugger-hook* #'escape)
                  (sb-ext:*invoke-debugger-hook* #'escape)
                  (*standard-output* null-output) (*error-output* null-output) (*trace-output* null-output)
                  (*standard-input* (make-string-input-stream ""))
                  (*terminal-io* (make-two-way-stream (make-string-input-stream "") null-output))
                  (*query-io* (make-two-way-stream (make-string-input-stream "") null-output))
                  (*debug-io* (make-two-way-stream (make-string-input-stream "") null-output))
                  (*print-readably* nil) (*print-circle* nil) (*print-length* nil) (*print-level* nil))
              (handler-bind ((warning (lambda (w)
                                        (incf *fz-warnings*)
                                        (let ((restart (find-restart 'muffle-warning w)))
                                          (when restart (invoke-restart restart))))))
                (sb-ext:with-timeout timeout
                  (values :ok (funcall thunk)))))
          (sb-ext:timeout (c) (values :timeout c))
          (player-error (c) (values :player-error c))
          (serious-condition (c) (values :escaped c)))))))

(defun fz-condition-message (condition timeout)
  "CONDITION's report as one string; (VALUES NIL ESCAPE) when printing the
report itself escapes or hangs."
  (multiple-value-bind (outcome value) (fz-protected (lambda () (princ-to-string condition)) timeout)
    (if (eq outcome :ok)
        value
        (values nil value outcome))))

(defun fz-events-to-send (machine prng)
  "MACHINE's events in order (the first 16), then two more chosen by PRNG:
deleting one event from a spec leaves the others sent as before."
  (let ((names (event-names machine)))
    (when names
      (append (subseq names 0 (min 16 (length names)))
              (loop repeat 2 collect (fz-pick prng names))))))

(defun fz-play-timed (machine prng)
  "Play MACHINE's events on a timed controller (null presenter), each arriving
a random eighth-second multiple after the one before, most while another
plays, under a random :when-busy policy; then advance a minute (its timers
and triggers go off).  The timeline's engine runs without type checks, so a
hostile spec that loads must not reach it with anything it cannot take."
  (let ((controller (make-controller machine :timed t :presenter (make-null-presenter)))
        (time 0))
    (dolist (event (fz-events-to-send machine prng))
      (incf time (/ (fz-below prng 12) 8))
      (send-event controller event :at time :when-busy (fz-pick prng *when-busy-policies*)))
    (advance controller (+ time 60))))

(defun fz-emit-p (case run)
  "Does CASE get emitted as C++? Every EMIT-EVERYth case, and every case with a hostile rename."
  (and (fzrun-emit-every run)
       (or (zerop (mod (fzc-index case) (fzrun-emit-every run)))
           (intersection (fzc-kinds case) '(:rename-c++ :collide :c++-token :rename-unicode :unicode-token)))))

(defun fz-run-spec (case run file prng)
  "The body of a spec case: load, then compile, control, check and emit every spec it defines."
  (setf *fz-phase* :load)
  (let ((specs (ecase (fzc-mode case)
                 ((:text :form-file) (load-spec file))
                 (:memory (let ((forms (fzc-forms case)))
                            (list (define-spec (if (consp forms) (car forms) forms)
                                               (if (consp forms) (cdr forms) nil)
                                               :package (find-package '#:player-user))))))))
    (setf *fz-phase* :returned-specs)
    (unless (listp specs) (error "load-spec returned ~S, not a list" (type-of specs)))
    (loop for spec in specs
          repeat 3
          do (setf *fz-phase* :compile)
             (let ((machine (compile-spec spec)))
               (setf *fz-phase* :make-controller)
               (let ((controller (make-controller machine :presenter (make-null-presenter))))
                 (setf *fz-phase* :send-event)
                 (dolist (event (fz-events-to-send machine prng))
                   (send-event controller event)))
               (setf *fz-phase* :timed)
               (fz-play-timed machine prng)
               (setf *fz-phase* :check-spec)
               (check-spec machine)
               (when (fz-emit-p case run)
                 (setf *fz-phase* :emit-c++)
                 (fz-emit case run machine))))
    :accepted))

(defun fz-emit (case run machine)
  "Emit MACHINE as C++ into RUN's emit directory; record a violation for a file
written anywhere else, then empty the directory."
  (let* ((emit (fzrun-emit run))
         (paths (emit-c++ machine emit))
         (inside (namestring (truename emit))))
    (dolist (path paths)
      (let ((true (probe-file path)))
        (unless (and true (eql 0 (search inside (namestring true))))
          (push (format nil "emit-c++ wrote outside its directory: ~A" (fz-visible (namestring path)))
                *fz-violations*))))
    (when (fzrun-emit-hook run)
      (funcall (fzrun-emit-hook run) case (directory (merge-pathnames "*.*" emit))))
    (dolist (path (directory (merge-pathnames "*.*" emit)))
      (delete-file path))))

(defvar *fz-companion-specs* (make-hash-table :test 'equal)
  "The spec objects of the library bases' specs, parsed once (not registered).")

(defun fz-companion-spec (name)
  "The spec object of spec base NAME (e.g. \"peedy\"), parsed once and not left in the registry."
  (or (gethash name *fz-companion-specs*)
      (setf (gethash name *fz-companion-specs*)
            (let* ((base (fz-base name))
                   (form (find-if #'fz-defspec-form-p (fzb-forms base))))
              (prog1 (define-spec (second form) (cddr form) :package (find-package '#:player-user)
                                                             :source-file (checkout-file (second (assoc name *fz-spec-files* :test #'string=))))
                (remove-spec (second form)))))))

(defun fz-run-library (case run file prng)
  "The body of a library case: load it, check its spec's scripts against it, and sometimes play it."
  (setf *fz-phase* :load)
  (let ((library (ecase (fzc-mode case)
                   ((:text :form-file) (load-script-library file))
                   (:memory (player.performance::parse-script-library-forms (fzc-forms case) :source (fz-case-file case run))))))
    (when (fzc-companion case)
      (let ((spec (fz-companion-spec (fzc-companion case))))
        (setf *fz-phase* :check-scripts)
        (player.performance::check-spec-scripts spec library)
        (when (and (fzrun-play-every run) (zerop (mod (fzc-index case) (fzrun-play-every run))))
          (setf *fz-phase* :play)
          (let* ((presenter (make-body-presenter spec :scripts library))
                 (machine (compile-spec spec))
                 (controller (make-controller machine :presenter presenter)))
            (dolist (event (fz-events-to-send machine prng))
              (send-event controller event))
            (dolist (time '(0 0.5 2.5))
              (performance-frame (presenter-performance presenter) time))))))
    :accepted))

;;; The registry

(defun fz-registry ()
  "The registered specs, as a list of spec objects."
  (loop for name in (list-specs) for spec = (find-spec name nil) when spec collect spec))

(defun fz-restore-registry (before case file)
  "Check the registry against BEFORE (a list of spec objects): new specs must
come from CASE's FILE (or, in memory mode, be its spec). Remove them and put
back any spec they replaced; return the violations."
  (let* ((after (fz-registry))
         (file-name (and file (probe-file file) (namestring (truename file))))
         (memory-name (and (eq (fzc-mode case) :memory) (consp (fzc-forms case)) (car (fzc-forms case))))
         (violations '()))
    (dolist (spec after)
      (unless (member spec before)
        (let ((source (ignore-errors (spec-source-file spec))))
          (unless (or (and file-name source (ignore-errors (equal (namestring (truename source)) file-name)))
                      (and memory-name (symbolp memory-name)
                           (string-equal (symbol-name memory-name) (symbol-name (spec-name spec)))))
            (push (format nil "registry gained a spec the case did not define: ~A"
                          (fz-bounded-text (spec-name spec) :limit 80))
                  violations)))
        (remove-spec (spec-name spec))))
    (let ((table (symbol-value (find-symbol "*SPECS*" '#:player.spec)))
          (key (fdefinition (find-symbol "NAME-KEY" '#:player.spec))))
      (dolist (spec before)
        (unless (eq (find-spec (spec-name spec) nil) spec)
          (unless (find (spec-name spec) after :key #'spec-name :test #'string-equal)
            (push (format nil "spec disappeared from the registry: ~A" (fz-bounded-text (spec-name spec) :limit 80))
                  violations))
          (setf (gethash (funcall key (spec-name spec)) table) spec))))
    violations))

;;; Side effects

(defparameter *fz-payload-symbols* '("*FUZZ-PAYLOAD-VAR*" "FUZZ-PAYLOAD-FN" "FUZZ-PAYLOAD-MACRO")
  "The PLAYER-USER symbols the payloads set or define.")

(defun fz-side-effects (run case)
  "The side effects the case left: the marker file, payload symbols, a payload
package, files in the run directory that do not belong there. Each is undone."
  (let ((violations '()))
    (when (probe-file (fzrun-marker run))
      (push "marker file created: a payload ran" violations)
      (delete-file (fzrun-marker run)))
    (dolist (name *fz-payload-symbols*)
      (let ((symbol (find-symbol name '#:player-user)))
        (when symbol
          (when (boundp symbol)
            (push (format nil "payload symbol set: player-user::~A" name) violations)
            (makunbound symbol))
          (when (fboundp symbol)
            (push (format nil "payload function defined: player-user::~A" name) violations)
            (fmakunbound symbol)))))
    (let ((package (find-package "PLAYER-FUZZ-PAYLOAD-PACKAGE")))
      (when package
        (push "payload package defined: player-fuzz-payload-package" violations)
        (delete-package package)))
    (let ((allowed (list* (namestring (fz-case-file case run)) (fzrun-expected run))))
      (dolist (path (directory (merge-pathnames "**/*.*" (fzrun-directory run)) :resolve-symlinks nil))
        (when (and (pathname-name path) (not (member (namestring path) allowed :test #'string=)))
          (push (format nil "file outside the emit directory: ~A" (fz-visible (namestring path))) violations)
          (ignore-errors (delete-file path)))))
    ;; Relative names land in the working directory: look there for what a
    ;; payload or a code generator would leave (not for other people's files).
    (dolist (path (directory (merge-pathnames "*.*" *default-pathname-defaults*) :resolve-symlinks nil))
      (when (and (pathname-name path)
                 (not (member (namestring path) (fzrun-cwd-files run) :test #'string=))
                 (or (member (pathname-type path) '("hpp" "cpp" "h") :test #'equal)
                     (search "fuzz" (namestring path)) (search "marker" (file-namestring path))))
        (push (namestring path) (fzrun-cwd-files run))          ; reported once
        (push (format nil "file in the working directory: ~A" (fz-visible (namestring path))) violations)))
    violations))

(defun fz-new-result (case run)
  "A FZ-RESULT describing CASE, its outcome not yet known."
  (let ((text (and (fzc-text case) (fz-case-file-text case run))))
    (make-fz-result :seed (fzc-seed case) :index (fzc-index case) :target (fzc-target case)
                    :mode (fzc-mode case) :base (fzc-base case) :kinds (fzc-kinds case)
                    :notes (fzc-notes case) :size (if text (length text) 0)
                    :excerpt (if text
                                 (fz-excerpt text (fzc-base-text case))
                                 (fz-bounded-text (fzc-forms case) :length 12 :level 5 :limit 400)))))

(defun fz-execute (case run)
  "Run CASE in RUN and return its FZ-RESULT."
  (let* ((file (and (member (fzc-mode case) '(:text :form-file)) (fz-case-file case run)))
         (text (and file (fz-case-file-text case run)))
         (prng (make-fz-prng (fzc-seed case) (fzc-index case) #x72756E))
         (before (fz-registry))
         (start (get-internal-real-time))
         (*fz-phase* :write)
         (*fz-warnings* 0)
         (*fz-violations* '())
         (result (fz-new-result case run)))
    (when file (fz-write-case-file text file))
    (multiple-value-bind (outcome condition)
        (fz-protected (lambda ()
                        (if (eq (fzc-target case) :spec)
                            (fz-run-spec case run file prng)
                            (fz-run-library case run file prng)))
                      (fzrun-timeout run))
      (setf (fzr-phase result) *fz-phase*)
      (ecase outcome
        (:ok (setf (fzr-outcome result) :accepted))
        ((:player-error :escaped :timeout)
         (setf (fzr-outcome result) outcome
               (fzr-condition result) condition
               (fzr-condition-type result) (type-of condition))
         (multiple-value-bind (message escape escape-outcome) (fz-condition-message condition (fzrun-timeout run))
           (if message
               (setf (fzr-message result) (fz-clip message 300))
               ;; Reporting the condition failed: that is the escape.
               (setf (fzr-outcome result) (if (eq escape-outcome :timeout) :timeout :escaped)
                     (fzr-phase result) :report
                     (fzr-condition-type result) (type-of escape)
                     (fzr-message result) (format nil "printing the ~A report: ~A" (type-of condition)
                                                  (fz-clip (ignore-errors (princ-to-string escape)) 200))))))))
    (setf (fzr-violations result)
          (append (reverse *fz-violations*)
                  (fz-side-effects run case)
                  (fz-restore-registry before case file)))
    (setf (fzr-warnings result) *fz-warnings*
          (fzr-seconds result) (/ (- (get-internal-real-time) start) internal-time-units-per-second))
    (fz-forget-new-symbols run)
    (when file (ignore-errors (delete-file file)))
    result))

;;; ---------------------------------------------------------------------------
;;; Runs and summaries

(defstruct (fz-summary (:conc-name fzs-))
  "The results of a run: FAILURES holds every failed FZ-RESULT; the rest are counted."
  seed (cases 0) (seconds 0)
  (outcomes (make-hash-table :test 'equal))     ; outcome label -> count
  (kinds (make-hash-table :test 'eq))           ; kind -> #(cases accepted player-error failed)
  (failures '())
  (slowest '()))                                ; the five slowest results

(defun fz-outcome-label (result)
  "RESULT's outcome as a table row label."
  (ecase (fzr-outcome result)
    (:accepted "accepted")
    (:player-error (format nil "player-error ~A" (fz-type-name (fzr-condition-type result))))
    (:escaped (format nil "ESCAPED ~A" (fz-type-name (fzr-condition-type result))))
    (:timeout "TIMEOUT")
    (:crashed (format nil "CRASHED ~A" (fzr-condition-type result)))
    (:hung "HUNG (the process stopped answering)")))

(defun fz-type-name (type)
  "TYPE (a symbol) with its package unless it is Player's (any layer's) or CL's."
  (if (and (symbolp type) (or (eq (symbol-package type) (find-package '#:cl))
                              (eql 0 (search "PLAYER" (package-name (symbol-package type))))))
      (symbol-name type)
      (let ((*package* (find-package '#:keyword))) (prin1-to-string type))))

(defun fz-summarize (summary result)
  "Count RESULT into SUMMARY."
  (incf (fzs-cases summary))
  (incf (gethash (fz-outcome-label result) (fzs-outcomes summary) 0))
  (when (fzr-violations result)
    (incf (gethash "SIDE EFFECT" (fzs-outcomes summary) 0)))
  (dolist (kind (remove-duplicates (fzr-kinds result)))
    (let ((row (or (gethash kind (fzs-kinds summary))
                   (setf (gethash kind (fzs-kinds summary)) (make-array 4 :initial-element 0)))))
      (incf (aref row 0))
      (incf (aref row (cond ((fzr-failed-p result) 3) ((eq (fzr-outcome result) :accepted) 1) (t 2))))))
  (when (fzr-failed-p result)
    (push result (fzs-failures summary)))
  (let* ((all (cons result (fzs-slowest summary)))
         (count (min 5 (length all))))
    (setf (fzs-slowest summary) (subseq (sort all #'> :key #'fzr-seconds) 0 count))))

(defun fz-prepare ()
  "Read the bases and parse the library bases' specs, once, outside any case."
  (fz-bases)
  (dolist (entry *fz-library-files*) (fz-companion-spec (third entry))))

(defun fuzz-run (&key (seed 1) (cases 2000) (start 0) (timeout 10) (emit-every 5) (play-every 10)
                      emit-hook progress (isolate t))
  "Generate and run CASES cases of SEED (numbered from START) and return a FZ-SUMMARY.
With ISOLATE (the default) the cases run in forked child processes, so a case
that kills SBCL is reported and the run goes on. PROGRESS, a stream, gets a dot
every 1,000 cases."
  (fz-prepare)
  (let ((run (fz-open-run :timeout timeout :emit-every emit-every :play-every play-every))
        (summary (make-fz-summary :seed seed))
        (begin (get-internal-real-time)))
    (setf (fzrun-emit-hook run) emit-hook)
    (flet ((record (result)
             (fz-summarize summary result)
             (when (and progress (zerop (mod (1+ (fzr-index result)) 1000)))
               (format progress ".~:[~;~%~]" (zerop (mod (1+ (fzr-index result)) 50000)))
               (force-output progress))))
      (unwind-protect
           (if isolate
               (fz-run-forked run (lambda (index) (fz-generate seed index)) start (+ start cases) #'record)
               (loop for index from start below (+ start cases)
                     do (record (fz-execute (fz-generate seed index) run))))
        (fz-close-run run)))
    (setf (fzs-seconds summary) (/ (- (get-internal-real-time) begin) internal-time-units-per-second))
    summary))

(defun fuzz-case (seed index &key (timeout 10) keep-file (emit t) (play t) in-process)
  "Replay case INDEX of SEED in a fresh run directory and return its FZ-RESULT
(outcome, condition type, phase, message, violations). The case runs in a
forked child, as in FUZZ-RUN, unless IN-PROCESS: then it runs in this image and
FZR-CONDITION holds the condition itself (but a case that kills SBCL kills this
image too). With KEEP-FILE the case's file is also written to
/tmp/player-fuzz-SEED-INDEX.lisp, whose name is the second value."
  (fz-prepare)
  (let ((run (fz-open-run :timeout timeout :emit-every (and emit 1) :play-every (and play 1)))
        (case (fz-generate seed index))
        (result nil))
    (unwind-protect
         (progn
           (if in-process
               (setf result (fz-execute case run))
               (fz-run-forked run (lambda (i) (fz-generate seed i)) index (1+ index) (lambda (r) (setf result r))))
           (values result
                   (when (and keep-file (fzc-text case))
                     (fz-write-case-file (fz-case-file-text case run)
                                         (format nil "/tmp/player-fuzz-~D-~D.lisp" seed index)))))
      (fz-close-run run))))
