;;;; parrot.lisp -- Peedy, the parrot of Microsoft Research's Persona project.
;;;; Data for PLAYER::LOAD-SKELETON; read with *READ-EVAL* NIL, never loaded.
;;;; Format: see src/body/skeleton-files.lisp.  Metres; +y up, +z the bird's
;;;; front (its beak), +x its left.  Rest pose: perched upright, wings folded
;;;; along the body, about 0.35 m from the feet to the top of the crest.
;;;;
;;;; Proportions and limits are estimates for a cartoon parrot of that size, not
;;;; measurements: parrots turn the head far (about 90 degrees each way between
;;;; neck and head here), move the eyes only a little (+-15), open the beak to
;;;; about 35 degrees, and raise the wings past the vertical when they flap.
;;;; The wings are arm chains (shoulder, elbow, wrist) with the primaries as the
;;;; "hand", so arm and hand drivers written for the humanoid drive them too.

(skeleton parrot
  (:documentation "Peedy the parrot: head, beak, eyes, lids, crest, wings, tail, legs.")

  (:joint parrot-root :parent nil :center (0 0.1400 0) :radius 0.06
          :dofs ((:x -180 180) (:y -180 180) (:z -180 180)))

  ;; Neck and head
  (:joint neck :parent parrot-root :center (0 0.2200 0.0200) :radius 0.035
          :dofs ((:x -45 60) (:y -45 45) (:z -30 30)))
  (:joint head :parent neck :center (0 0.2750 0.0350) :radius 0.04
          :dofs ((:x -45 60) (:y -90 90) (:z -45 45)))
  ;; The lower mandible hinges under the eyes; +x opens the beak.
  (:joint beak :parent head :center (0 0.2780 0.0750) :radius 0.015
          :dofs ((:x 0 35 :name open)))
  (:joint l_eye :parent head :center (0.0250 0.2950 0.0550) :radius 0.008
          :dofs ((:x -15 15 :name pitch) (:y -15 15 :name yaw)))
  (:joint r_eye :parent head :center (-0.0250 0.2950 0.0550) :radius 0.008
          :dofs ((:x -15 15 :name pitch) (:y -15 15 :name yaw)))
  (:joint l_lid :parent head :center (0.0250 0.2950 0.0550) :radius 0.009
          :dofs ((:x -10 70 :name close)))
  (:joint r_lid :parent head :center (-0.0250 0.2950 0.0550) :radius 0.009
          :dofs ((:x -10 70 :name close)))
  ;; The crest feathers lie back at rest and rise toward the vertical.
  (:joint crest :parent head :center (0 0.3150 0.0300) :radius 0.012
          :dofs ((:-x -10 60 :name raise)))

  ;; Wings: +z raises the left wing (the right mirrors it); the elbow and wrist
  ;; unfold the wing, the primaries spread at its tip.
  (:joint l_shoulder :parent parrot-root :center (0.0400 0.2000 0) :radius 0.02
          :dofs ((:x -90 90) (:y -60 60) (:z -20 150)))
  (:joint l_elbow :parent l_shoulder :center (0.0500 0.1500 -0.0300) :radius 0.015
          :dofs ((:x -10 150 :name unfold)))
  (:joint l_wrist :parent l_elbow :center (0.0500 0.1100 -0.0600) :radius 0.012
          :dofs ((:x -10 160 :name unfold) (:y -30 30)))
  (:joint l_primaries :parent l_wrist :center (0.0450 0.0500 -0.1000) :radius 0.01
          :dofs ((:-z 0 40 :name spread)))
  (:joint r_shoulder :parent parrot-root :center (-0.0400 0.2000 0) :radius 0.02
          :dofs ((:x -90 90) (:y -60 60) (:z -150 20)))
  (:joint r_elbow :parent r_shoulder :center (-0.0500 0.1500 -0.0300) :radius 0.015
          :dofs ((:x -10 150 :name unfold)))
  (:joint r_wrist :parent r_elbow :center (-0.0500 0.1100 -0.0600) :radius 0.012
          :dofs ((:x -10 160 :name unfold) (:y -30 30)))
  (:joint r_primaries :parent r_wrist :center (-0.0450 0.0500 -0.1000) :radius 0.01
          :dofs ((:z 0 40 :name spread)))

  ;; Tail: -x raises it, y sweeps it, spread fans the feathers.
  (:joint tail :parent parrot-root :center (0 0.0900 -0.0500) :radius 0.02
          :dofs ((:x -45 30) (:y -30 30) (:z 0 30 :name spread)))

  ;; Legs: hip, knee (tibiotarsus), ankle (tarsometatarsus), toes gripping the perch.
  (:joint l_hip :parent parrot-root :center (0.0250 0.1000 0.0050) :radius 0.015
          :dofs ((:x -60 60) (:z -20 30)))
  (:joint l_knee :parent l_hip :center (0.0300 0.0600 0.0150) :radius 0.01
          :dofs ((:x 0 120)))
  (:joint l_ankle :parent l_knee :center (0.0300 0.0300 -0.0050) :radius 0.008
          :dofs ((:x -120 0)))
  (:joint l_foot :parent l_ankle :center (0.0300 0.0050 0.0150) :radius 0.006
          :dofs ((:x 0 90 :name curl)))
  (:joint r_hip :parent parrot-root :center (-0.0250 0.1000 0.0050) :radius 0.015
          :dofs ((:x -60 60) (:z -30 20)))
  (:joint r_knee :parent r_hip :center (-0.0300 0.0600 0.0150) :radius 0.01
          :dofs ((:x 0 120)))
  (:joint r_ankle :parent r_knee :center (-0.0300 0.0300 -0.0050) :radius 0.008
          :dofs ((:x -120 0)))
  (:joint r_foot :parent r_ankle :center (-0.0300 0.0050 0.0150) :radius 0.006
          :dofs ((:x 0 90 :name curl)))

  (:role :head head)
  (:role :left-eye l_eye)
  (:role :right-eye r_eye)
  (:role :left-upper-lid l_lid)
  (:role :right-upper-lid r_lid)
  (:role :jaw beak)
  (:role :crest crest)
  (:role :tail tail)
  (:role :left-arm (l_shoulder l_elbow l_wrist))
  (:role :right-arm (r_shoulder r_elbow r_wrist))
  (:role :left-hand l_primaries)
  (:role :right-hand r_primaries)
  (:role :left-leg (l_hip l_knee l_ankle l_foot))
  (:role :right-leg (r_hip r_knee r_ankle r_foot))
  (:role :spine (neck head)))
