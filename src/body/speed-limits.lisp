;;;; speed-limits.lisp -- Pantomime's physics module, first part: no joint
;;;; turns faster than a body can turn it.  Whatever the drivers and the
;;;; arbitration composed, each DOF of the final pose moves at most its
;;;; maximum speed (degrees per second) from the pose shown before, so a cut,
;;;; a preemption or a driver asked for :blend 0 never snaps a joint: it
;;;; swings there as fast as the joint can.
;;;;
;;;; Defaults are peak angular velocities of people (rounded up, so ordinary
;;;; motion is never slowed): saccades reach 700-900 deg/s (Bahill et al.,
;;;; "The main sequence", 1975), a blink's lid 2000 deg/s; voluntary head
;;;; turns 600-700 deg/s; trunk 300-400; fast arm gestures 1000-1500 at
;;;; shoulder, elbow and wrist (throwing exceeds this, gesturing does not);
;;;; fingers 2000; hips 700, knees 1000, ankles 900.  A skeleton file
;;;; overrides them:
;;;;
;;;;   (:speed-limits (JOINT DEG/S) (JOINT DOF DEG/S) ...)
;;;;
;;;; JOINT a joint's name, DOF one of its DOFs' names (all of them without).
;;;; Morph weights (the channels after the DOFs) are not angles: not limited.

(in-package #:player.body)

(defparameter *default-speed-limits*
  '((("lid") 2000) (("brow") 600) (("eye") 900)
    (("temporomandibular" "jaw" "beak") 800)
    (("skullbase" "neck" "head") 700)
    (("vl5" "vc" "vt" "sacroiliac" "spine") 400)
    (("root") 500)
    (("shoulder" "clavicle") 1200) (("elbow") 1500) (("wrist") 1500)
    (("thumb" "index" "middle" "ring" "pinky" "primaries" "finger") 2000)
    (("hip") 700) (("knee") 1000) (("ankle" "midtarsal" "foot" "toe") 900)
    (("crest" "tail") 1000))
  "Each (NAME-PARTS DEG/S): the maximum speed of the DOFs of a joint whose name
contains one of NAME-PARTS (the first entry that matches wins).")

(defparameter *fallback-speed-limit* 1000
  "Degrees per second for a DOF of a joint no entry of *DEFAULT-SPEED-LIMITS* names.")

(defvar *speed-limits-enabled* t
  "When NIL, poses are not speed-limited (to compare with and without).")

(defun default-joint-speed (joint)
  "The default maximum speed (deg/s) of JOINT's DOFs, from its name."
  (let ((name (string (body-joint-name joint))))
    (or (loop for (parts speed) in *default-speed-limits*
              when (some (lambda (part) (search part name :test #'char-equal)) parts)
                return speed)
        *fallback-speed-limit*)))

;;;# The skeleton's clause

(defun parse-speed-limits-clause (clause)
  "The entries of CLAUSE, (:speed-limits (JOINT [DOF] DEG/S) ...), as a list
\(JOINT DOF-OR-NIL DEG/S); a SKELETON-ERROR when one is malformed.  The names
are checked against the joints by SKELETON-SPEED-LIMITS."
  (loop for entry in (rest clause)
        collect (if (and (alexandria:proper-list-p entry) (<= 2 (length entry) 3)
                         (every #'symbolp (butlast entry)) (first entry)
                         (realp (car (last entry))) (plusp (car (last entry))))
                    (list (first entry) (and (= (length entry) 3) (second entry)) (car (last entry)))
                    (skeleton-fail clause "a speed limit is written (JOINT DEG/S) or (JOINT DOF DEG/S), ~
                                           with DEG/S positive, not ~A" (lisp-text entry)))))

(defvar *skeleton-speed-limits* (make-hash-table :test #'eq :weakness :key :synchronized t)
  "Each skeleton's speed limits, a vector of deg/s per DOF, made on first use.")

(defun skeleton-speed-limits (skeleton)
  "The maximum speed (deg/s) of each DOF of SKELETON, a DOUBLE-FLOAT vector:
its :speed-limits clause over the defaults."
  (or (gethash skeleton *skeleton-speed-limits*)
      (setf (gethash skeleton *skeleton-speed-limits*)
            (let ((limits (make-array (skeleton-dof-count skeleton) :element-type 'double-float)))
              (loop for joint across (skeleton-joints skeleton)
                    do (loop for dof in (body-joint-dofs joint)
                             for i from (body-joint-dof-start joint)
                             do (setf (aref limits i) (float (default-joint-speed joint) 1d0))))
              (loop for (joint-name dof-name speed) in (skeleton-speed-limit-entries skeleton)
                    for joint = (or (find-joint skeleton joint-name)
                                    (skeleton-fail joint-name "skeleton ~A: a speed limit names the unknown joint ~A"
                                                   (lisp-text (skeleton-name skeleton)) (lisp-text joint-name)))
                    do (loop for dof in (body-joint-dofs joint)
                             for i from (body-joint-dof-start joint)
                             when (or (null dof-name) (string-equal dof-name (body-dof-name dof)))
                               do (setf (aref limits i) (float speed 1d0))
                                  (setf dof-name (and dof-name :found))
                             finally (when (and dof-name (not (eq dof-name :found)))
                                       (skeleton-fail joint-name "skeleton ~A: joint ~A has no DOF ~A"
                                                      (lisp-text (skeleton-name skeleton))
                                                      (lisp-text joint-name) (lisp-text dof-name)))))
              limits))))

;;;# The limiter

(defstruct (speed-state (:constructor make-speed-state (pose time)))
  "The pose last shown (POSE, a copy) and its TIME."
  (pose nil :type pose) (time 0d0 :type double-float))

(defvar *speed-states* (make-hash-table :test #'eq :weakness :key :synchronized t)
  "Each body's SPEED-STATE.")

(defun limit-joint-speeds (body pose time)
  "Move each DOF of POSE, BODY's pose composed for TIME, at most its maximum
speed from the pose BODY showed last (nothing before the first instant).  Changes POSE
in place and returns it."
  (declare (type pose pose) (type double-float time))
  (let ((state (gethash body *speed-states*))
        (limits (skeleton-speed-limits (body-skeleton body))))
    (declare (type (simple-array double-float (*)) limits))
    (cond ((null state)
           (setf (gethash body *speed-states*) (make-speed-state (copy-pose pose) time)))
          ;; What starts at the first instant is the initial pose: nothing moved to it.
          ((or (not *speed-limits-enabled*) (eql time (body-birth body)))
           (replace (speed-state-pose state) pose)
           (setf (speed-state-time state) time))
          (t
           (let ((previous (speed-state-pose state))
                 (dt (max 0d0 (- time (speed-state-time state)))))
             (declare (type pose previous))
             (dotimes (i (length limits))
               (let* ((step (* dt (aref limits i)))
                      (from (aref previous i))
                      (to (aref pose i)))
                 (setf (aref pose i) (max (- from step) (min (+ from step) to)))))
             (replace previous pose)
             (setf (speed-state-time state) time))))
    pose))

(defun note-shown-pose (body pose)
  "Tell BODY's limiter that POSE is what was shown at its last evaluation (a
pose corrected after it, as physics stops a hand at contact): the next pose
moves at most each DOF's maximum speed from there."
  (let ((state (gethash body *speed-states*)))
    (when state
      (replace (speed-state-pose state) pose))
    pose))
