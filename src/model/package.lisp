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
   #:import-model #:model-error #:model-error-file #:model-library-missing
   #:*model-post-processing* #:*model-vertex-limit* #:*model-triangle-limit*
   #:*model-joint-limit* #:*model-key-limit* #:*model-node-limit*
   #:model #:model-p #:model-file #:model-meshes #:model-joints #:model-animations
   #:model-vertex-count #:model-triangle-count #:model-bone-count #:model-textures
   #:model-morph-targets #:find-model-joint
   #:model-mesh #:model-mesh-name #:model-mesh-positions #:model-mesh-normals #:model-mesh-uvs #:model-mesh-colours
   #:model-mesh-triangles #:model-mesh-joints #:model-mesh-weights #:model-mesh-bones #:model-mesh-texture
   #:model-mesh-morph-targets #:model-mesh-morphs #:morph-target #:make-morph-target #:morph-target-name #:morph-target-deltas
   #:model-animation-morph-channels #:morph-channel #:morph-channel-node #:morph-channel-meshes
   #:morph-channel-times #:morph-channel-weights #:morph-channel-target-count #:make-morph-channel #:model-mesh-holder #:model-mesh-transform #:model-mesh-vertex-count #:model-mesh-triangle-count
   #:model-joint #:joint-name #:joint-parent #:joint-translation #:joint-rotation #:joint-scale
   #:joint-inverse-bind
   #:model-animation #:model-animation-name #:model-animation-duration #:model-animation-channels
   #:model-channel #:channel-joint #:channel-position-times #:channel-positions
   #:channel-rotation-times #:channel-rotations #:channel-scale-times #:channel-scales
   #:copy-model #:make-model #:make-model-mesh #:make-joint #:make-model-animation #:make-channel
   #:write-gltf #:model-write-error
   #:read-image #:image #:image-p #:image-width #:image-height #:image-channels #:image-pixels
   #:image-error #:image-error-file #:image-error-reason #:image-library-missing
   #:*image-pixel-limit* #:model-texture-images #:mesh-texture-image #:decode-image-octets
   #:model-embedded-textures #:embedded-texture #:embedded-texture-name #:embedded-texture-octets
   #:embedded-texture-image #:model-mesh-embedded-texture #:embedded-texture-p
   #:guess-roles #:role-error #:role-error-joint #:role-error-role #:roles-enabling-drivers))
