;;;; model.lisp -- `player model`: what an imported model holds, summarised:
;;;; meshes, vertices and triangles, the skeleton as an indented tree, the
;;;; animation clips, textures and morph targets, and the roles guessed from
;;;; the joints' names with the drivers they enable.

(in-package #:player.cli)

(define-command "model" (file &key texture)
    (:summary "import a model through Assimp and summarise it"
     :description "Imports MODEL-FILE (glTF, FBX, COLLADA, .x, BVH... whatever Assimp
reads; see doc/models.md) and prints its meshes with their vertices and
triangles, its joints as an indented tree (bones marked), its animation clips
with their durations in seconds, its textures (each with its size in
pixels, or marked missing or undecodable) and its morph targets, then the roles guessed from the joints' names (see
doc/models.md) and which drivers they enable. A file that is missing, that Assimp cannot
read, or that holds numbers that are not finite or more than Player's limits
is one error, and so is a --texture FILE that cannot be decoded."
     :arguments ("MODEL-FILE")
     :options (("--texture" :string "FILE" "use FILE as every mesh's diffuse texture instead of the model's own"))
     :output "the summary on standard output")
  (let* ((model (import-model file :texture texture))
         (decoded (model-texture-images model)))
    (when texture
      (check-chosen-texture decoded))
    (print-model-summary model decoded)))

(defun check-chosen-texture (decoded)
  "Signal the IMAGE-ERROR (naming the file and why) of a texture in DECODED (see
MODEL-TEXTURE-IMAGES) that could not be decoded.  Called with --texture, where
every mesh's texture is the file the command line gave: a file the user chose
that is not a picture fails the command, where the model's own broken texture
is only marked in the summary."
  (loop for (nil . result) in decoded
        when (typep result 'image-error)
          do (error result)))

(defun print-model-summary (model decoded)
  "Print MODEL's summary: meshes, joints, animations, textures (with DECODED, from
MODEL-TEXTURE-IMAGES), morph targets."
  (format t "model ~A~%" (model-file model))
  (print-model-meshes model)
  (print-model-joints model)
  (print-model-animations model)
  (format t "textures: ~:[none~;~:*~{~A~^, ~}~]~%"
          (mapcar (lambda (path)
                    (texture-description path (cdr (assoc path decoded :test #'string=))))
                  (model-textures model)))
  (format t "morph targets: ~:[none~;~:*~{~A~^, ~}~]~%" (model-morph-targets model))
  (print-model-roles model))

(defun texture-description (path result)
  "PATH with what decoding it gave, RESULT (see MODEL-TEXTURE-IMAGES): its size,
\"(missing)\" or \"(undecodable: REASON)\" (an embedded texture, \"*N\", is never missing)."
  (typecase result
    (image (format nil "~A ~Dx~D" path (image-width result) (image-height result)))
    (image-error (if (or (embedded-texture-p path) (probe-file path))
                     (format nil "~A (undecodable: ~A)" path (image-error-reason result))
                     (format nil "~A (missing)" path)))
    (t path)))

(defun print-model-meshes (model)
  "Print MODEL's mesh, vertex and triangle totals, then one line per mesh."
  (format t "~D mesh~:*~[es~;~:;es~], ~D vertices, ~D triangles~%"
          (length (model-meshes model)) (model-vertex-count model) (model-triangle-count model))
  (dolist (mesh (model-meshes model))
    (format t "  mesh ~:[~S~;(unnamed)~*~]: ~D vertices, ~D triangles~@[, skinned by ~D bones~]~%"
            (string= (model-mesh-name mesh) "") (model-mesh-name mesh)
            (model-mesh-vertex-count mesh) (model-mesh-triangle-count mesh)
            (and (model-mesh-joints mesh) (length (model-mesh-bones mesh))))))

(defun print-model-joints (model)
  "Print MODEL's joint count and its joints as a tree, two spaces a level, bones marked."
  (let* ((joints (model-joints model))
         (depths (make-array (length joints) :initial-element 0)))
    (format t "~D joint~:P (~D bone~:P)~:[~;:~]~%" (length joints)
            (count-if #'joint-inverse-bind joints) (plusp (length joints)))
    (loop for joint across joints
          for i from 0
          for parent = (joint-parent joint)
          do (when parent (setf (aref depths i) (1+ (aref depths parent))))
             (format t "  ~A~A~:[~; (bone)~]~%" (make-string (* 2 (aref depths i)) :initial-element #\Space)
                     (joint-name joint)
                     (joint-inverse-bind joint)))))

(defun print-model-animations (model)
  "Print MODEL's animation count and one line per clip: name, seconds, channels."
  (format t "~D animation~:P~:[~;:~]~%" (length (model-animations model)) (model-animations model))
  (dolist (animation (model-animations model))
    (format t "  ~:[~S~;(unnamed)~*~]: ~A s, ~D channel~:P~%"
            (string= (model-animation-name animation) "") (model-animation-name animation)
            (format-number (model-animation-duration animation))
            (length (model-animation-channels animation)))))

(defun role-joints (model)
  "The indices of MODEL's joints roles are guessed among: every joint but the
nodes that only hold a mesh (no bone themselves, none below them), so that a
mesh named \"Head\" is not taken for the head, while a BVH's hips, which
Assimp gives no skin weights, still count."
  (let* ((joints (model-joints model))
         (skeletal (make-array (length joints) :initial-element nil)))
    ;; A joint is part of the skeleton when it or a joint below it is a bone:
    ;; mark each bone and its ancestors, stopping at one already marked.
    (loop for i below (length joints)
          when (joint-inverse-bind (aref joints i))
            do (loop for at = i then (joint-parent (aref joints at))
                     while (and at (not (aref skeletal at)))
                     do (setf (aref skeletal at) t)))
    (let ((kept (loop for i below (length joints) when (aref skeletal i) collect i)))
      (coerce (or kept (loop for i below (length joints) collect i)) 'vector))))

(defun subset-parents (model subset)
  "For each joint of SUBSET (indices into MODEL's joints), the position in
SUBSET of its nearest ancestor there, or -1."
  (let ((joints (model-joints model)))
    (map 'vector (lambda (index)
                   (loop for parent = (joint-parent (aref joints index))
                           then (joint-parent (aref joints parent))
                         while parent
                         do (let ((at (position parent subset)))
                              (when at (return at)))
                         finally (return -1)))
         subset)))

(defun print-model-roles (model)
  "Print the roles guessed from the names of MODEL's bones, one line each (a
chain's joints in order), then the drivers they enable and those they do
not, with the roles each lacks."
  (let* ((subset (role-joints model))
         (names (map 'vector (lambda (index) (joint-name (aref (model-joints model) index))) subset))
         (roles (guess-roles names :parents (subset-parents model subset))))
    (format t "~D guessed role~:P~:[~;:~]~%" (length roles) roles)
    (loop for (role . where) in roles
          do (format t "  ~(~S~): ~{~A~^ ~}~%" role
                     (mapcar (lambda (index) (aref names index)) (ensure-list where))))
    (multiple-value-bind (enabled disabled)
        (roles-enabling-drivers roles :morphs (model-morph-targets model))
      (format t "drivers: ~:[none~;~:*~(~{~A~^, ~}~)~]~%" enabled)
      (loop for (driver . lacking) in disabled
            do (format t "  no ~(~A~): needs ~(~{~S~^ or ~}~)~%" driver lacking)))))
