;;;; model-skeleton.lisp -- MODEL-SKELETON: the skeleton, placement, skins and
;;;; roles of an imported model (see rig.lisp for the frames).

(in-package #:player.rig)

;;;# Placement

(defun points-bounds (points)
  "The (MIN . MAX) vec3s of the vec3 POINTS (a nonempty list)."
  (let ((low (copy-structure (first points))) (high (copy-structure (first points))))
    (dolist (p points (cons low high))
      (setf (vec3-x low) (min (vec3-x low) (vec3-x p)) (vec3-x high) (max (vec3-x high) (vec3-x p))
            (vec3-y low) (min (vec3-y low) (vec3-y p)) (vec3-y high) (max (vec3-y high) (vec3-y p))
            (vec3-z low) (min (vec3-z low) (vec3-z p)) (vec3-z high) (max (vec3-z high) (vec3-z p))))))

(defun model-placement (points up height scale)
  "The placement MAT4 and scale for a model whose bind pose has the model-space
POINTS: turned so UP is +y, scaled by SCALE or to HEIGHT metres tall (else
left in the file's units, taken as metres), and moved to stand on y = 0,
centred on x = z = 0.  A RIG-ERROR for a model with no height to scale."
  (let* ((turn (make-transform :rotation (up-rotation up)))
         (turned (mapcar (lambda (p) (transform-point turn p)) points))
         (bounds (points-bounds turned))
         (extent (- (vec3-y (cdr bounds)) (vec3-y (car bounds))))
         (s (cond (scale (float scale 1d0))
                  (height (if (> extent 1d-9)
                              (/ (float height 1d0) extent)
                              (rig-fail height "the model has no height in its bind pose, so :height cannot scale it; give :scale")))
                  (t 1d0)))
         (placement (identity-transform)))
    (dotimes (i 3)
      (dotimes (j 3)
        (setf (aref placement i j) (* s (aref turn i j)))))
    (let ((centre (v* (v+ (car bounds) (cdr bounds)) 0.5d0)))
      (setf (aref placement 0 3) (- (* s (vec3-x centre)))
            (aref placement 1 3) (- (* s (vec3-y (car bounds))))
            (aref placement 2 3) (- (* s (vec3-z centre)))))
    (values placement s)))

;;;# The skeleton form

(defun tidy-metres (x)
  "X rounded to 0 below a nanometre (the skeleton reader's smallest number)."
  (if (< (abs x) 1d-9) 0d0 x))

(defun joint-dof-clauses (name role-joints limits)
  "The :dofs of the joint NAME: x, y and z within +-*IMPORTED-DOF-RANGE*, narrowed
by the LIMITS entry naming it (by name, or by a role in ROLE-JOINTS)."
  (let ((entry (find-if (lambda (entry)
                          (let ((target (first entry)))
                            (if (keywordp target)
                                (member name (cdr (assoc target role-joints)) :test #'string-equal)
                                (string-equal (string target) name))))
                        limits :from-end t)))
    (loop for axis in '(:x :y :z)
          for given = (find axis (rest entry) :key #'first)
          collect (if given
                      (list axis (second given) (third given))
                      (list axis (- *imported-dof-range*) *imported-dof-range*)))))

(defun check-limits (limits names role-joints)
  "Signal a RIG-ERROR for a :limits entry that is not (JOINT-OR-ROLE (AXIS MIN MAX) ...)
naming a joint or filled role, with MIN <= MAX within [-180, 180]."
  (unless (alexandria:proper-list-p limits)
    (rig-fail limits ":limits is a list of (JOINT-OR-ROLE (AXIS MIN MAX) ...)"))
  (dolist (entry limits)
    (unless (and (alexandria:proper-list-p entry) (rest entry)
                 (or (stringp (first entry)) (and (first entry) (symbolp (first entry)))))
      (rig-fail entry "a limit is written (JOINT-OR-ROLE (AXIS MIN MAX) ...)"))
    (let ((target (first entry)))
      (unless (if (keywordp target)
                  (assoc target role-joints)
                  (find (string target) names :test #'string-equal))
        (rig-fail entry "~:[the model has no joint~;no joint of the model fills the role~] ~A"
                  (keywordp target) (lisp-text target))))
    (dolist (dof (rest entry))
      (unless (and (alexandria:proper-list-p dof) (= (length dof) 3)
                   (member (first dof) '(:x :y :z))
                   (realp (second dof)) (realp (third dof))
                   (<= -180 (second dof) (third dof) 180))
        (rig-fail entry "a limit's DOF is (AXIS MIN MAX), AXIS :x, :y or :z, -180 <= MIN <= MAX <= 180, not ~A"
                  (lisp-text dof))))))

;;;# Roles

(defun role-fits-p (role target parents)
  "Does TARGET (a joint index, or a list of them) fill ROLE as *SKELETON-ROLES* says?"
  (destructuring-bind (&optional kind documentation length) (rest (assoc role *skeleton-roles*))
    (declare (ignore documentation))
    (case kind
      (:joint (integerp target))
      ((:chain :set)
       (and (consp target) (every #'integerp target)
            (= (length target) (length (remove-duplicates target)))
            (or (null length) (= length (length target)))
            (or (eq kind :set)
                (loop for (parent child) on target
                      while child always (eql (aref parents child) parent)))))
      (t nil))))

(defun explicit-roles (roles)
  "The alist ROLE -> name or names of a :roles option, ((ROLE TARGET) ...); a
RIG-ERROR when it is malformed or names a role Player does not know."
  (unless (alexandria:proper-list-p roles)
    (rig-fail roles ":roles is a list of (ROLE \"JOINT\") or (ROLE (\"JOINT\" ...))"))
  (loop for entry in roles
        do (unless (and (alexandria:proper-list-p entry) (= (length entry) 2) (keywordp (first entry))
                        (or (stringp (second entry))
                            (and (consp (second entry)) (alexandria:proper-list-p (second entry))
                                 (every #'stringp (second entry)))))
             (rig-fail entry "a role is written (ROLE \"JOINT\") or (ROLE (\"JOINT\" ...))"))
           (unless (assoc (first entry) *skeleton-roles*)
             (rig-fail entry "unknown role ~A (known: ~{~A~^ ~})" (lisp-text (first entry))
                       (mapcar (lambda (e) (lisp-text (car e))) *skeleton-roles*)))
        collect (cons (first entry) (second entry))))

(defun model-roles (model roles parents)
  "The roles of MODEL's skeleton, an alist ROLE -> joint index or indices:
guessed from the joints' names (GUESS-ROLES), the explicit ROLES winning; a
guess that does not fit Player's role (a chain of the wrong length) is left
out, an explicit role that does not fit is a RIG-ERROR."
  (let* ((explicit (explicit-roles roles))
         (names (map 'vector #'joint-name (model-joints model)))
         (all (handler-case (guess-roles names :parents (map 'vector (lambda (p) (or p -1)) parents)
                                               :explicit explicit)
                (role-error (condition)
                  (rig-fail (find (role-error-role condition) roles :key #'first)
                            "role ~A names the joint ~S, which ~A does not have"
                            (lisp-text (role-error-role condition)) (role-error-joint condition)
                            (file-namestring (model-file model)))))))
    (loop for (role . target) in all
          for fits = (role-fits-p role target parents)
          when (and (not fits) (assoc role explicit))
            do (rig-fail (find role roles :key #'first)
                         "role ~A must name ~A" (lisp-text role)
                         (destructuring-bind (kind documentation &optional length) (rest (assoc role *skeleton-roles*))
                           (declare (ignore documentation))
                           (ecase kind
                             (:joint "one joint")
                             (:chain (format nil "a chain of ~@[~D ~]joints, each the child of the one before" length))
                             (:set "a list of distinct joints"))))
        when fits collect (cons role target))))

;;;# The entry point

(defun check-model-skeleton-options (height scale up)
  "A RIG-ERROR for a :height, :scale or :up that is not what MODEL-SKELETON takes."
  (when (and height scale) (rig-fail (list :height height :scale scale) "give :height or :scale, not both"))
  (unless (or (null height) (and (realp height) (< 1d-6 height 1d6)))
    (rig-fail height ":height is the bind pose's height in metres, a number between 1e-6 and 1e6"))
  (unless (or (null scale) (and (realp scale) (< 1d-9 scale 1d9)))
    (rig-fail scale ":scale is a positive number (metres per unit of the file)"))
  (unless (member up '(:y :z)) (rig-fail up ":up is :y or :z, the model's up axis")))

(defun model-bind-points (model worlds palettes)
  "Every vertex of MODEL at rest in the model's space, or, for a model without
meshes (motion capture), its joints' rest positions."
  (or (loop for mesh in (model-meshes model)
            for (joints . binds) in palettes
            nconc (multiple-value-bind (slots weights) (mesh-slots-and-weights mesh joints)
                    (bind-rest-points mesh (coerce binds 'simple-vector) slots weights)))
      (map 'list (lambda (world) (affine-point world 0d0 0d0 0d0)) worlds)))

(defun model-skeleton (model &key name height scale (up :y) roles limits clips)
  "A SKELETON made from the imported MODEL, with its RIG as SKELETON-RIG: one
joint per model joint, named as in the file (#2... added to a repeated name),
at its rest position in Player's space, each turning about x, y and z within
+-180 degrees.  UP (:y or :z) is the model's up axis; HEIGHT (metres) scales
the bind pose to that height, or SCALE multiplies the file's units (default:
the units are metres); the figure stands on y = 0, centred on x = z = 0.
ROLES, ((ROLE \"JOINT\") (ROLE (\"JOINT\" ...)) ...), names roles, which
win over those guessed from the joints' names (GUESS-ROLES); LIMITS,
((JOINT-OR-ROLE (AXIS MIN MAX) ...) ...), narrows DOFs.  Every animation
is a clip (CLIP-NAME-FROM-ANIMATION); CLIPS, ((NAME :from FRAME :to FRAME :fps
N [:animation NAME-OR-INDEX]) ...), cuts more (CUT-CLIP).  NAME names the
skeleton (default: after the file).  Signals RIG-ERROR for options that do
not fit the model."
  (check-argument 'model-skeleton 'model model #'model-p "a model (from import-model)")
  (check-model-skeleton-options height scale up)
  (unless (alexandria:proper-list-p clips)
    (rig-fail clips ":clips is a list of (NAME :from FRAME :to FRAME :fps N [:animation NAME-OR-INDEX])"))
  (when (zerop (length (model-joints model)))
    (if (model-morph-targets model)
        ;; Morph targets and no joints (a face of blend shapes): one joint
        ;; carries the meshes, the morphs move them.
        (setf model (with-root-joint model))
        (rig-fail (model-file model) "~A has no joints: it is a prop, not a character" (file-namestring (model-file model)))))
  (let* ((joints (model-joints model))
         (parents (map 'vector #'joint-parent joints))
         (names (unique-joint-names model))
         (worlds (model-world-rest model))
         (palettes (mapcar (lambda (mesh)
                             (let ((palette (mesh-palette-joints mesh)))
                               (cons palette (mesh-bind-matrices model mesh palette worlds))))
                           (model-meshes model)))
         (symbols (map 'vector #'make-symbol names))
         (role-indices (model-roles model roles parents))
         (role-joints (loop for (role . target) in role-indices
                            collect (cons role (mapcar (lambda (i) (svref names i)) (ensure-list target))))))
    (check-limits limits names role-joints)
    (multiple-value-bind (placement s)
        (model-placement (model-bind-points model worlds palettes) up height scale)
      (let* ((centres (map 'vector (lambda (world)
                                     (let ((p (affine-point (affine* placement world) 0d0 0d0 0d0)))
                                       (list (tidy-metres (vec3-x p)) (tidy-metres (vec3-y p))
                                             (tidy-metres (vec3-z p)))))
                           worlds))
             (form `(skeleton ,(or name (make-symbol (pathname-name (model-file model))))
                      (:documentation ,(format nil "Imported from ~A." (file-namestring (model-file model))))
                      ,@(loop for i below (length joints)
                              collect `(:joint ,(svref symbols i)
                                        :parent ,(and (aref parents i) (svref symbols (aref parents i)))
                                        :center ,(svref centres i)
                                        :dofs ,(joint-dof-clauses (svref names i) role-joints limits)))
                      ,@(loop for (role . target) in role-indices
                              collect `(:role ,role ,(if (listp target)
                                                         (mapcar (lambda (i) (svref symbols i)) target)
                                                         (svref symbols target))))))
             (skeleton (parse-skeleton form (model-file model))))
        ;; Morph weights are channels after the DOFs: set before any pose is made.
        (setf (skeleton-morphs skeleton) (coerce (model-morph-targets model) 'simple-vector))
        (multiple-value-bind (rest-rotations parent-rotations) (joint-rest-rotations model up)
          (let ((rig (%make-rig :model model :placement placement :scale s
                                :morph-base (skeleton-dof-count skeleton)
                                :world-rest worlds :rest-rotations rest-rotations
                                :parent-rotations parent-rotations
                                :joint-map (map 'simple-vector
                                                (lambda (n) (body-joint-index (find-joint skeleton n)))
                                                names))))
            (setf (rig-skins rig) (make-skins rig palettes skeleton)
                  (rig-bounds rig) (rig-bind-bounds rig skeleton)
                  (skeleton-rig skeleton) rig)
            (add-animation-clips rig)
            (dolist (clip clips) (cut-clip rig clip))
            skeleton))))))

(defun with-root-joint (model)
  "A copy of MODEL, which has no joints, with one at the scene's root that every mesh hangs from."
  (let ((copy (copy-model model)))
    (setf (model-joints copy)
          (vector (make-joint "root" nil (make-array 3 :element-type 'double-float :initial-element 0d0)
                              (make-array 4 :element-type 'double-float :initial-contents '(1d0 0d0 0d0 0d0))
                              (make-array 3 :element-type 'double-float :initial-element 1d0)
                              nil)))
    copy))

(defun make-skins (rig palettes skeleton)
  "The SKINs of RIG's model's meshes, from PALETTES ((JOINTS . BINDS) per mesh)."
  (loop for mesh in (model-meshes (rig-model rig))
        for (joints . binds) in palettes
        collect (multiple-value-bind (slots weights) (mesh-slots-and-weights mesh joints)
                  (%make-skin :mesh mesh
                              :palette-joints (map '(simple-array fixnum (*))
                                                   (lambda (j) (svref (rig-joint-map rig) j)) joints)
                              :palette (map 'simple-vector
                                            (lambda (joint bind)
                                              ;; B = T(-c) P E: from mesh space to the joint's rest frame.
                                              (let ((world (affine* (rig-placement rig) (svref (rig-world-rest rig) joint))))
                                                (affine* (translation-matrix
                                                          (make-vec3 (- (aref world 0 3)) (- (aref world 1 3)) (- (aref world 2 3))))
                                                         (affine* (rig-placement rig) bind))))
                                            joints binds)
                              :slots slots :weights weights
                              :morphs (loop for target in (model-mesh-morphs mesh)
                                            collect (cons (morph-index skeleton (morph-target-name target) t)
                                                          (morph-target-deltas target)))))))

(defun rig-bind-bounds (rig skeleton)
  "The (MIN . MAX) vec3s of RIG's skins at rest on SKELETON (its joints, for a model without meshes)."
  (let* ((transforms (pose-world-transforms skeleton (make-pose skeleton)))
         (points (or (loop for skin in (rig-skins rig)
                           nconc (let ((positions (skin-rest-positions skin transforms)))
                                   (loop for i below (length positions) by 3
                                         collect (make-vec3 (aref positions i) (aref positions (+ i 1))
                                                            (aref positions (+ i 2))))))
                     (map 'list #'transform-translation transforms))))
    (points-bounds points)))
