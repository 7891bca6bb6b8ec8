;;;; package.lisp -- player.model: models artists make (glTF, FBX, COLLADA, .x,
;;;; BVH...), imported through Assimp: meshes, skins, skeletons, animations,
;;;; morph targets and textures, as Lisp data the body and the renderer use.

(defpackage #:player.model
  (:use #:cl #:player.base)
  (:import-from #:alexandria
                #:when-let #:if-let #:ensure-list #:hash-table-keys
                #:with-gensyms #:once-only #:appendf #:read-file-into-string)
  (:documentation "Models artists make, imported through Assimp: meshes, skins, skeletons, animations, morph targets and textures.")
  (:export
   #:guess-roles #:role-error #:role-error-joint #:role-error-role #:roles-enabling-drivers))
