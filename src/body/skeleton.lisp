;;;; skeleton.lisp -- a character's body: joints, their rotational DOFs, named roles.
;;;; SKELETON structs are the BodyModel side of Pantomime's split between motor
;;;; control and rendering; skeleton-files.lisp reads them from s-expression
;;;; data files (never compiled or LOADed), and documents the format.

(in-package #:player.body)

(defparameter *skeleton-roles*
  '((:head :joint "turns the head")
    (:left-eye :joint "aims the left eye")
    (:right-eye :joint "aims the right eye")
    (:left-upper-lid :joint "closes the left upper lid")
    (:right-upper-lid :joint "closes the right upper lid")
    (:left-brow :joint "raises the left brow")
    (:right-brow :joint "raises the right brow")
    (:jaw :joint "opens the mouth (the lower mandible of a beak)")
    (:crest :joint "raises a crest")
    (:tail :joint "moves the tail")
    (:left-arm :chain "shoulder, elbow, wrist of the left arm or wing" 3)
    (:right-arm :chain "shoulder, elbow, wrist of the right arm or wing" 3)
    (:left-hand :joint "the left hand, or the tip of the left wing")
    (:right-hand :joint "the right hand, or the tip of the right wing")
    (:left-fingers :set "the left fingers, thumb first")
    (:right-fingers :set "the right fingers, thumb first")
    (:left-leg :chain "hip to foot, left")
    (:right-leg :chain "hip to foot, right")
    (:spine :chain "the lowest spinal joint up to the head"))
  "Every role a skeleton may fill: (ROLE KIND DOCUMENTATION [CHAIN-LENGTH]).")

(defparameter *dof-axes*
  '((:x 1 0 0) (:y 0 1 0) (:z 0 0 1) (:-x -1 0 0) (:-y 0 -1 0) (:-z 0 0 -1))
  "The rotation axes a DOF may name, with their unit vectors in the parent frame.")

(defparameter *default-joint-radius* 0.03
  "The limb radius, in metres, of a joint that gives none.")

