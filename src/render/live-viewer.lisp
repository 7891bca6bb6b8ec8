;;;; live-viewer.lisp -- the viewer as an authoring environment: its controller
;;;; follows its spec, so a DEFSPEC evaluated at the REPL (or over Swank) or,
;;;; with --watch, a saved spec file, script library, pose library or skeleton
;;;; file changes the character as it plays, each save saying so in one line.  Redefinitions reach the viewer's thread through its INBOX
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

;;;# Redefinitions

(defun take-reloaded-file (viewer)
  "The name of the file VIEWER read again this frame and has not said so yet
\(NIL if none); it is said now, by whoever takes it."
  (shiftf (viewer-reloaded viewer) nil))

(defun redefine-viewed (viewer machine)
  "Switch VIEWER's controller to MACHINE, a new definition of its spec, once
the body can play every script the new spec needs; report why not otherwise."
  (let* ((controller (viewer-controller viewer))
         (performance (presenter-performance (controller-presenter controller))))
    (handler-case
        (progn
          (checked-script-library (machine-spec machine) performance (performance-library performance))
          (when (eq (redefine-controller controller machine) :pending)
            (write-live-line *standard-output* "; ~@[read ~A again: ~]~A redefined: it switches when the running event ends~%"
                             (take-reloaded-file viewer) (viewer-name viewer))))
      (player-error (e)
        (take-reloaded-file viewer)
        (report-live-error viewer e)))))

(defun follow-in-viewer (viewer)
  "Make VIEWER's controller follow its spec, new machines handed over through VIEWER's inbox."
  (let ((inbox (viewer-inbox viewer)))
    (follow-spec (viewer-controller viewer)
                 :deliver (lambda (controller machine)
                            (declare (ignore controller))
                            (inbox-post inbox (lambda (viewer) (redefine-viewed viewer machine)))))))

(defun note-spec-switch (viewer)
  "When VIEWER's controller now runs another spec than the one last shown,
say so in one line (naming the file read again, if that was why), clear the
error in the title and print the new key map."
  (let ((spec (spec-of (viewer-controller viewer))))
    (unless (or (null (viewer-spec viewer)) (eq spec (viewer-spec viewer)))
      (setf (viewer-spec viewer) spec
            (viewer-message viewer) nil
            (viewer-keys viewer) (view-event-keys spec))
      (write-live-line *standard-output* "; now playing the new definition of ~A (from ~A s~@[, ~A read again~])~%"
                       (lisp-text (spec-name spec)) (format-number (controller-time (viewer-controller viewer)))
                       (take-reloaded-file viewer))
      (print-key-map (viewer-keys viewer) (viewer-terminal viewer)))))

;;;# Watched files

(defun viewer-watched-files (viewer spec-file)
  "The files VIEWER follows, as (PATH . KIND) with KIND :spec, :scripts,
:poses or :skeleton: SPEC-FILE (or NIL), its character's script library, the
pose library that names and the skeleton's file, those that are files."
  (let* ((performance (presenter-performance (controller-presenter (viewer-controller viewer))))
         (library (performance-library performance))
         (skeleton (body-skeleton (performance-body performance))))
    (loop for (path kind) in (list (list spec-file :spec)
                                   (list (script-library-source library) :scripts)
                                   (list (script-library-poses library) :poses)
                                   (list (skeleton-source skeleton) :skeleton))
          when path collect (cons (namestring path) kind))))

(defparameter *reload-lines*
  '((:scripts . "; read the script library ~A again~%")
    (:poses . "; read the pose library ~A again~%")
    (:skeleton . "; read the skeleton ~A again: the body is remade on it~%"))
  "The line each kind of watched file (but the spec's) prints when it was read again.")

(defun reload-watched-file (viewer path kind)
  "Read PATH, a changed file of KIND (see VIEWER-WATCHED-FILES, not :spec),
again for VIEWER's character and say so in one line; report an error."
  (let* ((controller (viewer-controller viewer))
         (presenter (controller-presenter controller)))
    (handler-case
        (progn (ecase kind
                 (:scripts (reload-script-library presenter (spec-of controller) path))
                 ;; The library reads its pose library each time it is read.
                 (:poses (reload-script-library presenter (spec-of controller)))
                 (:skeleton (reload-character-skeleton presenter (spec-of controller) path)))
               (setf (viewer-message viewer) nil)
               (write-live-line *standard-output* (cdr (assoc kind *reload-lines*)) (file-namestring path)))
      (player-error (e) (report-live-error viewer e)))))

