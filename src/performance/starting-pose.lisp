;;;; starting-pose.lisp -- the pose a character starts in: a script library's
;;;; (:pose-when EXPR POSE [:position (X Y Z)]) entries (read in
;;;; scripts/pose-when.lisp) checked against the spec and the pose library,
;;;; and the first whose EXPR holds in the controller's initial state put on
;;;; the performance's first character before anything plays.  Without a
;;;; matching entry the character starts in its rest pose, as before.

(in-package #:player.performance)

(defstruct (starting-pose (:constructor make-starting-pose (entry cubes angles)))
  "A checked POSE-WHEN ENTRY: the CUBES of its expression in the spec, and its
pose's ANGLES ((DOF-INDEX . DEGREES) ...) on the character's skeleton."
  entry cubes angles)

(defun pose-when-fail (entry control &rest arguments)
  "Signal a SCRIPT-ERROR at ENTRY's form, file and line."
  (let ((*script-context* (format nil "(:pose-when ~A ~A)"
                                  (bounded-lisp-text (pose-when-expression entry) 60)
                                  (lisp-text (pose-when-pose entry)))))
    (with-spec-context (:source-position (pose-when-source entry))
      (apply #'script-fail (pose-when-form entry) control arguments))))

(defun pose-when-cubes (entry spec)
  "The cubes of ENTRY's expression in SPEC; a SCRIPT-ERROR at ENTRY when it is
not a state expression of SPEC (an unknown variable, value or class)."
  (handler-case (with-spec-context (:spec spec :spec-name (spec-name spec) :form-places nil)
                  (check-form-structure (pose-when-expression entry) :what "expression")
                  (expression-cubes (parse-expression (pose-when-expression entry)) spec))
    (spec-error (condition)
      (pose-when-fail entry "~A is not a state expression of spec ~A: ~A"
                      (bounded-lisp-text (pose-when-expression entry) 80) (lisp-text (spec-name spec))
                      (spec-error-message condition)))))

(defun pose-when-angles (entry skeleton poses)
  "The angles of ENTRY's pose in the pose library POSES on SKELETON; a
SCRIPT-ERROR at ENTRY when POSES lacks it or it does not fit SKELETON."
  (let ((definition (find-pose poses (pose-when-pose entry) nil)))
    (unless definition
      (pose-when-fail entry "unknown pose ~A (pose library ~A has: ~{~A~^ ~})"
                      (lisp-text (pose-when-pose entry)) (pose-library-name poses)
                      (mapcar #'lisp-text (pose-library-names poses))))
    (handler-case (resolve-pose definition skeleton)
      (spec-error (condition)
        (pose-when-fail entry "pose ~A cannot be taken by skeleton ~A: ~A"
                        (lisp-text (pose-when-pose entry)) (lisp-text (skeleton-name skeleton))
                        (spec-error-message condition))))))

(defun check-starting-poses (library spec skeleton poses)
  "LIBRARY's (:pose-when ...) entries checked against SPEC and the pose
library POSES (NIL: the one shipped for SKELETON), as STARTING-POSEs in
order.  Signals a SCRIPT-ERROR naming the entry's file and line for an
expression that is not one of SPEC's or a pose POSES lacks."
  (let ((poses (or poses (shipped-pose-library skeleton))))
    (mapcar (lambda (entry)
              (make-starting-pose entry (pose-when-cubes entry spec)
                                  (pose-when-angles entry skeleton poses)))
            (script-library-pose-whens library))))

(defun choose-starting-pose (starting-poses state)
  "The first of STARTING-POSES whose expression holds in the one-hot STATE, or NIL."
  (find-if (lambda (start) (some (lambda (cube) (state-in-cube-p state cube)) (starting-pose-cubes start)))
           starting-poses))

(defun put-body-in-starting-pose (body start)
  "Make START (a STARTING-POSE) BODY's pose and, if it gives one, position, as
if BODY had always been so: its held angles, so channels nobody drives keep them."
  (let ((position (pose-when-position (starting-pose-entry start))))
    (when position
      (setf (property-value body 'position) position)))
  (let ((held (body-held body)))
    (apply-pose-angles (starting-pose-angles start) held)
    (%clamp-pose (body-skeleton body) held)
    (replace (body-base body) held)
    ;; The starting pose is also where the body settles until the state changes.
    (replace (body-target body) held)
    (replace (body-pose body) held)
    (pose-world-transforms (body-skeleton body) (body-pose body)
                           :placement (object-world-transform body) :result (body-transforms body)))
  body)

(defun start-performance-pose (performance)
  "Put PERFORMANCE's first character, freshly made by a replay, in the
performance's starting pose, if it has one."
  (let ((start (performance-starting-pose performance)))
    (when start
      (put-body-in-starting-pose (performance-body performance) start))))
