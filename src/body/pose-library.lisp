;;;; pose-library.lisp -- named, partial poses read from data files: arm
;;;; shapes, hand shapes, bows (Pantomime's shapes database), looked up by the
;;;; keyframe and pose drivers, checked against a skeleton's joints and limits.

(in-package #:player.body)

(defvar *resolved-poses* nil
  "While a pose is resolved: each pose resolved so far mapped to its entries, so
a pose included many times (fanned out, #1=(p1 p1), twice at every level) is
resolved once.")

;;; ---------------------------------------------------------------------------
;;; The file format
;;;
;;; A pose library file holds DEFPOSE forms, read as data (never evaluated)
;;; with *READ-EVAL* NIL, double-float numbers, in the package PLAYER-USER:
;;;
;;;   (defpose NAME ["DOCUMENTATION"] CLAUSE...)
;;;
;;;   CLAUSE = (JOINT-OR-ROLE DOF ANGLE [DOF ANGLE ...])   set DOFs, in degrees
;;;          | (:include POSE)                            another pose's angles
;;;          | (:mirror POSE)                             another pose, left <-> right
;;;          | (:morph NAME WEIGHT)                       a morph target's weight, 0 to 1
;;;
;;; A joint's name may be written as a string, as an imported model's must
;;; when it is no symbol ("mixamorig:LeftArm").
;;;
;;; JOINT-OR-ROLE is a joint name, or a role keyword (see *SKELETON-ROLES*); a
;;; :chain or :set role sets the DOF on each of its joints, so
;;; (:left-fingers curl 80) curls every left finger.  A pose is partial: it
;;; sets only the DOFs it names, so poses layer (a hand shape names only the
;;; fingers).  Later clauses override earlier ones.  :mirror swaps l_/r_
;;; joints and turns each angle so the mirrored joint turns as the mirror image
;;; (through the figure's x = 0 plane) of the original.  Names are compared
;;; case-insensitively.  Poses are checked against a skeleton when resolved:
;;; every joint, role and DOF must exist and every angle lie within limits.

(define-condition pose-error (spec-error)
  ()
  (:report report-spec-error-safely)
  (:documentation "A pose library or a pose is malformed, or does not fit a
skeleton: an unknown joint, role, DOF or pose, an angle outside the joint's
limits.  FORM is the offending form or clause."))

(defun pose-fail (form control &rest arguments)
  "Signal a POSE-ERROR about FORM with a message from CONTROL and ARGUMENTS."
  (error 'pose-error :form form :message (apply #'format nil control arguments)))

(defstruct (pose-definition (:constructor make-pose-definition
                                (name documentation clauses form position library)))
  "A pose as written: its NAME, CLAUSES, the FORM, where it was read
\(POSITION, (FILE . CHARACTER) or NIL) and the LIBRARY it belongs to."
  (name nil :type symbol :read-only t)
  (documentation nil :type (or null string) :read-only t)
  (clauses '() :type list :read-only t)
  (form nil :read-only t)
  (position nil :read-only t)
  (library nil :read-only t))

(defstruct (pose-library (:constructor %make-pose-library (name source)))
  "Poses by name (a string, compared case-insensitively), in file order; NAME
is the library's (a string), SOURCE its file or NIL; FALLBACK, the library
whose poses it keeps under its own (the skeleton's shipped one), or NIL."
  (name "" :type string :read-only t)
  (source nil :read-only t)
  (table (make-hash-table :test #'equalp) :type hash-table :read-only t)
  (order '() :type list)
  (fallback nil))

(defmethod print-object ((definition pose-definition) stream)
  (print-unreadable-object (definition stream :type t)
    (write-string (lisp-text (pose-definition-name definition)) stream)))

(defmethod print-object ((library pose-library) stream)
  (print-unreadable-object (library stream :type t)
    (format stream "~A, ~D poses" (pose-library-name library)
            (length (pose-library-order library)))))

(defun pose-library-names (library)
  "The names of LIBRARY's poses, in file order, then those of its fallback it does not override."
  (let ((own (mapcar #'pose-definition-name (pose-library-order library))))
    (append own (and (pose-library-fallback library)
                     (remove-if (lambda (name) (member name own :test #'string-equal))
                                (pose-library-names (pose-library-fallback library)))))))

(defun find-pose (library name &optional (errorp t))
  "LIBRARY's pose definition called NAME (a symbol or string).  When there is
none: a POSE-ERROR naming the known poses, or NIL without ERRORP."
  (or (and (or (symbolp name) (stringp name))
           (gethash (string name) (pose-library-table library)))
      ;; A pose the library does not define: its fallback's (the shipped one).
      (and (pose-library-fallback library)
           (find-pose (pose-library-fallback library) name nil))
      (and errorp
           (pose-fail name "pose library ~A has no pose ~A (known: ~{~A~^ ~})"
                      (pose-library-name library) (lisp-text name)
                      (mapcar #'lisp-text (pose-library-names library))))))

;;;# Reading

(defun check-pose-clause (clause)
  "Signal a POSE-ERROR unless CLAUSE is a well-formed pose clause (see the file format)."
  (unless (and (consp clause) (alexandria:proper-list-p clause)
               (or (stringp (first clause)) (symbolp (first clause)))
               (first clause))
    (pose-fail clause "a pose clause is written (JOINT-OR-ROLE DOF ANGLE ...), (:include POSE), (:mirror POSE) or (:morph NAME WEIGHT)"))
  (cond
    ((eq (first clause) :morph)
     (unless (and (= (length clause) 3) (or (stringp (second clause)) (and (second clause) (symbolp (second clause))))
                  (realp (third clause)) (<= 0 (third clause) 1))
       (pose-fail clause "a morph target's weight is written (:morph NAME WEIGHT), WEIGHT from 0 to 1")))
    ((member (first clause) '(:include :mirror))
     (unless (and (= (length clause) 2) (symbolp (second clause)) (second clause))
       (pose-fail clause "~A names one pose: (~A POSE)" (lisp-text (first clause))
                  (lisp-text (first clause)))))
    (t
     (let ((pairs (rest clause)))
       (unless (and pairs (evenp (length pairs))
                    (loop for (dof angle) on pairs by #'cddr
                          always (and dof (symbolp dof) (realp angle))))
         (pose-fail clause "~A must be followed by DOF ANGLE pairs (a DOF name, then degrees)"
                    (lisp-text (first clause)))))))
  clause)

(defun add-pose-form (library form position)
  "Parse FORM, (defpose NAME [DOC] CLAUSE...), and add it to LIBRARY."
  (unless (and (consp form) (alexandria:proper-list-p form) (symbolp (first form))
               (string-equal (first form) "DEFPOSE"))
    (pose-fail form "a pose library holds only (defpose NAME [DOCUMENTATION] CLAUSE...) forms"))
  (let ((bad (out-of-range-number form)))
    (when bad
      (pose-fail form "the angle ~A is out of range: pose numbers are 0 or between ~A and ~A in magnitude"
                 (argument-value-text bad) (first *library-number-range*) (second *library-number-range*))))
  (destructuring-bind (&optional name &rest body) (rest form)
    (unless (and name (symbolp name) (not (keywordp name)))
      (pose-fail form "defpose needs a name (a symbol)"))
    (let* ((documentation (and (stringp (first body)) (first body)))
           (clauses (if documentation (rest body) body)))
      (when (null clauses)
        (pose-fail form "pose ~A sets nothing: give at least one clause" (lisp-text name)))
      (mapc #'check-pose-clause clauses)
      ;; Twice in this file is an error; over a fallback's pose, an override.
      (when (gethash (string name) (pose-library-table library))
        (pose-fail form "pose ~A is defined twice" (lisp-text name)))
      (let ((definition (make-pose-definition name documentation clauses form position library)))
        (setf (gethash (string name) (pose-library-table library)) definition)
        (alexandria:appendf (pose-library-order library) (list definition))
        definition))))

(defun make-pose-library (forms &key (name "poses") source)
  "A pose library from FORMS, a list of DEFPOSE forms, called NAME.  Signals
POSE-ERROR for a malformed form.  (LOAD-POSE-LIBRARY reads them from a file.)"
  (let ((library (%make-pose-library name source)))
    (dolist (form forms library)
      (add-pose-form library form nil))))

(defun load-pose-library (path &key skeleton fallback)
  "Read the pose library file PATH and return a POSE-LIBRARY named after the
file.  FALLBACK (a POSE-LIBRARY, or NIL) keeps its poses under the file's:
a name the file does not define is found there, so naming your own library
keeps the skeleton's shipped poses (SHIPPED-POSE-LIBRARY) and yours override
them by name.  With SKELETON, every pose is also resolved against it (see
RESOLVE-POSE).  Signals POSE-ERROR, naming the file and line, for a missing or
unreadable file, a malformed form, or (with SKELETON) a pose that does not fit."
  (multiple-value-bind (entries text) (read-data-file path :what "pose library" :allow-in-package nil
                                       :fail (lambda (position message kind)
                                               (with-spec-context (:source-position (and position (cons (probe-file path) position)))
                                                 (case kind
                                                   (:missing (pose-fail path "there is no pose library file ~A"
                                                                        (namestring path)))
                                                   (:read (pose-fail nil "the Lisp reader could not read ~A: ~A"
                                                                     (file-namestring path) message))
                                                   (t (pose-fail nil "~A" message))))))
    (let* ((path (probe-file path))
           (library (%make-pose-library (pathname-name path) path)))
      (setf (pose-library-fallback library) fallback)
      ;; Errors about a clause name the clause's own line.
      (with-spec-context (:sub-form-places (sub-form-places entries text path))
        (loop for (form start) in entries
              do (with-spec-context (:source-position (cons path start))
                   (add-pose-form library form (cons path start))))
        (when skeleton
          (with-spec-context (:source-position nil)
            (let ((*resolved-poses* (make-hash-table :test 'eq)))  ; each pose resolved once
              (dolist (definition (pose-library-order library))
                (resolve-pose definition skeleton)))))
        library))))

;;;# Resolving against a skeleton

(defun clause-joints (clause skeleton)
  "The joints CLAUSE's head (a joint name or a role keyword) names in SKELETON, as a list."
  (let ((head (first clause)))
    (if (keywordp head)
        (let ((target (and (assoc head *skeleton-roles*) (skeleton-role skeleton head))))
          (cond ((null target)
                 (pose-fail clause "skeleton ~A fills no role ~A (roles: ~{~A~^ ~})"
                            (lisp-text (skeleton-name skeleton)) (lisp-text head)
                            (mapcar #'lisp-text (skeleton-role-names skeleton))))
                ((listp target) target)
                (t (list target))))
        (list (or (find-joint skeleton head)
                  (pose-fail clause "skeleton ~A has no joint ~A"
                             (lisp-text (skeleton-name skeleton)) (lisp-text head)))))))

(defun dof-text (name)
  "The DOF NAME as a pose file writes it: lower case, no colon."
  (string-downcase (string name)))

(defun check-angle (clause joint dof angle)
  "Signal a POSE-ERROR about CLAUSE unless ANGLE lies within DOF's limits."
  (unless (<= (- (body-dof-min dof) 1d-9) angle (+ (body-dof-max dof) 1d-9))
    (pose-fail clause "DOF ~A of joint ~A: ~A degrees is outside its limits ~A to ~A"
               (dof-text (body-dof-name dof)) (lisp-text (body-joint-name joint))
               (format-number angle) (format-number (body-dof-min dof))
               (format-number (body-dof-max dof)))))

(defun dof-clause-angles (clause skeleton)
  "The (INDEX . ANGLE) entries a (JOINT-OR-ROLE DOF ANGLE ...) CLAUSE sets in SKELETON."
  (loop for joint in (clause-joints clause skeleton)
        nconc (loop for (dof-name angle) on (rest clause) by #'cddr
                    for dof = (body-joint-dof joint dof-name)
                    do (unless dof
                         (pose-fail clause "joint ~A has no DOF ~A (it has ~{~A~^ ~})"
                                    (lisp-text (body-joint-name joint)) (dof-text dof-name)
                                    (mapcar (lambda (d) (dof-text (body-dof-name d)))
                                            (body-joint-dofs joint))))
                       (check-angle clause joint dof angle)
                    collect (cons (+ (body-joint-dof-start joint)
                                     (position dof (body-joint-dofs joint)))
                                  (float angle 1d0)))))

(defun mirror-joint-name (name)
  "The name of NAME's mirror-image joint: l_X <-> r_X, anything else itself."
  (let ((text (string name)))
    (cond ((and (> (length text) 2) (string-equal "L_" text :end2 2))
           (concatenate 'string "R_" (subseq text 2)))
          ((and (> (length text) 2) (string-equal "R_" text :end2 2))
           (concatenate 'string "L_" (subseq text 2)))
          (t text))))

(defun mirror-entry (entry skeleton clause)
  "The (INDEX . ANGLE) ENTRY of SKELETON reflected through the x = 0 plane.
Reflecting the rotation by A about axis U gives the rotation by -A about MU (M
negates x), so the partner DOF, about axis V, turns -A (V . MU)."
  (multiple-value-bind (joint dof) (skeleton-dof skeleton (car entry))
    (let* ((partner (or (find-joint skeleton (mirror-joint-name (body-joint-name joint)))
                        (pose-fail clause "skeleton ~A has no mirror image of joint ~A"
                                   (lisp-text (skeleton-name skeleton))
                                   (lisp-text (body-joint-name joint)))))
           (partner-dof (or (body-joint-dof partner (body-dof-name dof))
                            (pose-fail clause "joint ~A has no DOF ~A to mirror ~A's"
                                       (lisp-text (body-joint-name partner))
                                       (dof-text (body-dof-name dof))
                                       (lisp-text (body-joint-name joint)))))
           (angle (* (- (cdr entry))
                     (destructuring-bind (ux uy uz) (dof-axis-vector dof)
                       (destructuring-bind (vx vy vz) (dof-axis-vector partner-dof)
                         (+ (* vx (- ux)) (* vy uy) (* vz uz)))))))
      (check-angle clause partner partner-dof angle)
      (cons (+ (body-joint-dof-start partner) (position partner-dof (body-joint-dofs partner)))
            (if (zerop angle) 0d0 (float angle 1d0))))))

(defun resolve-clauses (clauses skeleton &key library visiting)
  "The (INDEX . ANGLE) entries of CLAUSES in SKELETON, one per DOF (the last
clause naming a DOF wins), sorted by index.  :include and :mirror clauses look
their pose up in LIBRARY; VISITING lists the poses being resolved, to catch
cycles.  Signals POSE-ERROR for anything that does not fit SKELETON."
  (let ((entries '()))
    (dolist (clause clauses)
      (check-pose-clause clause)
      (let ((more
              (case (first clause)
                ((:include :mirror)
                 (let ((other (or (and library (find-pose library (second clause) nil))
                                  (pose-fail clause "there is no pose ~A~@[ in pose library ~A~]"
                                             (lisp-text (second clause))
                                             (and library (pose-library-name library))))))
                   (when (member other visiting)
                     (pose-fail clause "pose ~A includes itself" (lisp-text (second clause))))
                   (let ((included (resolve-pose other skeleton visiting)))
                     (if (eq (first clause) :mirror)
                         (mapcar (lambda (entry)
                                   ;; A morph target's weight has no side to mirror.
                                   (if (>= (car entry) (skeleton-dof-count skeleton))
                                       entry
                                       (mirror-entry entry skeleton clause)))
                                 included)
                         included))))
                (:morph (list (cons (or (morph-index skeleton (second clause))
                                        (pose-fail clause "skeleton ~A has no morph target ~A (it has ~:[none~;~:*~{~A~^, ~}~])"
                                                   (lisp-text (skeleton-name skeleton)) (lisp-text (second clause))
                                                   (coerce (skeleton-morphs skeleton) 'list)))
                                    (float (third clause) 1d0))))
                (t (dof-clause-angles clause skeleton)))))
        (dolist (entry more)
          (setf entries (cons entry (remove (car entry) entries :key #'car))))))
    (sort entries #'< :key #'car)))

(defun resolve-pose (definition skeleton &optional visiting)
  "DEFINITION's angles in SKELETON as a list of (POSE-INDEX . DEGREES), sorted
by index.  Signals POSE-ERROR, naming the clause (and the file and line it was
read from), for an unknown joint, role, DOF or pose, or an angle outside the
joint's limits."
  (if (null *resolved-poses*)
      (let ((*resolved-poses* (make-hash-table :test 'eq)))
        (resolve-pose definition skeleton visiting))
      (or (gethash definition *resolved-poses*)
          (setf (gethash definition *resolved-poses*)
                (with-spec-context (:source-position (or (pose-definition-position definition) *source-position*))
                  (resolve-clauses (pose-definition-clauses definition) skeleton
                                   :library (pose-definition-library definition)
                                   :visiting (cons definition visiting)))))))

(defun apply-pose-angles (entries pose)
  "Write the (INDEX . DEGREES) ENTRIES into POSE; return POSE."
  (loop for (index . angle) in entries
        do (setf (aref pose index) angle))
  pose)

;;;# The library a body uses

(defparameter *shipped-poses-directory*
  (merge-pathnames "poses/" #.(or *compile-file-truename* *load-truename*))
  "Where the pose libraries shipped with Player live: <skeleton-name>-poses.lisp.")

(defvar *pose-library* nil
  "The pose library of bodies that have none of their own (see BODY-POSE-LIBRARY);
NIL means the shipped library for the body's skeleton.")

(defvar *shipped-pose-libraries* (make-hash-table :test #'equalp :synchronized t)
  "Shipped pose libraries already loaded, by skeleton name.")

(defvar *body-pose-libraries* (make-hash-table :test #'eq :weakness :key :synchronized t)
  "Pose libraries set for single bodies with (SETF BODY-POSE-LIBRARY); weak, so
a forgotten body is collected.")

(defun shipped-pose-library (skeleton)
  "The pose library shipped for SKELETON (poses/<name>-poses.lisp), loaded and
checked against SKELETON once, then cached; an empty library when none ships."
  (let ((name (string-downcase (string (skeleton-name skeleton)))))
    (or (gethash name *shipped-pose-libraries*)
        (setf (gethash name *shipped-pose-libraries*)
              (let ((path (merge-pathnames (format nil "~A-poses.lisp" name)
                                           *shipped-poses-directory*)))
                (if (probe-file path)
                    (load-pose-library path :skeleton skeleton)
                    (%make-pose-library (format nil "~A-poses" name) nil)))))))

(defun body-pose-library (body)
  "The pose library BODY's drivers find poses in: the one set for BODY, else
*POSE-LIBRARY*, else the shipped library for BODY's skeleton."
  (or (values (gethash body *body-pose-libraries*))
      *pose-library*
      (shipped-pose-library (body-skeleton body))))

(defun (setf body-pose-library) (library body)
  "Make LIBRARY (a POSE-LIBRARY, or NIL for the default) BODY's pose library."
  (if library
      (setf (gethash body *body-pose-libraries*) library)
      (remhash body *body-pose-libraries*))
  library)