(defun reload-spec-file (viewer spec-file allow-code)
  "Read SPEC-FILE again (with ALLOW-CODE); its DEFSPEC reaches VIEWER's
controller as any redefinition does, and the line saying so names the file."
  (handler-case
      (let ((name (name-key (spec-name (spec-of (viewer-controller viewer))))))
        (setf (viewer-reloaded viewer) (file-namestring spec-file))
        (unless (find name (load-spec spec-file :allow-code allow-code)
                      :key (lambda (spec) (name-key (spec-name spec))) :test #'equal)
          (error 'player-error-with-message
                 :message (format nil "~A no longer defines spec ~A" (file-namestring spec-file)
                                  (viewer-name viewer)))))
    (player-error (e)
      (setf (viewer-reloaded viewer) nil)
      (report-live-error viewer e))))

(defun reload-watched (viewer changed spec-file allow-code)
  "Read again the files in CHANGED: libraries and the skeleton first (a new
spec may need their new scripts), then SPEC-FILE (with ALLOW-CODE).  Each
save says so in one line; errors are reported.  The watcher then follows the
files the character now uses."
  (let ((kinds (viewer-watched-files viewer spec-file)))
    (dolist (path changed)
      (let ((kind (cdr (assoc path kinds :test #'equal))))
        (unless (member kind '(nil :spec))
          (reload-watched-file viewer path kind))))
    (when (member spec-file changed :test #'equal)
      (reload-spec-file viewer spec-file allow-code))
    (let ((paths (mapcar #'car (viewer-watched-files viewer spec-file)))
          (watcher (viewer-watcher viewer)))
      (unless (equal paths (watcher-paths watcher))
        (setf (viewer-watcher viewer) (make-file-watcher paths (file-watcher-checked-at watcher)))))
    (finish-output)))

(defun start-live-viewer (viewer &key inbox watch (allow-code t))
  "Make VIEWER live: its controller follows its spec through INBOX (a new one
if NIL), and with WATCH its spec's file, script library, pose library and
skeleton file are read again when they change (the spec file with ALLOW-CODE)."
  (let* ((controller (viewer-controller viewer))
         (spec-file (and watch (spec-source-file (spec-of controller))
                         (namestring (spec-source-file (spec-of controller))))))
    (setf (viewer-inbox viewer) (or inbox (make-inbox)))
    (follow-in-viewer viewer)
    (when watch
      (let ((files (viewer-watched-files viewer spec-file)))
        (setf (viewer-watcher viewer) (make-file-watcher (mapcar #'car files) (glfw-time))
              (viewer-reload viewer) (lambda (viewer changed) (reload-watched viewer changed spec-file allow-code)))
        (write-live-line *standard-output* "; watching~{ ~A~} for changes~%"
                         (mapcar (lambda (file) (file-namestring (car file))) files))))))

(defun serve-live-viewer (viewer)
  "Once a frame: read changed watched files again, run what other threads
posted, and note a switch of spec.  A spec file read again that changed
nothing the viewer shows still says so, once."
  (let ((watcher (viewer-watcher viewer)))
    (when watcher
      (let ((changed (watcher-changes watcher (glfw-time))))
        (when changed (funcall (viewer-reload viewer) viewer changed)))))
  (when (viewer-inbox viewer)
    (run-inbox (viewer-inbox viewer) viewer))
  (note-spec-switch viewer)
  (let ((file (take-reloaded-file viewer)))
    (when file (write-live-line *standard-output* "; read ~A again~%" file))))

(defun stop-live-viewer (viewer)
  "VIEWER's window is closing: its controller stops following, its inbox takes nothing more."
  (unfollow-spec (viewer-controller viewer))
  (when (viewer-inbox viewer)
    (close-inbox (viewer-inbox viewer))))
