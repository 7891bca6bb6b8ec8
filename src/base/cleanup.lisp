;;;; cleanup.lisp -- what a command leaves behind when it is stopped: child
;;;; processes (g++, sox, ffmpeg, espeak) and temporary files and folders.  Each
;;;; is registered while it lives; unwinding removes it, and an interrupt
;;;; (SIGINT, SIGTERM) unwinds the command -- or, when the command cannot
;;;; unwind in time, kills the children, removes the files and exits at once.
;;;; The signal handlers only note the signal and interrupt the main thread:
;;;; they take no lock, so they cannot deadlock whatever the command is doing.

(in-package #:player.base)

(defvar *cleanups* '()
  "Temporary files and folders (pathnames or names) and child processes alive now.
Read without a lock by the emergency exit, which must never wait.")

(defvar *cleanups-lock* (sb-thread:make-mutex :name "player cleanups"))

(defun register-cleanup (thing)
  "Note THING (a temporary file or folder, or a child process) to remove on an interrupt."
  (sb-thread:with-mutex (*cleanups-lock*)
    (setf *cleanups* (cons thing *cleanups*)))
  thing)

(defun unregister-cleanup (thing)
  "THING is gone, or kept: forget it."
  (sb-thread:with-mutex (*cleanups-lock*)
    (setf *cleanups* (remove thing *cleanups* :test #'equal))))

(defun kill-child (process)
  "End PROCESS and its process group (a child's own children, as g++'s cc1plus):
TERM, then KILL when it has not gone within a fifth of a second."
  (when (sb-ext:process-alive-p process)
    (ignore-errors (sb-ext:process-kill process sb-unix:sigterm :process-group))
    (ignore-errors (sb-ext:process-kill process sb-unix:sigterm))
    (loop repeat 20 while (sb-ext:process-alive-p process) do (sleep 0.01))
    (when (sb-ext:process-alive-p process)
      (ignore-errors (sb-ext:process-kill process sb-unix:sigkill :process-group))
      (ignore-errors (sb-ext:process-kill process sb-unix:sigkill))))
  (ignore-errors (sb-ext:process-close process)))

(defun remove-leftover (thing)
  "Remove THING, a registered temporary file, folder or child process."
  (ignore-errors
   (cond ((sb-ext:process-p thing) (kill-child thing))
         ((and (pathnamep thing) (null (pathname-name thing)))
          (sb-ext:delete-directory thing :recursive t))
         ((stringp thing) (sb-posix:unlink thing)) ; a temporary's native name
         (t (sb-posix:unlink (os-file-name thing))))))

(defun run-child (program arguments &rest options)
  "Run PROGRAM with ARGUMENTS (OPTIONS as for SB-EXT:RUN-PROGRAM; standard input
defaults to none, so the child gets its own process group) and wait for it.
A non-local exit while it runs -- an interrupt, an error -- kills it and its
children.  Returns the finished process."
  (let ((process (apply #'sb-ext:run-program program arguments :wait nil
                        (append options (list :input nil))))
        (done nil))
    (register-cleanup process)
    (unwind-protect (progn (sb-ext:process-wait process) (setf done t) process)
      (unless done (kill-child process))
      (unregister-cleanup process))))

(defun run-child-output (program arguments &rest options)
  "Run PROGRAM as RUN-CHILD does, capturing its output and error text.  Returns
its exit code, standard output and standard error as strings."
  (let* ((out (make-string-output-stream))
         (err (make-string-output-stream))
         (process (apply #'run-child program arguments :output out :error err options)))
    (values (sb-ext:process-exit-code process)
            (get-output-stream-string out) (get-output-stream-string err))))

(defmacro with-work-folder ((folder parent &optional (prefix "player-work")) &body body)
  "Run BODY with FOLDER, a new private folder (mode 0700) in PARENT, removed
with everything in it when BODY ends, however it ends."
  `(let ((,folder (make-private-folder ,parent ,prefix)))
     (unwind-protect (progn ,@body) (remove-folder ,folder))))

;;;# Interrupts

(define-condition interrupted (serious-condition)
  ((signal-name :initarg :signal-name :reader interrupted-signal-name)
   (exit-code :initarg :exit-code :initform 130 :reader interrupted-exit-code
              :documentation "The status to exit with: 128 plus the signal's number."))
  (:report (lambda (condition stream)
             (format stream "interrupted (~A)" (interrupted-signal-name condition))))
  (:documentation "The command was stopped by SIGINT or SIGTERM.  Not an ERROR, so
no handler of errors swallows it (as SBCL's own INTERACTIVE-INTERRUPT)."))

(defvar *interrupt-count* 0 "How many stop signals have arrived.")

(defparameter *unwind-grace* 2
  "Seconds an interrupted command has to unwind before it is ended at once.")

(defun emergency-exit (code)
  "Kill every child, remove every temporary, and exit with CODE now, running nothing else."
  (mapc #'remove-leftover *cleanups*)
  (sb-ext:exit :code code :abort t))

(defun signal-exit-code (signal)
  "The exit status of a command ended by SIGNAL, as a shell reports it."
  (+ 128 signal))

(defun note-stop-signal (signal name main-thread)
  "A stop signal arrived: interrupt MAIN-THREAD to unwind with an INTERRUPTED
error; a second signal, or an unwind longer than *UNWIND-GRACE*, ends the
process at once."
  (when (> (incf *interrupt-count*) 1)
    (emergency-exit (signal-exit-code signal)))
  (sb-thread:make-thread (lambda () (sleep *unwind-grace*) (emergency-exit (signal-exit-code signal)))
                         :name "player stop watchdog")
  (ignore-errors
   (sb-thread:interrupt-thread main-thread
                               (lambda ()
                                 (sb-sys:with-interrupts
                                   (error 'interrupted :signal-name name
                                                             :exit-code (signal-exit-code signal)))))))

(defun stop-at-once (signal info context)
  "A stop signal before INSTALL-STOP-HANDLERS: nothing is running yet to unwind,
so exit 128 + SIGNAL now."
  (declare (ignore info context))
  (emergency-exit (signal-exit-code signal)))

(defun stop-at-once-from-start-up ()
  "Make a saved core's start-up install STOP-AT-ONCE for SIGINT and SIGTERM.
SBCL installs its own handlers while it starts, before any hook of ours can
run, and delivers a signal that arrived earlier right then: its SIGTERM
handler exits with status 0 and its SIGINT one prints a backtrace.  It installs
them by name, so naming ours instead covers every moment of the start."
  (sb-ext:without-package-locks
    (setf (fdefinition 'sb-unix::sigterm-handler) #'stop-at-once
          (fdefinition 'sb-unix::sigint-handler) #'stop-at-once)))

(defun install-stop-handlers ()
  "Make SIGINT and SIGTERM unwind the calling (main) thread as an INTERRUPTED
error, killing children and removing temporaries on the way out."
  (let ((main sb-thread:*current-thread*))
    (setf *interrupt-count* 0)
    (sb-sys:enable-interrupt sb-unix:sigint
                             (lambda (&rest ignore) (declare (ignore ignore))
                               (note-stop-signal sb-unix:sigint "SIGINT" main)))
    (sb-sys:enable-interrupt sb-unix:sigterm
                             (lambda (&rest ignore) (declare (ignore ignore))
                               (note-stop-signal sb-unix:sigterm "SIGTERM" main)))))
