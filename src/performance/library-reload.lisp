;;;; library-reload.lisp -- a body presenter's script library read again while
;;;; it plays (live authoring: the file was edited).  The new library passes
;;;; the checks MAKE-BODY-PRESENTER makes before it replaces the old one, so a
;;;; broken edit leaves the character playing the last good library.  Scripts
;;;; already started play on as they began; the next ones come from the new
;;;; library.

(in-package #:player.performance)

(defun checked-script-library (spec performance library)
  "LIBRARY's pose library for PERFORMANCE's first character, or NIL, once
LIBRARY has every script SPEC needs and each can play on that character;
otherwise the SCRIPT-ERROR (or POSE-ERROR) MAKE-BODY-PRESENTER would signal."
  (check-spec-scripts spec library)
  (let* ((character (first (performance-characters performance)))
         (skeleton (character-spec-skeleton character))
         (poses (and (script-library-poses library)
                     (load-pose-library (script-library-poses library) :skeleton skeleton
                                                            :fallback (shipped-pose-library skeleton))))
         (failure (first (check-library-scripts library skeleton (spec-script-names spec)
                                                :characters (list (character-spec-name character))
                                                :poses poses))))
    (when failure
      (error 'script-error :spec (spec-name spec) :message (diagnostic-message failure)))
    poses))

(defun reload-script-library (presenter spec &optional path)
  "Read PRESENTER's script library again from PATH (default: the file it was
read from) and play it from now on, when it has every script SPEC needs and
each can play on the character.  Returns the new library.  Signals a
SCRIPT-ERROR (the old library playing on) when the file is broken or lacks a
script, and an ARGUMENT-ERROR for an argument of the wrong kind or when
there is no file to read."
  (check-argument 'reload-script-library 'presenter presenter (lambda (x) (typep x 'body-presenter))
                  "a body presenter (from make-body-presenter)")
  (check-argument 'reload-script-library 'spec spec #'spec-designator-p *spec-designator*)
  (check-argument 'reload-script-library 'path path (lambda (x) (or (null x) (pathname-designator-p x)))
                  (format nil "NIL or ~A" *path-phrase*))
  (let* ((spec (if (spec-p spec) spec (find-spec spec)))
         (performance (presenter-performance presenter))
         (path (or path (script-library-source (performance-library performance))
                   (argument-fail 'reload-script-library 'path path
                                  "a file's path: the presenter's library was not read from a file")))
         (library (library-with-placeholders
                   (load-script-library path) spec
                   (character-spec-skeleton (first (performance-characters performance)))))
         (poses (checked-script-library spec performance library)))
    (setf (slot-value performance 'library) library
          (performance-poses performance) poses)
    (reactions-library-changed performance spec)
    library))
