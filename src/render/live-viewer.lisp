;;;; live-viewer.lisp -- the viewer as an authoring environment: its controller
;;;; follows its spec, so a DEFSPEC evaluated at the REPL (or over Swank) or,
;;;; with --watch, a saved spec file or script library changes the character
;;;; as it plays.  Redefinitions reach the viewer's thread through its INBOX
;;;; and happen between frames, at the controller's next safe point; an error
;;;; is printed and shown in the title while the window plays on.

(in-package #:player.render)

(defun report-live-error (viewer condition)
  "Print CONDITION as a \"player: error: ...\" line and show it in VIEWER's title."
  (setf (viewer-message viewer) (truncate-text (format nil "error: ~A" (print-live-error condition)) 100)))

(defun call-with-live-errors-reported (viewer function)
  "Call FUNCTION; a REDEFINITION-WARNING it signals is reported for VIEWER and muffled."
  (handler-bind ((redefinition-warning
                   (lambda (warning)
                     (report-live-error viewer (redefinition-warning-error warning))
                     (muffle-warning warning))))
    (funcall function)))

(defun redefine-viewed (viewer machine)
  "Switch VIEWER's controller to MACHINE, a new definition of its spec, once
the body can play every script the new spec needs; report why not otherwise."
  (let* ((controller (viewer-controller viewer))
         (performance (presenter-performance (controller-presenter controller))))
    (handler-case
        (progn
          (checked-script-library (machine-spec machine) performance (performance-library performance))
          (when (eq (redefine-controller controller machine) :pending)
            (write-live-line *standard-output* "; ~A redefined: it switches when the running event ends~%"
                             (viewer-name viewer))))
      (player-error (e) (report-live-error viewer e)))))

(defun follow-in-viewer (viewer)
  "Make VIEWER's controller follow its spec, new machines handed over through VIEWER's inbox."
  (let ((inbox (viewer-inbox viewer)))
    (follow-spec (viewer-controller viewer)
                 :deliver (lambda (controller machine)
                            (declare (ignore controller))
                            (inbox-post inbox (lambda (viewer) (redefine-viewed viewer machine)))))))

(defun note-spec-switch (viewer)
  "When VIEWER's controller now runs another spec than the one last shown,
say so, clear the error in the title and print the new key map."
  (let ((spec (spec-of (viewer-controller viewer))))
    (unless (or (null (viewer-spec viewer)) (eq spec (viewer-spec viewer)))
      (setf (viewer-spec viewer) spec
            (viewer-message viewer) nil
            (viewer-keys viewer) (view-event-keys spec))
      (write-live-line *standard-output* "; now playing the new definition of ~A (from ~A s)~%"
                       (lisp-text (spec-name spec)) (format-number (controller-time (viewer-controller viewer))))
      (print-key-map (viewer-keys viewer) (viewer-terminal viewer)))))

(defun reload-watched (viewer changed spec-file allow-code)
  "Read again the files in CHANGED: the script library first (a new spec may
need its new scripts), then SPEC-FILE (with ALLOW-CODE), whose DEFSPEC
reaches VIEWER's controller as any redefinition does.  Errors are reported."
  (let ((presenter (controller-presenter (viewer-controller viewer))))
    (dolist (path changed)
      (unless (equal path spec-file)
        (handler-case
            (progn (reload-script-library presenter (spec-of (viewer-controller viewer)) path)
                   (setf (viewer-message viewer) nil)
                   (write-live-line *standard-output* "; read the script library ~A again~%" (file-namestring path)))
          (player-error (e) (report-live-error viewer e)))))
    (when (member spec-file changed :test #'equal)
      (handler-case
          (let ((name (name-key (spec-name (spec-of (viewer-controller viewer))))))
            (write-live-line *standard-output* "; read ~A again~%" (file-namestring spec-file))
            (unless (find name (load-spec spec-file :allow-code allow-code)
                          :key (lambda (spec) (name-key (spec-name spec))) :test #'equal)
              (error 'player-error-with-message
                     :message (format nil "~A no longer defines spec ~A" (file-namestring spec-file)
                                      (viewer-name viewer)))))
        (player-error (e) (report-live-error viewer e))))
    (finish-output)))

(defun start-live-viewer (viewer &key inbox watch (allow-code t))
  "Make VIEWER live: its controller follows its spec through INBOX (a new one
if NIL), and with WATCH its spec's file and script library are read again
when they change (the spec file with ALLOW-CODE)."
  (let* ((controller (viewer-controller viewer))
         (spec-file (and watch (spec-source-file (spec-of controller))
                         (namestring (spec-source-file (spec-of controller)))))
         (library (and watch (script-library-source (presenter-library (controller-presenter controller))))))
    (setf (viewer-inbox viewer) (or inbox (make-inbox)))
    (follow-in-viewer viewer)
    (when watch
      (setf (viewer-watcher viewer) (make-file-watcher (list spec-file (and library (namestring library)))
                                                       (glfw-time))
            (viewer-reload viewer) (lambda (viewer changed) (reload-watched viewer changed spec-file allow-code)))
      (write-live-line *standard-output* "; watching~@[ ~A~]~@[ ~A~] for changes~%"
                       (and spec-file (file-namestring spec-file)) (and library (file-namestring library))))))

(defun serve-live-viewer (viewer)
  "Once a frame: read changed watched files again, run what other threads
posted, and note a switch of spec."
  (let ((watcher (viewer-watcher viewer)))
    (when watcher
      (let ((changed (watcher-changes watcher (glfw-time))))
        (when changed (funcall (viewer-reload viewer) viewer changed)))))
  (when (viewer-inbox viewer)
    (run-inbox (viewer-inbox viewer) viewer))
  (note-spec-switch viewer))

(defun stop-live-viewer (viewer)
  "VIEWER's window is closing: its controller stops following, its inbox takes nothing more."
  (unfollow-spec (viewer-controller viewer))
  (when (viewer-inbox viewer)
    (close-inbox (viewer-inbox viewer))))
