;;;; humanoid.lisp -- a human figure: H-Anim level of articulation 1, plus the
;;;; face (eyes, upper lids, brows, jaw) and one curl DOF per finger.
;;;; Data for PLAYER::LOAD-SKELETON; read with *READ-EVAL* NIL, never loaded.
;;;; Format: see src/body/skeleton-files.lisp.  Metres; +y up, +z front, +x
;;;; the figure's left.  Rest pose: standing, arms at the sides, palms in.
;;;;
;;;; Joint centres of the LOA-1 joints are the H-Anim 1.1 reference figure's,
;;;; exactly.  HumanoidRoot is written humanoid-root; the face and finger joints
;;;; take H-Anim 200x names (l_eyeball_joint, l_eyelid_joint, l_eyebrow_joint,
;;;; temporomandibular, l_thumb1 ... l_pinky1); their centres are estimates
;;;; scaled to this figure (interpupillary distance 63 mm).
;;;;
;;;; Limits: active ranges of motion from the AAOS averages ("Joint Motion:
;;;; Method of Measuring and Recording", American Academy of Orthopaedic
;;;; Surgeons, 1965), as tabulated in Norkin & White, "Measurement of Joint
;;;; Motion: A Guide to Goniometry", appendix A:
;;;;   shoulder flexion 180, extension 60, abduction 180, internal rotation 70,
;;;;     external rotation 90; elbow flexion 150; forearm pronation 80,
;;;;     supination 80; wrist flexion 80, extension 70, radial deviation 20,
;;;;     ulnar deviation 30; finger MCP flexion 90, hyperextension 45; thumb
;;;;     MCP flexion 50;
;;;;   hip flexion 120, extension 30, abduction 45, adduction 30, internal and
;;;;     external rotation 45; knee flexion 135; ankle dorsiflexion 20,
;;;;     plantarflexion 50; subtalar inversion 35, eversion 15; first MTP
;;;;     extension 70, flexion 45 (used for the midtarsal joint, which at LOA 1
;;;;     stands for the whole forefoot);
;;;;   cervical spine flexion 45, extension 45, lateral flexion 45, rotation 60
;;;;     (skullbase, which at LOA 1 carries the whole neck); thoracolumbar
;;;;     flexion 80, extension 25, lateral flexion 35, rotation 45 (vl5, which
;;;;     carries the whole trunk).
;;;; Not from a clinical table, and marked "estimate" below: the root (free),
;;;; the sacroiliac (pelvic tilt, a few degrees in life, +-15 allowed for
;;;; posture), the eyes (the oculomotor range is about +-45 to 50 degrees;
;;;; natural gaze stays well inside it), lids, brows and jaw (a 45-50 mm
;;;; incisal opening is about 28 degrees of mandible rotation).
;;;; Signs: a DOF turns right-handed about its axis, so for the legs and arms
;;;; flexion is -x at hip and shoulder, +x at knee, -x at elbow; left-side
;;;; abduction is +z and the right side mirrors it.

