;;;; skeleton-reload.lisp -- a body presenter's skeleton read again while it
;;;; plays (live authoring: the skeleton file was edited).  As for a library
;;;; read again (library-reload.lisp), the new skeleton must pass the checks
;;;; MAKE-BODY-PRESENTER makes, or the character plays on the old one.  The
;;;; scene is then rebuilt: the body is remade on the new skeleton and the
;;;; scripts played so far replay on it.

(in-package #:player.performance)

(defun reload-character-skeleton (presenter spec &optional path)
  "Read the skeleton of PRESENTER's character again from PATH (default: the
file it was read from) and play on it from now on, once every script SPEC
needs can play on it.  Returns the new skeleton.  Signals a SKELETON-ERROR
for a broken file and a SCRIPT-ERROR (or POSE-ERROR) for a script that cannot
play, the old skeleton playing on; an ARGUMENT-ERROR when there is no file."
  (check-argument 'reload-character-skeleton 'presenter presenter (lambda (x) (typep x 'body-presenter))
                  "a body presenter (from make-body-presenter)")
  (check-argument 'reload-character-skeleton 'spec spec #'spec-designator-p *spec-designator*)
  (let* ((spec (if (spec-p spec) spec (find-spec spec)))
         (performance (presenter-performance presenter))
         (character (first (performance-characters performance)))
         (old (character-spec-skeleton character))
         (path (or path (skeleton-source old)
                   (argument-fail 'reload-character-skeleton 'path path
                                  "a file's path: the character's skeleton was not read from a file")))
         (skeleton (load-skeleton path))
         (library (performance-library performance)))
    (setf (character-spec-skeleton character) skeleton)
    (let ((poses (handler-bind ((error (lambda (e)
                                         (declare (ignore e))
                                         (setf (character-spec-skeleton character) old))))
                   (let ((poses (checked-script-library spec performance library)))
                     (check-starting-poses library spec skeleton poses)
                     poses))))
      (setf (performance-poses performance) poses
            (slot-value presenter 'starting-poses) (check-starting-poses library spec skeleton poses)
            (replay-stale performance) t))
    skeleton))