(defparameter *shipped-skeletons-directory*
  (merge-pathnames "skeletons/" #.(or *compile-file-truename* *load-truename*))
  "Where the skeletons shipped with Player live (humanoid.lisp, parrot.lisp); the
directory beside this source file, fixed when it is compiled.")

(define-condition skeleton-error (spec-error)
  ()
  (:report report-spec-error-safely)
  (:documentation "A skeleton file or form is malformed or inconsistent; FORM is
the offending clause."))

(defun skeleton-fail (form control &rest arguments)
  "Signal a SKELETON-ERROR about FORM, with a message from CONTROL and ARGUMENTS."
  (error 'skeleton-error :form form :message (apply #'format nil control arguments)))

;;; ---------------------------------------------------------------------------
;;; Data

(defstruct (body-dof (:constructor make-body-dof (name axis min max)))
  "One rotational degree of freedom of a joint."
  (name nil :type symbol :read-only t)
  (axis :x :type keyword :read-only t)
  (min 0.0 :type real :read-only t)
  (max 0.0 :type real :read-only t))

(defstruct (body-joint (:constructor %make-body-joint))
  "A joint of a skeleton: where it turns, what it may turn, what hangs off it."
  (name nil :type symbol :read-only t)
  (parent nil :type (or null body-joint))
  (children '() :type list)
  (center #(0.0 0.0 0.0) :type (simple-vector 3) :read-only t)
  (dofs '() :type list :read-only t)
  (radius *default-joint-radius* :type real :read-only t)
  (index 0 :type fixnum)
  (dof-start 0 :type fixnum))

(defstruct (skeleton (:constructor %make-skeleton))
  "A loaded skeleton: JOINTS parent before child, lookup tables by name and role."
  (name nil :type symbol :read-only t)
  (documentation nil :type (or null string) :read-only t)
  (joints #() :type simple-vector)
  (dof-count 0 :type fixnum)
  (joint-table (make-hash-table :test #'equalp) :type hash-table)
  (roles '() :type list)
  (source nil)
  ;; Set by PLAYER.RIG for a skeleton made from an imported model: its RIG
  ;; (the model, its placement, skins and clips).  The body layer never reads it.
  (rig nil)
  ;; The names (strings) of its morph targets: channels after the DOFs, each a
  ;; weight from 0 to 1 (see pose.lisp).  Set by PLAYER.RIG; empty otherwise.
  (morphs #() :type simple-vector)
  ;; Its (:speed-limits ...) clause, as (JOINT DOF-OR-NIL DEG/S) entries (speed-limits.lisp).
  (speed-limit-entries '() :type list)
  ;; Its joints as typed arrays for posing every frame, made on first use (pose.lisp).
  (posing nil))

(defmethod print-object ((skeleton skeleton) stream)
  (print-unreadable-object (skeleton stream :type t)
    (format stream "~A, ~D joints" (lisp-text (skeleton-name skeleton))
            (length (skeleton-joints skeleton)))))

(defmethod print-object ((joint body-joint) stream)
  (print-unreadable-object (joint stream :type t)
    (write-string (lisp-text (body-joint-name joint)) stream)))

(defun body-joint-parent-name (joint)
  "The name of JOINT's parent, or NIL for the root."
  (let ((parent (body-joint-parent joint)))
    (and parent (body-joint-name parent))))

(defun body-joint-dof (joint dof-name)
  "JOINT's DOF called DOF-NAME (compared by name), or NIL."
  (find (string dof-name) (body-joint-dofs joint)
        :key (lambda (dof) (string (body-dof-name dof))) :test #'string-equal))

(defun dof-axis-vector (dof)
  "The unit axis of DOF as a list (X Y Z)."
  (rest (assoc (body-dof-axis dof) *dof-axes*)))

;;; ---------------------------------------------------------------------------
;;; Lookups

(defun skeleton-root (skeleton)
  "The root joint of SKELETON."
  (svref (skeleton-joints skeleton) 0))

(defun find-joint (skeleton name &optional (errorp nil))
  "SKELETON's joint called NAME (a symbol or string, compared case-insensitively).
NIL if there is none, unless ERRORP, when a SKELETON-ERROR is signalled."
  (check-argument 'find-joint 'skeleton skeleton #'skeleton-p "a skeleton (from load-skeleton)")
  (check-argument 'find-joint 'name name #'string-designator-p "a joint's name (a symbol or string)")
  (or (gethash (string name) (skeleton-joint-table skeleton))
      (and errorp
           (skeleton-fail name "skeleton ~A has no joint ~A"
                          (lisp-text (skeleton-name skeleton)) (lisp-text name)))))

(defun skeleton-joint-names (skeleton)
  "The names of SKELETON's joints, parent before child."
  (map 'list #'body-joint-name (skeleton-joints skeleton)))

(defun skeleton-role (skeleton role)
  "What SKELETON's ROLE (a keyword from *SKELETON-ROLES*) names: a BODY-JOINT for a
:joint role, a list of them for a :chain or :set role, NIL when unfilled."
  (check-argument 'skeleton-role 'skeleton skeleton #'skeleton-p "a skeleton (from load-skeleton)")
  (check-argument 'skeleton-role 'role role #'symbolp "a role (a keyword such as :head)")
  (cdr (assoc role (skeleton-roles skeleton))))

(defun skeleton-role-names (skeleton)
  "The roles SKELETON fills, in file order."
  (mapcar #'car (skeleton-roles skeleton)))

(defun skeleton-channel-count (skeleton)
  "How many channels SKELETON's poses hold: its DOFs, then its morph targets."
  (+ (skeleton-dof-count skeleton) (length (skeleton-morphs skeleton))))

(defun morph-index (skeleton name &optional errorp)
  "The pose index of SKELETON's morph target NAME (a string or symbol, compared
case-insensitively); NIL when it has none, unless ERRORP, when a SKELETON-ERROR
lists its morph targets."
  (let ((position (position (string name) (skeleton-morphs skeleton) :test #'string-equal)))
    (cond (position (+ (skeleton-dof-count skeleton) position))
          (errorp (skeleton-fail name "skeleton ~A has no morph target ~A (it has ~:[none~;~:*~{~A~^, ~}~])"
                                 (lisp-text (skeleton-name skeleton)) (lisp-text name)
                                 (coerce (skeleton-morphs skeleton) 'list)))
          (t nil))))

(defun skeleton-channels (skeleton)
  "Every DOF of SKELETON as a channel name (JOINT-NAME . DOF-NAME), parent first."
  (loop for joint across (skeleton-joints skeleton)
        nconc (loop for dof in (body-joint-dofs joint)
                    collect (cons (body-joint-name joint) (body-dof-name dof)))))