(skeleton humanoid
  (:documentation "An H-Anim LOA-1 human, 1.75 m tall, with a face and finger curls.")

  (:joint humanoid-root :parent nil :center (0 0.8240 0.0277) :radius 0.12
          ;; estimate: the whole figure turns freely
          :dofs ((:x -180 180) (:y -180 180) (:z -180 180)))

  ;; Legs
  (:joint sacroiliac :parent humanoid-root :center (0 0.9149 0.0016) :radius 0.12
          :dofs ((:x -15 15) (:y -15 15) (:z -15 15)))          ; estimate
  (:joint l_hip :parent sacroiliac :center (0.0961 0.9124 -0.0001) :radius 0.07
          :dofs ((:x -120 30) (:y -45 45) (:z -30 45)))
  (:joint l_knee :parent l_hip :center (0.1040 0.4867 0.0308) :radius 0.05
          :dofs ((:x 0 135)))
  (:joint l_ankle :parent l_knee :center (0.1101 0.0656 -0.0736) :radius 0.04
          :dofs ((:x -20 50) (:z -35 15)))
  (:joint l_midtarsal :parent l_ankle :center (0.1086 0.0001 0.0368) :radius 0.03
          :dofs ((:x -70 45)))
  (:joint r_hip :parent sacroiliac :center (-0.0950 0.9171 0.0029) :radius 0.07
          :dofs ((:x -120 30) (:y -45 45) (:z -45 30)))
  (:joint r_knee :parent r_hip :center (-0.0867 0.4913 0.0318) :radius 0.05
          :dofs ((:x 0 135)))
  (:joint r_ankle :parent r_knee :center (-0.0801 0.0712 -0.0766) :radius 0.04
          :dofs ((:x -20 50) (:z -15 35)))
  (:joint r_midtarsal :parent r_ankle :center (-0.0801 0 0.0368) :radius 0.03
          :dofs ((:x -70 45)))

  ;; Trunk and head
  (:joint vl5 :parent humanoid-root :center (0.0028 1.0568 -0.0776) :radius 0.13
          :dofs ((:x -25 80) (:y -45 45) (:z -35 35)))
  (:joint skullbase :parent vl5 :center (0.0044 1.6209 0.0236) :radius 0.09
          :dofs ((:x -45 45) (:y -60 60) (:z -45 45)))
  ;; Face; estimates.  +x pitches the gaze down, +y turns it to the figure's left.
  (:joint l_eyeball_joint :parent skullbase :center (0.0359 1.6680 0.1000) :radius 0.012
          :dofs ((:x -35 45 :name pitch) (:y -45 45 :name yaw)))
  (:joint r_eyeball_joint :parent skullbase :center (-0.0271 1.6680 0.1000) :radius 0.012
          :dofs ((:x -35 45 :name pitch) (:y -45 45 :name yaw)))
  ;; An upper lid turns about its eye's centre: 0 open at rest, 60 shut.
  (:joint l_eyelid_joint :parent skullbase :center (0.0359 1.6680 0.1000) :radius 0.013
          :dofs ((:x -15 60 :name close)))
  (:joint r_eyelid_joint :parent skullbase :center (-0.0271 1.6680 0.1000) :radius 0.013
          :dofs ((:x -15 60 :name close)))
  ;; A brow tilts about its own centre: positive raises it.
  (:joint l_eyebrow_joint :parent skullbase :center (0.0374 1.6960 0.1150) :radius 0.005
          :dofs ((:-x -10 20 :name raise)))
  (:joint r_eyebrow_joint :parent skullbase :center (-0.0286 1.6960 0.1150) :radius 0.005
          :dofs ((:-x -10 20 :name raise)))
  (:joint temporomandibular :parent skullbase :center (0.0044 1.6300 0.0500) :radius 0.04
          :dofs ((:x 0 28 :name open) (:y -8 8 :name side)))

  ;; Arms
  (:joint l_shoulder :parent vl5 :center (0.2029 1.4376 -0.0387) :radius 0.045
          :dofs ((:x -180 60) (:y -70 90) (:z -30 180)))
  (:joint l_elbow :parent l_shoulder :center (0.2014 1.1357 -0.0682) :radius 0.035
          ;; y is the forearm's pronation/supination
          :dofs ((:x -150 0) (:y -80 80)))
  (:joint l_wrist :parent l_elbow :center (0.1984 0.8663 -0.0583) :radius 0.03
          ;; palms in: flexion is about z (-z flexes the left hand), deviation about x
          :dofs ((:x -20 30) (:z -80 70)))
  (:joint r_shoulder :parent vl5 :center (-0.1907 1.4407 -0.0325) :radius 0.045
          :dofs ((:x -180 60) (:y -90 70) (:z -180 30)))
  (:joint r_elbow :parent r_shoulder :center (-0.1949 1.1388 -0.0620) :radius 0.035
          :dofs ((:x -150 0) (:y -80 80)))
  (:joint r_wrist :parent r_elbow :center (-0.1959 0.8694 -0.0521) :radius 0.03
          :dofs ((:x -20 30) (:z -70 80)))

  ;; Fingers: one curl DOF each, turning the finger at its knuckle toward the
  ;; palm (-z on the left, +z on the right, so +90 curls either hand shut).  A
  ;; later driver spreads the curl over the finger's three joints.
  (:joint l_thumb1 :parent l_wrist :center (0.1904 0.8363 -0.0283) :radius 0.01
          :dofs ((:-z 0 50 :name curl)))
  (:joint l_index1 :parent l_wrist :center (0.1944 0.7763 -0.0363) :radius 0.008
          :dofs ((:-z -45 90 :name curl)))
  (:joint l_middle1 :parent l_wrist :center (0.1964 0.7713 -0.0563) :radius 0.008
          :dofs ((:-z -45 90 :name curl)))
  (:joint l_ring1 :parent l_wrist :center (0.1954 0.7763 -0.0743) :radius 0.008
          :dofs ((:-z -45 90 :name curl)))
  (:joint l_pinky1 :parent l_wrist :center (0.1924 0.7863 -0.0903) :radius 0.007
          :dofs ((:-z -45 90 :name curl)))
  (:joint r_thumb1 :parent r_wrist :center (-0.1879 0.8394 -0.0221) :radius 0.01
          :dofs ((:z 0 50 :name curl)))
  (:joint r_index1 :parent r_wrist :center (-0.1919 0.7794 -0.0301) :radius 0.008
          :dofs ((:z -45 90 :name curl)))
  (:joint r_middle1 :parent r_wrist :center (-0.1939 0.7744 -0.0501) :radius 0.008
          :dofs ((:z -45 90 :name curl)))
  (:joint r_ring1 :parent r_wrist :center (-0.1929 0.7794 -0.0681) :radius 0.008
          :dofs ((:z -45 90 :name curl)))
  (:joint r_pinky1 :parent r_wrist :center (-0.1899 0.7894 -0.0841) :radius 0.007
          :dofs ((:z -45 90 :name curl)))

  (:role :head skullbase)
  (:role :left-eye l_eyeball_joint)
  (:role :right-eye r_eyeball_joint)
  (:role :left-upper-lid l_eyelid_joint)
  (:role :right-upper-lid r_eyelid_joint)
  (:role :left-brow l_eyebrow_joint)
  (:role :right-brow r_eyebrow_joint)
  (:role :jaw temporomandibular)
  (:role :left-arm (l_shoulder l_elbow l_wrist))
  (:role :right-arm (r_shoulder r_elbow r_wrist))
  (:role :left-hand l_wrist)
  (:role :right-hand r_wrist)
  (:role :left-fingers (l_thumb1 l_index1 l_middle1 l_ring1 l_pinky1))
  (:role :right-fingers (r_thumb1 r_index1 r_middle1 r_ring1 r_pinky1))
  (:role :left-leg (l_hip l_knee l_ankle l_midtarsal))
  (:role :right-leg (r_hip r_knee r_ankle r_midtarsal))
  (:role :spine (vl5 skullbase)))
