;;;; main.lisp -- the entry point of bin/player.  Every error becomes one
;;;; "player: error: ..." line on stderr with exit status 1, or 2 for a wrong
;;;; command line; a closed output pipe ends the program quietly; never a
;;;; debugger or a backtrace.  Also the saved core bin/player starts from.

(in-package #:player.cli)

(defun storage-message (condition)
  "What ran out, for a STORAGE-CONDITION: the stack (input nested too deeply) or the heap."
  (if (typep condition 'sb-kernel::control-stack-exhausted)
      "the input is nested too deeply (the control stack is exhausted)"
      (memory-limit-message)))

(defun standard-output-error-p (condition)
  "Is CONDITION a failed write to standard output?"
  (and (typep condition 'stream-error)
       (member (stream-error-stream condition) (list *standard-output* sb-sys:*stdout*))))

(defun closed-pipe-p (condition)
  "Is CONDITION a write to an output whose reader has gone (`player ... | head`)?
A full disk under `player ... > file` is not: that is an error to report."
  (or (typep condition 'sb-int:broken-pipe)
      (and (standard-output-error-p condition)
           (equal (condition-reason condition) (errno-reason sb-posix:epipe)))))

(defun exit-with-error (status message)
  "Print MESSAGE as the one error line and exit with STATUS, flushing what was printed before."
  (ignore-errors (finish-output *standard-output*))
  (ignore-errors (format *error-output* "player: error: ~A~%" message)
                 (finish-output *error-output*))
  (sb-ext:exit :code status :abort t))

;;;# Library chatter

(defconstant +fd-cloexec+ 1 "FD_CLOEXEC: a file descriptor closed on exec (SB-POSIX lacks it).")

(defun private-copy (fd stream name)
  "An output stream like STREAM, named NAME, on a copy of FD that child processes do not inherit."
  (let ((copy (sb-posix:dup fd)))
    (sb-posix:fcntl copy sb-posix:f-setfd +fd-cloexec+)
    (sb-sys:make-fd-stream copy :output t :buffering :line :element-type :default
                                :external-format (stream-external-format stream)
                                :name name)))

(defun keep-library-chatter-out ()
  "C libraries print their own messages on file descriptors 1 and 2 (espeak-ng's
'Error processing file ...' when its data is missing, Mesa's warnings), and so
does SBCL's runtime.  Player's standard output and error move to private copies
of those, and 1 and 2 then lead to /dev/null: stdout holds only Player's output,
stderr at most its one error line.  Children Player runs capture their own."
  (finish-output sb-sys:*stdout*)
  (finish-output sb-sys:*stderr*)
  (let ((out (private-copy 1 sb-sys:*stdout* "standard output"))
        (err (private-copy 2 sb-sys:*stderr* "standard error"))
        (null (sb-posix:open "/dev/null" sb-posix:o-wronly)))
    (sb-posix:dup2 null 1)
    (sb-posix:dup2 null 2)
    (sb-posix:close null)
    ;; *STANDARD-OUTPUT* and *ERROR-OUTPUT* are synonyms of these two.
    (setf sb-sys:*stdout* out
          sb-sys:*stderr* err)))

(defun silence-error-output (condition)
  "An interrupted command says nothing on stderr, its exit status tells: what it
unwinds through (SBCL's compiler among them) may not print on the way out."
  (declare (ignore condition))
  (setf *error-output* (make-broadcast-stream)))

(defun main (&optional (arguments (rest sb-ext:*posix-argv*)))
  "Entry point of bin/player: run ARGUMENTS; exit 0 on success, 1 when the work
fails, 2 for a wrong command line, 141 (as if killed by SIGPIPE) when standard
output is closed early, 130 on SIGINT and 143 on SIGTERM."
  (handler-case
      (handler-bind ((interrupted #'silence-error-output))
        (restart-with-memory-option arguments)
        (start-progress-note arguments)  ; it asks whether descriptor 2 is a terminal
        (keep-library-chatter-out)
        (run-command-line arguments)
        (finish-output *standard-output*)
        (finish-output *error-output*)
        ;; Without unwinding: SBCL's orderly exit waits for threads, and a
        ;; stop signal landing there would find no handler.
        (dolist (hook sb-ext:*exit-hooks*) (ignore-errors (funcall hook)))
        (sb-ext:exit :code 0 :abort t))
    (usage-error (e) (exit-with-error 2 (condition-line e)))
    (sb-sys:interactive-interrupt () (sb-ext:exit :code 130 :abort t))
    ;; SIGINT or SIGTERM (INSTALL-STOP-HANDLERS): children and temporaries are gone by now.
    (interrupted (e) (ignore-errors (finish-output *standard-output*))
      (sb-ext:exit :code (interrupted-exit-code e) :abort t))
    (storage-condition (e) (exit-with-error 1 (storage-message e)))
    (error (e)
      (cond ((closed-pipe-p e) (sb-ext:exit :code 141 :abort t))
            ((standard-output-error-p e)
             (exit-with-error 1 (format nil "cannot write standard output: ~A" (condition-reason e))))
            (t (exit-with-error 1 (condition-line e)))))))

;;;# The saved core

(defun core-toplevel ()
  "The toplevel of the executable core bin/player builds: MAIN on the command line."
  ;; SIGINT and SIGTERM unwind the command (killing its children, removing its
  ;; temporaries) instead of SBCL's handlers, which can deadlock in EXIT (and
  ;; exit 0 on SIGTERM); before this, STOP-AT-ONCE-FROM-START-UP's handlers exit.
  (install-stop-handlers)
  (sb-ext:disable-debugger)
  (install-memory-guard)
  (setf *default-pathname-defaults* (uiop:getcwd))
  (main (rest sb-ext:*posix-argv*)))

(defun save-core (path)
  "Save this image, with Player loaded, as the executable PATH that starts in MAIN.
Does not return."
  ;; Runtime options are not saved: bin/player gives the heap's size
  ;; (--dynamic-space-size) when it starts the core, and --max-memory restarts it.
  (stop-at-once-from-start-up)
  (sb-ext:save-lisp-and-die path :executable t :toplevel #'core-toplevel))
