;;;; package.lisp -- player.rig: characters brought from models artists make.
;;;; An imported model's joint tree becomes a Player skeleton (whose joints are
;;;; channels every driver can move), its animations become clips that a
;;;; :clip item plays, motion capture is retargeted onto any skeleton by
;;;; roles, and the skin follows the skeleton (the palette the renderer and
;;;; the glTF export use).

(defpackage #:player.rig
  (:use #:cl #:player.base #:player.spec #:player.model #:player.body)
  (:import-from #:alexandria #:when-let #:if-let #:ensure-list #:hash-table-keys)
  (:documentation "Characters from imported models: skeletons and skins made from a model's joints, clips, retargeting.")
  (:export
   #:rig #:rig-p #:rig-model #:rig-placement #:rig-scale #:rig-clips #:rig-bounds #:rig-skins
   #:model-skeleton #:rig-error
   #:prop-model #:prop-model-p #:prop-model-model #:prop-model-skins #:prop-model-placement #:make-prop-model
   #:model-prop #:model-prop-model
   #:moves-root-p #:make-root-motion-control #:root-motion-control #:clip-travel
   #:motion-clip #:motion-clip-p #:clip-name #:clip-duration #:clip-tracks #:find-clip #:rig-clip-names
   #:clip-angles #:clip-joint-indices #:make-animation-clip #:cut-clip #:clip-name-from-animation
   #:mesh-skin #:skin-mesh #:skin-palette-joints #:skin-palette-matrices #:skin-palette
   #:skin-vertices #:skin-rest-positions #:skin-slots #:skin-weights
   #:quat-to-xyz-degrees #:rig-error #:clip-driver #:clip-root-offset #:*clip-resolvers*
   #:make-motion-clip #:make-track #:clip-track #:track-joint #:track-times #:track-quats #:add-rig-clip #:skin-morphs #:clip-morph-tracks #:clip-morph-weight #:rig-morph-base
   #:clip-root-times #:clip-root-offsets #:clip-source
   #:clip-dof-angles #:clip-layouts #:joint-dof-layout #:dof-layout
   #:retarget-clip #:retargeted-clip #:clip-file-clip #:clip-file-source))
