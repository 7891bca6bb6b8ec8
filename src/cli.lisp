;;;; cli.lisp -- the bin/player command line: run, plans and check.
;;;; Every error becomes one "player: error: ..." line on stderr with exit
;;;; status 1 (2 for usage mistakes); never a debugger or a backtrace.

(in-package #:player)

(define-condition usage-error (player-error)
  ((message :initarg :message :reader usage-error-message))
  (:report (lambda (condition stream) (write-string (usage-error-message condition) stream)))
  (:documentation "The command line itself is wrong."))

(defun usage-fail (control &rest arguments)
  "Signal a USAGE-ERROR with a formatted message."
  (error 'usage-error :message (apply #'format nil control arguments)))

(defparameter *usage*
  (format nil "usage: player COMMAND SPEC-FILE [OPTIONS]
commands:
  run SPEC-FILE [--spec NAME] [--initial var=value,...] [--events ev1,ev2,...] [--backend lisp|c++]
      play events in simulated time and print the trace
  emit-c++ SPEC-FILE [--spec NAME] --out DIR [--name NAME] [--namespace NS]
      write NAME.hpp and NAME.cpp, a standalone C++17 controller
  simulate SPEC-FILE [--spec NAME] [--initial ...] --events ev1,... [--fps 30] [--seed N]
           [--bvh FILE] [--frames FILE] [--scripts FILE] [--body NAME]
      play the events on the spec's body in simulated time; print the trace,
      write the motion as BVH and, with --frames, one s-expression per frame
~A
~A
  plans SPEC-FILE [--spec NAME]    print every goal's plan table
  check SPEC-FILE [--spec NAME]    print the spec's diagnostics
  help                             print this text" *render-usage* *view-usage*)
  "What `player help` prints.")

(defparameter *command-options*
  `(("run" "--spec" "--initial" "--events" "--backend")
    ("emit-c++" "--spec" "--out" "--name" "--namespace")
    ("simulate" "--spec" "--initial" "--events" "--fps" "--seed" "--bvh" "--frames"
     "--scripts" "--body")
    ,*render-command-options*
    ,*view-command-options*
    ("plans" "--spec")
    ("check" "--spec" "--scripts"))
  "Each command with the options it accepts (all take a value).")

(defun parse-command-line (arguments)
  "Split ARGUMENTS into (VALUES COMMAND FILE OPTIONS-ALIST)."
  (let* ((command (or (first arguments) (usage-fail "no command given~%~A" *usage*)))
         (allowed (or (rest (assoc command *command-options* :test #'string=))
                      (usage-fail "unknown command ~A~%~A" command *usage*)))
         (file nil)
         (options '()))
    (loop with rest = (rest arguments)
          while rest
          do (let ((argument (pop rest)))
               (cond ((member argument allowed :test #'string=)
                      (when (assoc argument options :test #'string=)
                        (usage-fail "option ~A given twice" argument))
                      (push (cons argument (or (pop rest) (usage-fail "option ~A needs a value" argument)))
                            options))
                     ((and (plusp (length argument)) (char= (char argument 0) #\-))
                      (usage-fail "unknown option ~A for ~A (allowed: ~{~A~^ ~})" argument command allowed))
                     (file (usage-fail "unexpected argument ~A" argument))
                     (t (setf file argument)))))
    (unless file (usage-fail "~A needs a SPEC-FILE" command))
    (values command file options)))

(defun option (name options)
  "The value of command-line option NAME, or NIL."
  (cdr (assoc name options :test #'string=)))

(defun split-list (string)
  "STRING split at commas, blanks trimmed, empty parts dropped."
  (loop for start = 0 then (1+ comma)
        for comma = (position #\, string :start start)
        for part = (string-trim " " (subseq string start comma))
        unless (string= part "") collect part
        while comma))

(defun read-cli-value (text)
  "The value TEXT denotes on the command line: a number, or a symbol in PLAYER-USER."
  (let ((*package* (find-package '#:player-user))
        (*read-eval* nil)
        (*read-default-float-format* 'double-float))
    (handler-case (multiple-value-bind (value end) (read-from-string text)
                    (if (= end (length text)) value (error "trailing text")))
      (error () (usage-fail "cannot read value ~S" text)))))

(defun parse-initial-option (text)
  "--initial var=value,... as an alist of symbols to values."
  (mapcar (lambda (part)
            (let ((equals (position #\= part)))
              (unless (and equals (plusp equals) (< equals (1- (length part))))
                (usage-fail "--initial takes var=value pairs, not ~S" part))
              (cons (intern (string-upcase (subseq part 0 equals)) '#:player-user)
                    (read-cli-value (subseq part (1+ equals))))))
          (split-list text)))

(defun choose-spec (file options)
  "Load FILE and return the spec to use: --spec NAME, or the file's only spec."
  (let ((specs (load-spec file))
        (name (option "--spec" options)))
    (cond (name (or (find (string-upcase name) specs :key (lambda (s) (name-key (spec-name s)))
                                                     :test #'string=)
                    (usage-fail "~A defines no spec ~A (it defines ~{~A~^, ~})"
                                file (string-downcase name)
                                (mapcar (lambda (s) (lisp-text (spec-name s))) specs))))
          ((null specs) (usage-fail "~A defines no spec" file))
          ((rest specs) (usage-fail "~A defines several specs (~{~A~^, ~}); choose one with --spec"
                                    file (mapcar (lambda (s) (lisp-text (spec-name s))) specs)))
          (t (first specs)))))

(defun command-run (spec options)
  "Play --events from --initial on SPEC with the --backend (lisp or c++), printing the trace."
  (let* ((backend (or (option "--backend" options) "lisp"))
         (machine (compile-spec spec))
         (initial (parse-initial-option (or (option "--initial" options) "")))
         (events (split-list (or (option "--events" options) "")))
         (controller (make-controller machine :initial-state initial
                                              :presenter (make-trace-presenter
                                                          :stream (and (string= backend "lisp")
                                                                       *standard-output*)))))
    (dolist (event events)
      (find-compiled-event controller event))
    (cond ((string= backend "lisp")
           (dolist (event events)
             (send-event controller event)))
          ((string= backend "c++")
           (format t "~{~A~%~}" (run-c++-trace machine :initial-state initial :events events)))
          (t (usage-fail "unknown backend ~A (expected lisp or c++)" backend)))))

(defun number-option (name options default &key (test #'realp) (what "a number"))
  "The value of option NAME read as a number passing TEST, or DEFAULT when absent."
  (let ((text (option name options)))
    (if text
        (let ((value (read-cli-value text)))
          (unless (funcall test value)
            (usage-fail "~A takes ~A, not ~A" name what text))
          value)
        default)))

(defun command-simulate (spec options)
  "Play --events on SPEC's body in simulated time: print the trace and what the
drivers reported, write --bvh and --frames."
  (let* ((simulation
           (simulate spec :initial (parse-initial-option (or (option "--initial" options) ""))
                          :events (split-list (or (option "--events" options) ""))
                          :fps (number-option "--fps" options 30
                                              :test (lambda (x) (and (realp x) (plusp x) (<= x 1000)))
                                              :what "a frame rate from 0 to 1000")
                          :seed (number-option "--seed" options 0 :test #'integerp :what "an integer")
                          :scripts (option "--scripts" options)
                          :body (let ((body (option "--body" options)))
                                  (and body (intern (string-upcase body) '#:player-user)))
                          :stream *standard-output*))
         (written (write-simulation simulation :bvh (option "--bvh" options)
                                               :frames (option "--frames" options))))
    (loop for (time text) in (simulation-reports simulation)
          do (format t "; ~A s: ~A~%" (format-number time) text))
    (format t "; ~D frames at ~A fps over ~A s~%" (simulation-frame-count simulation)
            (format-number (simulation-fps simulation)) (format-number (simulation-end simulation)))
    (dolist (path written)
      (format t "; wrote ~A~%" (namestring path)))))

(defun command-emit-c++ (spec options)
  "Write SPEC's C++ controller into --out."
  (let ((directory (or (option "--out" options) (usage-fail "emit-c++ needs --out DIR"))))
    (format t "~{~A~%~}"
            (mapcar #'namestring
                    (emit-c++ (compile-spec spec) directory
                              :name (option "--name" options)
                              :namespace (option "--namespace" options))))))

(defun command-plans (spec options)
  "Print every goal's plan table."
  (declare (ignore options))
  (let ((machine (compile-spec spec)))
    (format t "spec ~A: ~D goals, ~D states, max-depth ~D~%"
            (lisp-text (spec-name spec)) (length (machine-goal-table machine))
            (machine-state-count machine) (spec-max-depth spec))
    (loop for goal across (machine-goal-table machine)
          do (format t "~%goal ~D: ~A~%" (1+ (goal-id goal)) (lisp-text (goal-expression goal)))
             (format t "  requested as: ~{~A~^, ~}~%" (mapcar #'lisp-text (reverse (goal-forms goal))))
             (loop for (condition . ops) in (goal-plan-table goal spec)
                   for i from 1
                   do (format t "  ~3D. if ~A~%       run ~A~%" i (lisp-text condition)
                              (if ops (lisp-text ops) "nothing (already true)")))
             (let ((missing (- (machine-state-count machine) (goal-solved-count goal))))
               (when (plusp missing)
                 (format t "  unreachable from ~D of ~D states~%" missing
                         (machine-state-count machine)))))))

(defun command-check (spec options)
  "Print SPEC's diagnostics, and with a script library (its (:scripts FILE) or
--scripts) the scripts it lacks and the ops whose :duration disagrees with their script."
  (let ((diagnostics (append (check-spec spec) (script-diagnostics spec (option "--scripts" options)))))
    (if diagnostics
        (dolist (d diagnostics)
          (format t "warning: ~A~%" (diagnostic-message d)))
        (format t "~A: no problems found~%" (lisp-text (spec-name spec))))))

(defun run-command (arguments)
  "Run the command ARGUMENTS name."
  (when (member (first arguments) '("help" "--help" "-h") :test #'equal)
    (write-line *usage*)
    (return-from run-command))
  (multiple-value-bind (command file options) (parse-command-line arguments)
    (let ((spec (choose-spec file options)))
      (funcall (cond ((string= command "run") #'command-run)
                     ((string= command "emit-c++") #'command-emit-c++)
                     ((string= command "plans") #'command-plans)
                     ((string= command "simulate") #'command-simulate)
                     ((string= command "render") #'command-render)
                     ((string= command "view") #'command-view)
                     ((string= command "check") #'command-check))
               spec options))))

(defun one-line (condition)
  "CONDITION's report on one line."
  (substitute #\Space #\Newline (string-trim '(#\Space #\Newline) (princ-to-string condition))))

(defun main (&optional (arguments (rest sb-ext:*posix-argv*)))
  "Entry point of bin/player: run ARGUMENTS, exit 0 on success, 1 on an error, 2 on misuse."
  (flet ((fail (status condition)
           (finish-output *standard-output*)
           (format *error-output* "player: error: ~A~%" (if (typep condition 'usage-error)
                                                            (usage-error-message condition)
                                                            (one-line condition)))
           (finish-output *error-output*)
           (sb-ext:exit :code status :abort t)))
    (handler-case
        (progn (run-command arguments)
               (finish-output *standard-output*)
               (sb-ext:exit :code 0))
      (usage-error (e) (fail 2 e))
      (sb-sys:interactive-interrupt () (sb-ext:exit :code 130 :abort t))
      (error (e) (fail 1 e)))))
