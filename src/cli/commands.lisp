;;;; commands.lisp -- the one command table.  Each command is declared once,
;;;; with DEFINE-COMMAND: its name, a one-line summary, its arguments, its
;;;; options, where its output goes, and the function that does the work.
;;;; Parsing the command line, `player help`, `player help CMD` and
;;;; `player CMD --help` all read this table.

(in-package #:player.cli)

(defstruct (command (:constructor %make-command))
  "A command of bin/player: NAME, a one-line SUMMARY, a longer DESCRIPTION
(or NIL), the ARGUMENTS it takes (metavariables such as \"SPEC-FILE\"), its
OPTIONS (OPTION structs), where its OUTPUT goes, and the FUNCTION called with
the arguments, then the options as keywords."
  (name "" :type string)
  (summary "" :type string)
  (description nil)
  (arguments '() :type list)
  (options '() :type list)
  (output nil)
  (function nil))

(defvar *commands* '()
  "The commands, in the order help lists them.")

(defun register-command (command)
  "Add COMMAND to *COMMANDS*, replacing one of the same name in place."
  (let ((old (position (command-name command) *commands* :key #'command-name :test #'string=)))
    (if old
        (setf (nth old *commands*) command)
        (setf *commands* (append *commands* (list command))))
    command))

(defmacro define-command (name lambda-list (&key summary description arguments options output)
                          &body body)
  "Define the command NAME (a string): a function COMMAND-NAME of LAMBDA-LIST,
its required parameters the ARGUMENTS (metavariable strings), its keyword
parameters the OPTIONS (designators for RESOLVE-OPTION), and its entry in the
command table with SUMMARY, DESCRIPTION and OUTPUT for help."
  (let ((function (intern (format nil "COMMAND-~:@(~A~)" name))))
    `(progn
       (defun ,function ,lambda-list
         ,(format nil "The `player ~A` command: ~A." name summary)
         ,@body)
       (register-command
        (%make-command :name ,name :summary ,summary :description ,description
                       :arguments ',arguments :output ,output
                       :options (mapcar #'resolve-option ',options)
                       :function ',function)))))

(defun find-command (name)
  "The command NAME, or a USAGE-ERROR listing the commands."
  (or (find name *commands* :key #'command-name :test #'string=)
      (usage-fail "unknown command ~A (commands: ~{~A~^, ~}; see player help)"
                  name (mapcar #'command-name *commands*))))

;;;# Parsing a command line

(defun help-option-p (argument)
  "Is ARGUMENT a request for help?"
  (member argument '("--help" "-h") :test #'string=))

(defun find-command-option (command name)
  "COMMAND's option NAME, or a USAGE-ERROR listing the options it takes."
  (or (find name (command-options command) :key #'option-name :test #'string=)
      (usage-fail "unknown option ~A for ~A (it takes ~{~A~^, ~}; see player help ~A)"
                  name (command-name command) (mapcar #'option-name (command-options command))
                  (command-name command))))

(defun parse-command-arguments (command arguments)
  "ARGUMENTS (the words after COMMAND's name) as (VALUES POSITIONALS OPTIONS),
OPTIONS a plist of every option's keyword and value, defaults filled in.
--name value and --name=value both work.  Signals a USAGE-ERROR for anything
COMMAND does not take."
  (let ((positionals '()) (given '()))
    (loop while arguments
          do (let ((argument (pop arguments)))
               (if (and (> (length argument) 1) (char= (char argument 0) #\-))
                   (let* ((equals (position #\= argument))
                          (option (find-command-option command (subseq argument 0 equals)))
                          (name (option-name option)))
                     (when (assoc name given :test #'string=)
                       (usage-fail "option ~A given twice" name))
                     (push (cons name
                                 (cond ((eq (option-type option) :flag)
                                        (when equals (usage-fail "option ~A takes no value" name))
                                        t)
                                       (equals (read-option-value (option-type option)
                                                                  (subseq argument (1+ equals)) option))
                                       (arguments (read-option-value (option-type option) (pop arguments) option))
                                       (t (usage-fail "option ~A needs a value (~A)" name (option-metavar option)))))
                           given))
                   (push argument positionals))))
    (setf positionals (nreverse positionals))
    (let ((expected (command-arguments command)))
      (cond ((< (length positionals) (length expected))
             (usage-fail "~A needs ~{a ~A~^ and ~} (see player help ~A)" (command-name command)
                         (nthcdr (length positionals) expected) (command-name command)))
            ((> (length positionals) (length expected))
             (usage-fail "unexpected argument ~A for ~A" (nth (length expected) positionals)
                         (command-name command)))))
    (values positionals
            (loop for option in (command-options command)
                  for entry = (assoc (option-name option) given :test #'string=)
                  collect (option-keyword option)
                  collect (if entry (cdr entry) (option-default option))))))

(defun run-command-line (arguments)
  "Run the command ARGUMENTS name: `help [CMD]`, `CMD --help`, or a command
with its arguments and options.  --max-memory, which every command takes, is
read by MAIN before (see memory.lisp) and ignored here."
  (let* ((arguments (take-memory-option arguments))
         (name (first arguments)))
    (cond ((null name)
           (usage-fail "no command given (commands: ~{~A~^, ~}; see player help)"
                       (mapcar #'command-name *commands*)))
          ((or (string= name "help") (help-option-p name))
           (print-help (second arguments)))
          ((some #'help-option-p (rest arguments))
           (print-help (command-name (find-command name))))
          (t (let ((command (find-command name)))
               (multiple-value-bind (positionals options) (parse-command-arguments command (rest arguments))
                 (apply (command-function command) (append positionals options))))))))

;;;# What commands share

(defun choose-spec (file name &key (allow-code t))
  "Load the spec FILE (refusing :code and :c++ unless ALLOW-CODE) and return
the spec to use: the one called NAME (a string), or the file's only spec when
NAME is NIL.  A USAGE-ERROR when NAME is not there or the choice is ambiguous."
  (let ((specs (load-spec file :allow-code allow-code)))
    (flet ((names () (mapcar (lambda (s) (lisp-text (spec-name s))) specs)))
      (cond (name (or (find (string-upcase name) specs :key (lambda (s) (name-key (spec-name s)))
                                                       :test #'string=)
                      (usage-fail "~A defines no spec ~A (it defines ~{~A~^, ~})"
                                  file (string-downcase name) (names))))
            ((null specs) (error 'player-error-with-message
                                 :message (format nil "~A defines no spec" file)))
            ((rest specs) (usage-fail "~A defines several specs (~{~A~^, ~}); choose one with --spec"
                                      file (names)))
            (t (first specs))))))

(defun print-scenario-summary (simulation frame-count fps)
  "Print, as ; comment lines, what SIMULATION's drivers reported and its frames."
  (loop for (time text) in (simulation-reports simulation)
        do (format t "; ~A s: ~A~%" (format-number time) text))
  (format t "; ~D frames at ~A fps over ~A s~%" frame-count (format-number fps)
          (format-number (simulation-end simulation))))
