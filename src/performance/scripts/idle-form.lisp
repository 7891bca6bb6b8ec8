;;;; idle-form.lisp -- the (idle FLAG) form of a script library: (idle nil)
;;;; keeps its characters still between scripts, without the idle life
;;;; (blinks, breathing, saccades, weight shifts, relaxed hands) they get by
;;;; default; (idle t) says the default.

(in-package #:player.performance)

(defun set-library-idle (library form)
  "Record FORM, (idle T-OR-NIL), in LIBRARY; a SCRIPT-ERROR when it is malformed."
  (unless (and (alexandria:proper-list-p form) (= (length form) 2) (member (second form) '(t nil)))
    (script-fail form "idle life is switched with (idle nil) or (idle t), not ~A" (lisp-text form)))
  (setf (script-library-idle library) (second form)))
