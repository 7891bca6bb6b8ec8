;;;; pose-when.lisp -- a script library's starting poses: (:pose-when EXPR POSE
;;;; [:position (X Y Z)]) says that a character whose controller starts in a
;;;; state where the state expression EXPR holds starts in the pose POSE of the
;;;; library's pose library (at POSITION, metres, when given), instead of its
;;;; rest pose, so the first frame matches the initial state: Peedy with
;;;; posture=sit starts seated.  The first entry whose EXPR holds wins.  Here
;;;; the form is read; EXPR and POSE are checked against the spec and the pose
;;;; library when a performance is set up (performance/starting-pose.lisp),
;;;; since a library is read before it knows either.

(in-package #:player.performance)

(defstruct (pose-when (:constructor make-pose-when (expression pose position form source)))
  "One (:pose-when EXPR POSE [:position (X Y Z)]) entry: EXPRESSION as written,
the POSE's name, POSITION (a VEC3 or NIL), the FORM and its SOURCE (FILE .
CHARACTER-POSITION) or NIL, for errors found later."
  expression (pose nil :type symbol) position form source)

(defun parse-pose-when (form)
  "The POSE-WHEN entry FORM, (:pose-when EXPR POSE [:position (X Y Z)]), declares;
a SCRIPT-ERROR when it is malformed."
  (unless (and (alexandria:proper-list-p form) (>= (length form) 3))
    (script-fail form "a starting pose is written (:pose-when EXPRESSION POSE [:position (X Y Z)])"))
  (destructuring-bind (head expression pose &rest options) form
    (declare (ignore head))
    (let ((*script-context* (format nil "(:pose-when ~A ~A)" (bounded-lisp-text expression 60)
                                    (bounded-lisp-text pose 40))))
      (unless (usable-name-p pose)
        (script-fail form "the pose must be a pose's name, not ~A" (lisp-text pose)))
      (check-options form options '(:position) ":pose-when")
      (let ((position (getf options :position)))
        (make-pose-when expression pose
                        (and position (parse-property-value :vector position form ":position"))
                        form *source-position*)))))
