;;;; skeleton-files.lisp -- reading a skeleton file into a SKELETON: finding
;;;; it (a shipped name or a path), parsing its joints, DOFs and roles, ordering
;;;; the joints parent first.  The file is data: read with *READ-EVAL* NIL.

(in-package #:player.body)

;;; ---------------------------------------------------------------------------
;;; The file format
;;;
;;; A skeleton file holds exactly one form, read with *READ-EVAL* NIL in the
;;; package PLAYER-USER (names are compared by name, case-insensitively):
;;;
;;;   (skeleton NAME
;;;     [(:documentation "TEXT")]
;;;     (:joint NAME :parent PARENT-OR-NIL :center (X Y Z)
;;;             [:dofs ((AXIS MIN MAX [:name DOF-NAME]) ...)] [:radius R])
;;;     ...
;;;     (:role ROLE JOINT-OR-(JOINT ...))
;;;     ...
;;;     [(:speed-limits (JOINT [DOF] DEG/S) ...)])   ; see speed-limits.lisp
;;;
;;; Coordinates are metres in the H-Anim frame: +y up, +z the figure's front,
;;; +x the figure's left.  CENTER is where the joint rotates, in the figure's
;;; rest pose.  Exactly one joint has :parent NIL (the root); the others may be
;;; listed in any order.  Each DOF is a rotation, in degrees, about AXIS taken
;;; right-handed through the joint centre in the parent's rest frame: :x :y :z,
;;; or :-x :-y :-z for the negative axis (so a mirrored joint can keep its
;;; partner's limits, e.g. a finger curl that closes the hand at +90 on either
;;; side).  MIN <= MAX, both within [-180, 180].  DOF-NAME defaults to the axis
;;; keyword and is unique within its joint; (JOINT . DOF-NAME) names a channel.
;;; :radius (metres, default 0.03) is the limb's thickness for later rendering.
;;; :dofs may be empty: a joint that only carries its children.
;;;
;;; Roles name the joints that drivers look for, so a gaze driver finds the
;;; eyes of a human and a parrot alike.  The roles are *SKELETON-ROLES*; a
;;; :joint role names one joint, a :chain role a list in which each joint is the
;;; child of the one before, a :set role any list of joints.  A skeleton need
;;; not fill every role, but every role it fills must resolve.

;;; ---------------------------------------------------------------------------
;;; Loading

(defun load-skeleton (name-or-path)
  "Read the skeleton NAME-OR-PATH and return a SKELETON.  A symbol, or a string
without a directory or type, names a shipped skeleton (HUMANOID, PARROT);
anything else is a file's path.  Signals SKELETON-ERROR for an unknown name, an
unreadable file, or any malformed or inconsistent content; an ARGUMENT-ERROR
for NAME-OR-PATH that is neither a symbol, a string nor a pathname."
  (check-argument 'load-skeleton 'name-or-path name-or-path
                  (lambda (x) (or (symbolp x) (pathname-designator-p x)))
                  (format nil "a shipped skeleton's name (~{~A~^, ~}) or ~A"
                          (shipped-skeleton-names) *path-phrase*))
  (let ((path (skeleton-path name-or-path)))
    (with-spec-context (:spec-name nil)
      (let ((entries (with-spec-context (:source-position nil)
                       (read-data-file path :what "skeleton file" :allow-in-package nil
                                            :fail (lambda (position message kind)
                                                    (with-spec-context (:source-position (and position (cons (probe-file path) position)))
                                                      (case kind
                                                        (:missing (skeleton-fail name-or-path "there is no skeleton file ~A"
                                                                                 (namestring path)))
                                                        (:read (skeleton-fail nil "the Lisp reader could not read ~A: ~A"
                                                                              (file-namestring path) message))
                                                        (t (skeleton-fail nil "~A" message)))))))))
        (with-spec-context (:source-position nil)
          (cond ((null entries) (skeleton-fail nil "~A holds no skeleton form" (file-namestring path)))
                ((rest entries) (skeleton-fail nil "~A holds more than one form" (file-namestring path)))))
        (with-spec-context (:source-position (cons (probe-file path) (second (first entries))))
          (parse-skeleton (first (first entries)) path))))))

(defun shipped-skeleton-names ()
  "The names of the skeletons shipped with Player, as lower-case strings."
  (sort (mapcar #'pathname-name
                (directory (merge-pathnames "*.lisp" *shipped-skeletons-directory*)))
        #'string<))

(defun skeleton-path (name-or-path)
  "The file NAME-OR-PATH designates (see LOAD-SKELETON).  Signals SKELETON-ERROR for
a name that is not a shipped skeleton."
  (let ((shipped-name
          (typecase name-or-path
            (symbol (string-downcase (symbol-name name-or-path)))
            (string (and (not (find #\/ name-or-path))
                         (not (find #\. name-or-path))
                         (string-downcase name-or-path))))))
    (cond ((null shipped-name) (pathname name-or-path))
          ((member shipped-name (shipped-skeleton-names) :test #'string=)
           (merge-pathnames (make-pathname :name shipped-name :type "lisp")
                            *shipped-skeletons-directory*))
          (t (skeleton-fail name-or-path "unknown skeleton ~A (shipped: ~{~A~^, ~})"
                            (lisp-text name-or-path) (shipped-skeleton-names))))))

(defun parse-skeleton (form &optional source)
  "Build a SKELETON from FORM, a (SKELETON NAME CLAUSE...) list; SOURCE is kept as
the skeleton's origin.  Signals SKELETON-ERROR for anything malformed: unknown
parent, duplicate joint, cycle, bad limits, unknown axis, unknown or unresolved
role."
  (unless (and (consp form) (alexandria:proper-list-p form)
               (symbolp (first form)) (string-equal (first form) "SKELETON")
               (rest form) (symbolp (second form)) (second form))
    (skeleton-fail form "a skeleton must be written (skeleton NAME CLAUSE...)"))
  (let ((bad (out-of-range-number form)))
    (when bad
      (skeleton-fail form "the number ~A is out of range: skeleton numbers are 0 or between ~A and ~A in magnitude"
                     (argument-value-text bad) (first *library-number-range*) (second *library-number-range*))))
  (let ((name (second form))
        (documentation nil)
        (joint-clauses '())
        (role-clauses '())
        (speed-limits '()))
    (dolist (clause (cddr form))
      (unless (and (consp clause) (alexandria:proper-list-p clause))
        (skeleton-fail clause "a skeleton clause must be a list starting with :joint, :role or :documentation"))
      (case (first clause)
        (:joint (push clause joint-clauses))
        (:role (push clause role-clauses))
        (:speed-limits (setf speed-limits (append speed-limits (parse-speed-limits-clause clause))))
        (:documentation
         (unless (and (= (length clause) 2) (stringp (second clause)))
           (skeleton-fail clause "(:documentation TEXT) takes one string"))
         (setf documentation (second clause)))
        (t (skeleton-fail clause "a skeleton clause must start with :joint, :role, :speed-limits or :documentation"))))
    (let* ((joints (order-joints (mapcar #'parse-joint-clause (nreverse joint-clauses))
                                 name))
           (skeleton (%make-skeleton :name name :documentation documentation
                                     :joints joints :source source
                                     :speed-limit-entries speed-limits)))
      (loop with start = 0
            for joint across joints
            do (setf (gethash (string (body-joint-name joint))
                              (skeleton-joint-table skeleton))
                     joint
                     (body-joint-dof-start joint) start)
               (incf start (length (body-joint-dofs joint)))
            finally (setf (skeleton-dof-count skeleton) start))
      (setf (skeleton-roles skeleton)
            (parse-role-clauses (nreverse role-clauses) skeleton))
      skeleton)))

;;; A joint clause is first parsed on its own into a JOINT-DRAFT; ORDER-JOINTS
;;; then links parents, finds the root and checks for cycles.

(defstruct (joint-draft (:constructor make-joint-draft (clause joint parent-name)))
  "A parsed joint clause whose parent is still a name."
  (clause nil :read-only t)
  (joint nil :type body-joint :read-only t)
  (parent-name nil :type symbol :read-only t))

(defun parse-joint-clause (clause)
  "A JOINT-DRAFT from CLAUSE, (:joint NAME :parent P :center (X Y Z) [:dofs D] [:radius R])."
  (destructuring-bind (name &rest plist) (rest clause)
    (unless (and name (symbolp name) (not (keywordp name)))
      (skeleton-fail clause "a joint needs a name (a symbol) after :joint"))
    (unless (evenp (length plist))
      (skeleton-fail clause "joint ~A's options must be keyword/value pairs" (lisp-text name)))
    (loop for key in plist by #'cddr
          unless (member key '(:parent :center :dofs :radius))
            do (skeleton-fail clause "joint ~A has an unknown option ~A (known: :parent :center :dofs :radius)"
                              (lisp-text name) (lisp-text key)))
    (unless (member :parent plist)
      (skeleton-fail clause "joint ~A needs :parent (NIL for the root)" (lisp-text name)))
    (let ((parent (getf plist :parent))
          (radius (getf plist :radius *default-joint-radius*)))
      (unless (symbolp parent)
        (skeleton-fail clause "joint ~A's :parent must be a joint name or NIL" (lisp-text name)))
      (unless (and (realp radius) (plusp radius))
        (skeleton-fail clause "joint ~A's :radius must be a positive number of metres" (lisp-text name)))
      (make-joint-draft
       clause
       (%make-body-joint :name name
                         :center (parse-center (getf plist :center) name clause)
                         :dofs (parse-dofs (getf plist :dofs) name clause)
                         :radius radius)
       parent))))

(defun parse-center (center name clause)
  "CENTER, a list of three reals, as a simple vector of floats."
  (unless (and (alexandria:proper-list-p center) (= (length center) 3)
               (every #'realp center))
    (skeleton-fail clause "joint ~A needs :center (X Y Z), three numbers of metres" (lisp-text name)))
  (map 'simple-vector (lambda (x) (float x 1d0)) center))

(defun parse-dofs (dofs name clause)
  "DOFS, a list of (AXIS MIN MAX [:name DOF-NAME]), as BODY-DOFs; checks axes,
limits and that DOF names are unique within the joint."
  (unless (alexandria:proper-list-p dofs)
    (skeleton-fail clause "joint ~A's :dofs must be a list of (AXIS MIN MAX [:name NAME])" (lisp-text name)))
  (let ((parsed (mapcar (lambda (dof) (parse-dof dof name clause)) dofs)))
    (loop for (dof . later) on parsed
          when (find (body-dof-name dof) later :key #'body-dof-name :test #'string-equal)
            do (skeleton-fail clause "joint ~A has two DOFs called ~A"
                              (lisp-text name) (lisp-text (body-dof-name dof))))
    ;; BVH and Euler decompositions need each axis at most once per joint.
    (loop for (dof . later) on parsed
          for line = (dof-axis-line dof)
          when (find line later :key #'dof-axis-line)
            do (skeleton-fail clause "joint ~A turns twice about the ~A axis"
                              (lisp-text name) (lisp-text line)))
    parsed))

(defun dof-axis-line (dof)
  "The unsigned axis (:x, :y or :z) DOF turns about."
  (ecase (body-dof-axis dof) ((:x :-x) :x) ((:y :-y) :y) ((:z :-z) :z)))

(defun parse-dof (dof name clause)
  "One BODY-DOF from DOF, (AXIS MIN MAX [:name DOF-NAME])."
  (unless (and (alexandria:proper-list-p dof) (member (length dof) '(3 5))
               (or (= (length dof) 3) (eq (fourth dof) :name)))
    (skeleton-fail clause "joint ~A: a DOF is written (AXIS MIN MAX [:name NAME]), not ~A"
                   (lisp-text name) (lisp-text dof)))
  (destructuring-bind (axis min max &key (name axis)) dof
    (unless (assoc axis *dof-axes*)
      (skeleton-fail clause "joint ~A has a DOF about the unknown axis ~A (known: ~{~A~^ ~})"
                     (lisp-text (second clause)) (lisp-text axis)
                     (mapcar (lambda (entry) (lisp-text (car entry))) *dof-axes*)))
    (unless (and (symbolp name) name)
      (skeleton-fail clause "joint ~A: a DOF's :name must be a symbol" (lisp-text (second clause))))
    (unless (and (realp min) (realp max) (<= -180 min max 180))
      (skeleton-fail clause "joint ~A: the limits of DOF ~A must be degrees with -180 <= MIN <= MAX <= 180, not ~A ~A"
                     (lisp-text (second clause)) (lisp-text name) (lisp-text min) (lisp-text max)))
    (make-body-dof name axis min max)))

(defun order-joints (drafts skeleton-name)
  "The joints of DRAFTS linked to their parents, as a vector in depth-first
pre-order from the root, children in file order.  Signals SKELETON-ERROR for a
duplicate joint, an unknown parent, no root or two, or a cycle."
  (let ((table (make-hash-table :test #'equalp)))
    (dolist (draft drafts)
      (let ((key (string (body-joint-name (joint-draft-joint draft)))))
        (when (gethash key table)
          (skeleton-fail (joint-draft-clause draft) "joint ~A is defined twice"
                         (lisp-text (body-joint-name (joint-draft-joint draft)))))
        (setf (gethash key table) draft)))
    (let ((roots (remove-if #'joint-draft-parent-name drafts)))
      (unless (= (length roots) 1)
        (skeleton-fail (mapcar #'joint-draft-clause roots)
                       "skeleton ~A needs exactly one root joint (:parent nil), not ~D"
                       (lisp-text skeleton-name) (length roots)))
      (dolist (draft drafts)
        (let ((parent-name (joint-draft-parent-name draft)))
          (when parent-name
            (let ((parent (gethash (string parent-name) table)))
              (unless parent
                (skeleton-fail (joint-draft-clause draft) "joint ~A names the unknown parent ~A"
                               (lisp-text (body-joint-name (joint-draft-joint draft)))
                               (lisp-text parent-name)))
              (link-joint (joint-draft-joint draft) (joint-draft-joint parent))))))
      (let ((ordered (joints-depth-first (joint-draft-joint (first roots)))))
        (when (< (length ordered) (length drafts))
          (let ((stray (find-if-not (lambda (draft) (member (joint-draft-joint draft) ordered))
                                    drafts)))
            (skeleton-fail (joint-draft-clause stray)
                           "joint ~A is its own ancestor: the parents form a cycle"
                           (lisp-text (body-joint-name (joint-draft-joint stray))))))
        (loop for joint in ordered
              for index from 0
              do (setf (body-joint-index joint) index))
        (coerce ordered 'simple-vector)))))

(defun link-joint (joint parent)
  "Make PARENT the parent of JOINT, appending JOINT to PARENT's children."
  (setf (body-joint-parent joint) parent)
  (setf (body-joint-children parent)
        (append (body-joint-children parent) (list joint))))

(defun joints-depth-first (root)
  "ROOT and its descendants, each parent before its children."
  (cons root (mapcan #'joints-depth-first (copy-list (body-joint-children root)))))

(defun parse-role-clauses (clauses skeleton)
  "An alist (ROLE . TARGET) from CLAUSES, each (:role ROLE JOINT-OR-LIST), resolved
against SKELETON's joints (see *SKELETON-ROLES*)."
  (let ((roles '()))
    (dolist (clause clauses (nreverse roles))
      (unless (= (length clause) 3)
        (skeleton-fail clause "a role is written (:role ROLE JOINT) or (:role ROLE (JOINT ...))"))
      (destructuring-bind (role target) (rest clause)
        (let ((entry (assoc role *skeleton-roles*)))
          (unless entry
            (skeleton-fail clause "unknown role ~A (known: ~{~A~^ ~})" (lisp-text role)
                           (mapcar (lambda (e) (lisp-text (car e))) *skeleton-roles*)))
          (when (assoc role roles)
            (skeleton-fail clause "role ~A is given twice" (lisp-text role)))
          (push (cons role (resolve-role clause role (second entry) (fourth entry)
                                         target skeleton))
                roles))))))

(defun resolve-role (clause role kind chain-length target skeleton)
  "The joint or joints TARGET names for ROLE of KIND (:joint, :chain, :set)."
  (flet ((resolve (name)
           (or (and name (symbolp name) (find-joint skeleton name))
               (skeleton-fail clause "role ~A names ~A, which is not a joint of skeleton ~A"
                              (lisp-text role) (lisp-text name)
                              (lisp-text (skeleton-name skeleton))))))
    (if (eq kind :joint)
        (if (and target (symbolp target))
            (resolve target)
            (skeleton-fail clause "role ~A names one joint" (lisp-text role)))
        (progn
          (unless (and (consp target) (alexandria:proper-list-p target))
            (skeleton-fail clause "role ~A names a list of joints" (lisp-text role)))
          (let ((joints (mapcar #'resolve target)))
            (when (and chain-length (/= chain-length (length joints)))
              (skeleton-fail clause "role ~A is a chain of ~D joints, not ~D"
                             (lisp-text role) chain-length (length joints)))
            (when (eq kind :chain)
              (loop for (parent child) on joints
                    while child
                    unless (eq (body-joint-parent child) parent)
                      do (skeleton-fail clause "role ~A is a chain, but ~A's parent is not ~A"
                                        (lisp-text role) (lisp-text (body-joint-name child))
                                        (lisp-text (body-joint-name parent)))))
            (when (/= (length joints) (length (remove-duplicates joints)))
              (skeleton-fail clause "role ~A names a joint twice" (lisp-text role)))
            joints)))))
