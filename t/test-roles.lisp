;;;; test-roles.lisp -- guessed roles (src/model/roles.lisp, naming-schemes.lisp,
;;;; driver-needs.lisp): one realistic skeleton per naming scheme with the
;;;; roles it should get, explicit roles,
;;;; sides never swapped, the drivers the roles enable, and Player's own
;;;; skeletons guessed to the roles their files declare.

(in-package #:player-tests)

(def-suite* roles :in player-tests)

;;; ---------------------------------------------------------------------------
;;; Skeletons, written as (JOINT PARENT-OR-NIL) in import order

(defparameter *mixamo-skeleton*
  '(("mixamorig:Hips" nil)
    ("mixamorig:Spine" "mixamorig:Hips") ("mixamorig:Spine1" "mixamorig:Spine")
    ("mixamorig:Spine2" "mixamorig:Spine1") ("mixamorig:Neck" "mixamorig:Spine2")
    ("mixamorig:Head" "mixamorig:Neck") ("mixamorig:HeadTop_End" "mixamorig:Head")
    ("mixamorig:LeftEye" "mixamorig:Head") ("mixamorig:RightEye" "mixamorig:Head")
    ("mixamorig:LeftShoulder" "mixamorig:Spine2") ("mixamorig:LeftArm" "mixamorig:LeftShoulder")
    ("mixamorig:LeftForeArm" "mixamorig:LeftArm") ("mixamorig:LeftHand" "mixamorig:LeftForeArm")
    ("mixamorig:LeftHandThumb1" "mixamorig:LeftHand") ("mixamorig:LeftHandThumb2" "mixamorig:LeftHandThumb1")
    ("mixamorig:LeftHandThumb3" "mixamorig:LeftHandThumb2") ("mixamorig:LeftHandThumb4" "mixamorig:LeftHandThumb3")
    ("mixamorig:LeftHandIndex1" "mixamorig:LeftHand") ("mixamorig:LeftHandIndex2" "mixamorig:LeftHandIndex1")
    ("mixamorig:LeftHandIndex3" "mixamorig:LeftHandIndex2") ("mixamorig:LeftHandIndex4" "mixamorig:LeftHandIndex3")
    ("mixamorig:LeftHandMiddle1" "mixamorig:LeftHand") ("mixamorig:LeftHandMiddle2" "mixamorig:LeftHandMiddle1")
    ("mixamorig:LeftHandRing1" "mixamorig:LeftHand") ("mixamorig:LeftHandRing2" "mixamorig:LeftHandRing1")
    ("mixamorig:LeftHandPinky1" "mixamorig:LeftHand") ("mixamorig:LeftHandPinky2" "mixamorig:LeftHandPinky1")
    ("mixamorig:RightShoulder" "mixamorig:Spine2") ("mixamorig:RightArm" "mixamorig:RightShoulder")
    ("mixamorig:RightForeArm" "mixamorig:RightArm") ("mixamorig:RightHand" "mixamorig:RightForeArm")
    ("mixamorig:RightHandThumb1" "mixamorig:RightHand") ("mixamorig:RightHandThumb2" "mixamorig:RightHandThumb1")
    ("mixamorig:RightHandIndex1" "mixamorig:RightHand") ("mixamorig:RightHandIndex2" "mixamorig:RightHandIndex1")
    ("mixamorig:RightHandMiddle1" "mixamorig:RightHand") ("mixamorig:RightHandRing1" "mixamorig:RightHand")
    ("mixamorig:RightHandPinky1" "mixamorig:RightHand") ("mixamorig:RightHandPinky2" "mixamorig:RightHandPinky1")
    ("mixamorig:LeftUpLeg" "mixamorig:Hips") ("mixamorig:LeftLeg" "mixamorig:LeftUpLeg")
    ("mixamorig:LeftFoot" "mixamorig:LeftLeg") ("mixamorig:LeftToeBase" "mixamorig:LeftFoot")
    ("mixamorig:LeftToe_End" "mixamorig:LeftToeBase")
    ("mixamorig:RightUpLeg" "mixamorig:Hips") ("mixamorig:RightLeg" "mixamorig:RightUpLeg")
    ("mixamorig:RightFoot" "mixamorig:RightLeg") ("mixamorig:RightToeBase" "mixamorig:RightFoot")
    ("mixamorig:RightToe_End" "mixamorig:RightToeBase")))

(defparameter *mixamo-roles*
  '((:head . "mixamorig:Head") (:neck . "mixamorig:Neck") (:hips . "mixamorig:Hips")
    (:left-eye . "mixamorig:LeftEye") (:right-eye . "mixamorig:RightEye")
    (:left-arm "mixamorig:LeftArm" "mixamorig:LeftForeArm" "mixamorig:LeftHand")
    (:right-arm "mixamorig:RightArm" "mixamorig:RightForeArm" "mixamorig:RightHand")
    (:left-hand . "mixamorig:LeftHand") (:right-hand . "mixamorig:RightHand")
    (:left-fingers "mixamorig:LeftHandThumb1" "mixamorig:LeftHandIndex1" "mixamorig:LeftHandMiddle1"
     "mixamorig:LeftHandRing1" "mixamorig:LeftHandPinky1")
    (:right-fingers "mixamorig:RightHandThumb1" "mixamorig:RightHandIndex1" "mixamorig:RightHandMiddle1"
     "mixamorig:RightHandRing1" "mixamorig:RightHandPinky1")
    (:left-leg "mixamorig:LeftUpLeg" "mixamorig:LeftLeg" "mixamorig:LeftFoot" "mixamorig:LeftToeBase")
    (:right-leg "mixamorig:RightUpLeg" "mixamorig:RightLeg" "mixamorig:RightFoot" "mixamorig:RightToeBase")
    (:spine "mixamorig:Spine" "mixamorig:Spine1" "mixamorig:Spine2" "mixamorig:Neck" "mixamorig:Head")))

;;; Blender's Rigify human metarig (the legacy spine names).
(defparameter *rigify-skeleton*
  '(("hips" nil) ("spine" "hips") ("chest" "spine") ("neck" "chest") ("head" "neck")
    ("eye.L" "head") ("eye.R" "head") ("jaw" "head")
    ("shoulder.L" "chest") ("upper_arm.L" "shoulder.L") ("forearm.L" "upper_arm.L") ("hand.L" "forearm.L")
    ("palm.01.L" "hand.L") ("finger_index.01.L" "palm.01.L") ("finger_index.02.L" "finger_index.01.L")
    ("thumb.01.L" "palm.01.L") ("thumb.02.L" "thumb.01.L")
    ("palm.02.L" "hand.L") ("finger_middle.01.L" "palm.02.L")
    ("palm.03.L" "hand.L") ("finger_ring.01.L" "palm.03.L")
    ("palm.04.L" "hand.L") ("finger_pinky.01.L" "palm.04.L")
    ("shoulder.R" "chest") ("upper_arm.R" "shoulder.R") ("forearm.R" "upper_arm.R") ("hand.R" "forearm.R")
    ("thumb.01.R" "hand.R") ("finger_index.01.R" "hand.R")
    ("thigh.L" "hips") ("shin.L" "thigh.L") ("foot.L" "shin.L") ("toe.L" "foot.L") ("heel.L" "shin.L")
    ("thigh.R" "hips") ("shin.R" "thigh.R") ("foot.R" "shin.R") ("toe.R" "foot.R") ("heel.R" "shin.R")))

(defparameter *rigify-roles*
  '((:head . "head") (:neck . "neck") (:hips . "hips") (:left-eye . "eye.L") (:right-eye . "eye.R")
    (:jaw . "jaw")
    (:left-arm "upper_arm.L" "forearm.L" "hand.L") (:right-arm "upper_arm.R" "forearm.R" "hand.R")
    (:left-hand . "hand.L") (:right-hand . "hand.R")
    (:left-fingers "thumb.01.L" "finger_index.01.L" "finger_middle.01.L" "finger_ring.01.L"
     "finger_pinky.01.L")
    (:right-fingers "thumb.01.R" "finger_index.01.R")
    (:left-leg "thigh.L" "shin.L" "foot.L" "toe.L") (:right-leg "thigh.R" "shin.R" "foot.R" "toe.R")
    (:spine "spine" "chest" "neck" "head")))

;;; 3ds Max Biped.
(defparameter *biped-skeleton*
  '(("Bip01" nil) ("Bip01 Pelvis" "Bip01") ("Bip01 Spine" "Bip01 Pelvis")
    ("Bip01 Spine1" "Bip01 Spine") ("Bip01 Spine2" "Bip01 Spine1") ("Bip01 Neck" "Bip01 Spine2")
    ("Bip01 Head" "Bip01 Neck") ("Bip01 HeadNub" "Bip01 Head")
    ("Bip01 L Clavicle" "Bip01 Neck") ("Bip01 L UpperArm" "Bip01 L Clavicle")
    ("Bip01 L Forearm" "Bip01 L UpperArm") ("Bip01 L Hand" "Bip01 L Forearm")
    ("Bip01 L Finger0" "Bip01 L Hand") ("Bip01 L Finger01" "Bip01 L Finger0")
    ("Bip01 L Finger02" "Bip01 L Finger01") ("Bip01 L Finger1" "Bip01 L Hand")
    ("Bip01 L Finger11" "Bip01 L Finger1") ("Bip01 L Finger2" "Bip01 L Hand")
    ("Bip01 L Finger3" "Bip01 L Hand") ("Bip01 L Finger4" "Bip01 L Hand")
    ("Bip01 R Clavicle" "Bip01 Neck") ("Bip01 R UpperArm" "Bip01 R Clavicle")
    ("Bip01 R Forearm" "Bip01 R UpperArm") ("Bip01 R Hand" "Bip01 R Forearm")
    ("Bip01 R Finger0" "Bip01 R Hand") ("Bip01 R Finger01" "Bip01 R Finger0")
    ("Bip01 R Finger1" "Bip01 R Hand")
    ("Bip01 L Thigh" "Bip01 Spine") ("Bip01 L Calf" "Bip01 L Thigh") ("Bip01 L Foot" "Bip01 L Calf")
    ("Bip01 L Toe0" "Bip01 L Foot") ("Bip01 L Toe0Nub" "Bip01 L Toe0")
    ("Bip01 R Thigh" "Bip01 Spine") ("Bip01 R Calf" "Bip01 R Thigh") ("Bip01 R Foot" "Bip01 R Calf")
    ("Bip01 R Toe0" "Bip01 R Foot") ("Bip01 R Toe0Nub" "Bip01 R Toe0")
    ("Bip01 Ponytail1" "Bip01 Head")))

(defparameter *biped-roles*
  '((:head . "Bip01 Head") (:neck . "Bip01 Neck") (:hips . "Bip01 Pelvis")
    (:left-arm "Bip01 L UpperArm" "Bip01 L Forearm" "Bip01 L Hand")
    (:right-arm "Bip01 R UpperArm" "Bip01 R Forearm" "Bip01 R Hand")
    (:left-hand . "Bip01 L Hand") (:right-hand . "Bip01 R Hand")
    (:left-fingers "Bip01 L Finger0" "Bip01 L Finger1" "Bip01 L Finger2" "Bip01 L Finger3"
     "Bip01 L Finger4")
    (:right-fingers "Bip01 R Finger0" "Bip01 R Finger1")
    (:left-leg "Bip01 L Thigh" "Bip01 L Calf" "Bip01 L Foot" "Bip01 L Toe0")
    (:right-leg "Bip01 R Thigh" "Bip01 R Calf" "Bip01 R Foot" "Bip01 R Toe0")
    (:spine "Bip01 Spine" "Bip01 Spine1" "Bip01 Spine2" "Bip01 Neck" "Bip01 Head")))

;;; The CMU motion capture database as BVH (the cgspeed conversion).
(defparameter *cmu-skeleton*
  '(("Hips" nil) ("LHipJoint" "Hips") ("LeftUpLeg" "LHipJoint") ("LeftLeg" "LeftUpLeg")
    ("LeftFoot" "LeftLeg") ("LeftToeBase" "LeftFoot")
    ("RHipJoint" "Hips") ("RightUpLeg" "RHipJoint") ("RightLeg" "RightUpLeg")
    ("RightFoot" "RightLeg") ("RightToeBase" "RightFoot")
    ("LowerBack" "Hips") ("Spine" "LowerBack") ("Spine1" "Spine") ("Neck" "Spine1")
    ("Neck1" "Neck") ("Head" "Neck1")
    ("LeftShoulder" "Spine1") ("LeftArm" "LeftShoulder") ("LeftForeArm" "LeftArm")
    ("LeftHand" "LeftForeArm") ("LeftFingerBase" "LeftHand") ("LeftHandIndex1" "LeftFingerBase")
    ("LThumb" "LeftHand")
    ("RightShoulder" "Spine1") ("RightArm" "RightShoulder") ("RightForeArm" "RightArm")
    ("RightHand" "RightForeArm") ("RightFingerBase" "RightHand") ("RightHandIndex1" "RightFingerBase")
    ("RThumb" "RightHand")))

(defparameter *cmu-roles*
  '((:head . "Head") (:neck . "Neck") (:hips . "Hips")
    (:left-arm "LeftArm" "LeftForeArm" "LeftHand") (:right-arm "RightArm" "RightForeArm" "RightHand")
    (:left-hand . "LeftHand") (:right-hand . "RightHand")
    (:left-fingers "LThumb" "LeftHandIndex1") (:right-fingers "RThumb" "RightHandIndex1")
    (:left-leg "LeftUpLeg" "LeftLeg" "LeftFoot" "LeftToeBase")
    (:right-leg "RightUpLeg" "RightLeg" "RightFoot" "RightToeBase")
    (:spine "Spine" "Spine1" "Neck" "Neck1" "Head")))

;;; H-Anim, level of articulation 2 (a part of its spine and hands).
(defparameter *h-anim-skeleton*
  '(("humanoid_root" nil) ("sacroiliac" "humanoid_root")
    ("l_hip" "sacroiliac") ("l_knee" "l_hip") ("l_ankle" "l_knee") ("l_subtalar" "l_ankle")
    ("l_midtarsal" "l_subtalar") ("l_metatarsal" "l_midtarsal")
    ("r_hip" "sacroiliac") ("r_knee" "r_hip") ("r_ankle" "r_knee") ("r_subtalar" "r_ankle")
    ("r_midtarsal" "r_subtalar") ("r_metatarsal" "r_midtarsal")
    ("vl5" "humanoid_root") ("vl1" "vl5") ("vt10" "vl1") ("vt6" "vt10") ("vt1" "vt6")
    ("vc4" "vt1") ("skullbase" "vc4")
    ("l_eyeball_joint" "skullbase") ("r_eyeball_joint" "skullbase")
    ("l_eyelid_joint" "skullbase") ("r_eyelid_joint" "skullbase")
    ("l_eyebrow_joint" "skullbase") ("r_eyebrow_joint" "skullbase")
    ("temporomandibular" "skullbase")
    ("l_sternoclavicular" "vt1") ("l_acromioclavicular" "l_sternoclavicular")
    ("l_shoulder" "l_acromioclavicular") ("l_elbow" "l_shoulder") ("l_wrist" "l_elbow")
    ("l_thumb1" "l_wrist") ("l_thumb2" "l_thumb1") ("l_index1" "l_wrist") ("l_index2" "l_index1")
    ("l_middle1" "l_wrist") ("l_ring1" "l_wrist") ("l_pinky1" "l_wrist")
    ("r_sternoclavicular" "vt1") ("r_acromioclavicular" "r_sternoclavicular")
    ("r_shoulder" "r_acromioclavicular") ("r_elbow" "r_shoulder") ("r_wrist" "r_elbow")
    ("r_thumb1" "r_wrist") ("r_index1" "r_wrist")))

(defparameter *h-anim-roles*
  '((:head . "skullbase") (:neck . "vc4") (:hips . "humanoid_root")
    (:left-eye . "l_eyeball_joint") (:right-eye . "r_eyeball_joint")
    (:left-upper-lid . "l_eyelid_joint") (:right-upper-lid . "r_eyelid_joint")
    (:left-brow . "l_eyebrow_joint") (:right-brow . "r_eyebrow_joint") (:jaw . "temporomandibular")
    (:left-arm "l_shoulder" "l_elbow" "l_wrist") (:right-arm "r_shoulder" "r_elbow" "r_wrist")
    (:left-hand . "l_wrist") (:right-hand . "r_wrist")
    (:left-fingers "l_thumb1" "l_index1" "l_middle1" "l_ring1" "l_pinky1")
    (:right-fingers "r_thumb1" "r_index1")
    (:left-leg "l_hip" "l_knee" "l_ankle" "l_midtarsal") (:right-leg "r_hip" "r_knee" "r_ankle" "r_midtarsal")
    (:spine "vl5" "vl1" "vt10" "vt6" "vt1" "vc4" "skullbase")))

;;; VRM 1.0 humanoid bones.
(defparameter *vrm-skeleton*
  '(("hips" nil) ("spine" "hips") ("chest" "spine") ("upperChest" "chest") ("neck" "upperChest")
    ("head" "neck") ("leftEye" "head") ("rightEye" "head") ("jaw" "head")
    ("leftShoulder" "upperChest") ("leftUpperArm" "leftShoulder") ("leftLowerArm" "leftUpperArm")
    ("leftHand" "leftLowerArm") ("leftThumbMetacarpal" "leftHand") ("leftThumbProximal" "leftThumbMetacarpal")
    ("leftThumbDistal" "leftThumbProximal") ("leftIndexProximal" "leftHand")
    ("leftIndexIntermediate" "leftIndexProximal") ("leftMiddleProximal" "leftHand")
    ("leftRingProximal" "leftHand") ("leftLittleProximal" "leftHand")
    ("rightShoulder" "upperChest") ("rightUpperArm" "rightShoulder") ("rightLowerArm" "rightUpperArm")
    ("rightHand" "rightLowerArm") ("rightThumbMetacarpal" "rightHand") ("rightIndexProximal" "rightHand")
    ("rightMiddleProximal" "rightHand") ("rightRingProximal" "rightHand") ("rightLittleProximal" "rightHand")
    ("leftUpperLeg" "hips") ("leftLowerLeg" "leftUpperLeg") ("leftFoot" "leftLowerLeg") ("leftToes" "leftFoot")
    ("rightUpperLeg" "hips") ("rightLowerLeg" "rightUpperLeg") ("rightFoot" "rightLowerLeg")
    ("rightToes" "rightFoot")))

(defparameter *vrm-roles*
  '((:head . "head") (:neck . "neck") (:hips . "hips") (:left-eye . "leftEye") (:right-eye . "rightEye")
    (:jaw . "jaw")
    (:left-arm "leftUpperArm" "leftLowerArm" "leftHand") (:right-arm "rightUpperArm" "rightLowerArm" "rightHand")
    (:left-hand . "leftHand") (:right-hand . "rightHand")
    (:left-fingers "leftThumbMetacarpal" "leftIndexProximal" "leftMiddleProximal" "leftRingProximal"
     "leftLittleProximal")
    (:right-fingers "rightThumbMetacarpal" "rightIndexProximal" "rightMiddleProximal" "rightRingProximal"
     "rightLittleProximal")
    (:left-leg "leftUpperLeg" "leftLowerLeg" "leftFoot" "leftToes")
    (:right-leg "rightUpperLeg" "rightLowerLeg" "rightFoot" "rightToes")
    (:spine "spine" "chest" "upperChest" "neck" "head")))

;;; Names people write by hand: separators, case and side markers varying.
(defparameter *plain-skeleton*
  '(("root" nil) ("Pelvis" "root") ("Spine" "Pelvis") ("Chest" "Spine") ("Neck" "Chest")
    ("Head" "Neck") ("Jaw" "Head") ("eye.l" "Head") ("eye.r" "Head")
    ("Arm_Left" "Chest") ("Forearm_Left" "Arm_Left") ("Hand_Left" "Forearm_Left")
    ("R_Arm" "Chest") ("R-Elbow" "R_Arm") ("Hand_R" "R-Elbow")
    ("LegL" "Pelvis") ("KneeL" "LegL") ("FootL" "KneeL")
    ("right leg" "Pelvis") ("right shin" "right leg") ("right foot" "right shin")))

(defparameter *plain-roles*
  '((:head . "Head") (:neck . "Neck") (:hips . "Pelvis") (:jaw . "Jaw")
    (:left-eye . "eye.l") (:right-eye . "eye.r")
    (:left-arm "Arm_Left" "Forearm_Left" "Hand_Left") (:right-arm "R_Arm" "R-Elbow" "Hand_R")
    (:left-hand . "Hand_Left") (:right-hand . "Hand_R")
    (:left-leg "LegL" "KneeL" "FootL") (:right-leg "right leg" "right shin" "right foot")
    (:spine "Spine" "Chest" "Neck" "Head")))

;;; Unreal Engine's mannequin: lower-case names, _l and _r, numbers written apart.
(defparameter *unreal-skeleton*
  '(("root" nil) ("pelvis" "root") ("spine_01" "pelvis") ("spine_02" "spine_01") ("spine_03" "spine_02")
    ("clavicle_l" "spine_03") ("upperarm_l" "clavicle_l") ("lowerarm_l" "upperarm_l") ("hand_l" "lowerarm_l")
    ("index_01_l" "hand_l") ("index_02_l" "index_01_l") ("middle_01_l" "hand_l") ("pinky_01_l" "hand_l")
    ("ring_01_l" "hand_l") ("thumb_01_l" "hand_l") ("thumb_02_l" "thumb_01_l")
    ("lowerarm_twist_01_l" "lowerarm_l") ("upperarm_twist_01_l" "upperarm_l")
    ("clavicle_r" "spine_03") ("upperarm_r" "clavicle_r") ("lowerarm_r" "upperarm_r") ("hand_r" "lowerarm_r")
    ("thumb_01_r" "hand_r") ("lowerarm_twist_01_r" "lowerarm_r")
    ("neck_01" "spine_03") ("head" "neck_01")
    ("thigh_l" "pelvis") ("calf_l" "thigh_l") ("calf_twist_01_l" "calf_l") ("foot_l" "calf_l") ("ball_l" "foot_l")
    ("thigh_twist_01_l" "thigh_l")
    ("thigh_r" "pelvis") ("calf_r" "thigh_r") ("foot_r" "calf_r") ("ball_r" "foot_r")
    ("ik_foot_root" "root") ("ik_foot_l" "ik_foot_root") ("ik_foot_r" "ik_foot_root")
    ("ik_hand_root" "root") ("ik_hand_gun" "ik_hand_root") ("ik_hand_l" "ik_hand_gun")
    ("ik_hand_r" "ik_hand_gun")))

(defparameter *unreal-roles*
  '((:head . "head") (:neck . "neck_01") (:hips . "pelvis")
    (:left-arm "upperarm_l" "lowerarm_l" "hand_l") (:right-arm "upperarm_r" "lowerarm_r" "hand_r")
    (:left-hand . "hand_l") (:right-hand . "hand_r")
    (:left-fingers "thumb_01_l" "index_01_l" "middle_01_l" "ring_01_l" "pinky_01_l")
    (:right-fingers "thumb_01_r")
    (:left-leg "thigh_l" "calf_l" "foot_l" "ball_l") (:right-leg "thigh_r" "calf_r" "foot_r" "ball_r")
    (:spine "spine_01" "spine_02" "spine_03" "neck_01" "head")))

;;; Debian's assimp test models, the joints `assimp info` lists (their meshes'
;;; nodes left out).  Testwuson is a dog: its legs are named HindLeg and ForeLeg,
;;; which no human scheme has, so only its neck, pelvis and tail are roles.
(defparameter *testwuson-skeleton*
  '(("Root" nil) ("Spine_Back01" "Root") ("Spine_Back02" "Spine_Back01")
    ("Spine_Back03" "Spine_Back02") ("Pelvis" "Spine_Back03")
    ("Tail01" "Pelvis") ("Tail02" "Tail01") ("Tail03" "Tail02") ("Tail04" "Tail03")
    ("Tail05" "Tail04") ("Tail06" "Tail05")
    ("HindLeg_L_01" "Pelvis") ("HindLeg_L_02" "HindLeg_L_01") ("HindLeg_L_03" "HindLeg_L_02")
    ("HindLeg_L_04" "HindLeg_L_03")
    ("HindLeg_R_01" "Pelvis") ("HindLeg_R_02" "HindLeg_R_01") ("HindLeg_R_03" "HindLeg_R_02")
    ("HindLeg_R_04" "HindLeg_R_03")
    ("Spine_Front01" "Root") ("Spine_Front02" "Spine_Front01") ("Spine_Front03" "Spine_Front02")
    ("Spine_Front04" "Spine_Front03") ("Spine_Front05" "Spine_Front04") ("Neck" "Spine_Front05")
    ("Ear_L" "Neck") ("Mouth" "Neck") ("Ear_R" "Neck")
    ("ForeLeg_L_01" "Spine_Front03") ("ForeLeg_L_02" "ForeLeg_L_01") ("ForeLeg_L_03" "ForeLeg_L_02")
    ("ForeLeg_L_04" "ForeLeg_L_03") ("ForeLeg_L_05" "ForeLeg_L_04")
    ("ForeLeg_R_01" "Spine_Front03") ("ForeLeg_R_02" "ForeLeg_R_01") ("ForeLeg_R_03" "ForeLeg_R_02")
    ("ForeLeg_R_04" "ForeLeg_R_03") ("ForeLeg_R_05" "ForeLeg_R_04")))

(defparameter *testwuson-roles*
  '((:neck . "Neck") (:hips . "Pelvis") (:tail . "Tail01")))

;;; BCN_Epileptic's root is B_Root_Pelvis_L, whose L is no side but reads as
;;; one: no name gives the hips, so the one root is taken for them.  Its head
;;; joint is B_Neck (the eyes hang off it), so the neck is found, not the head.
(defparameter *bcn-skeleton*
  '(("B_Root_Pelvis_L" nil) ("B_LowerPelvis" "B_Root_Pelvis_L")
    ("B_Hip_Left" "B_LowerPelvis") ("B_Knee_Left" "B_Hip_Left") ("B_Ankle_Left" "B_Knee_Left")
    ("B_Toe_Left" "B_Ankle_Left")
    ("B_Hip_Right" "B_LowerPelvis") ("B_Knee_Right" "B_Hip_Right") ("B_Ankle_Right" "B_Knee_Right")
    ("B_Toe_Right" "B_Ankle_Right")
    ("B_Root_Pelvis_T" "B_Root_Pelvis_L") ("B_Spine1" "B_Root_Pelvis_T") ("B_Spine2" "B_Spine1")
    ("B_Spine3" "B_Spine2") ("B_Spine4" "B_Spine3")
    ("B_Clavicle_Left" "B_Spine4") ("B_UpperArm_Left" "B_Clavicle_Left")
    ("B_ForeArm_Left" "B_UpperArm_Left") ("B_Hand_Left" "B_ForeArm_Left")
    ("B_Finger1_Left" "B_Hand_Left") ("B_Finger2_Left" "B_Finger1_Left") ("B_Finger3_Left" "B_Finger2_Left")
    ("B_Thumb1_Left" "B_Hand_Left") ("B_Thumb2_Left" "B_Thumb1_Left")
    ("B_Clavicle_Right" "B_Spine4") ("B_UpperArm_Right" "B_Clavicle_Right")
    ("B_ForeArm_Right" "B_UpperArm_Right") ("B_Hand_Right" "B_ForeArm_Right")
    ("B_Thumb1_Right" "B_Hand_Right") ("B_Thumb2_Right" "B_Thumb1_Right")
    ("B_Finger1_Right" "B_Hand_Right") ("B_Finger2_Right" "B_Finger1_Right") ("B_Finger3_Right" "B_Finger2_Right")
    ("B_Root_Neck_T" "B_Spine4") ("B_Root_Neck_H" "B_Root_Neck_T") ("B_Neck" "B_Root_Neck_H")
    ("B_PTail1" "B_Neck") ("B_PTail2" "B_PTail1") ("B_PTail3" "B_PTail2")
    ("B_UpperLip" "B_Neck") ("B_Jaw" "B_Neck") ("B_LowerLip" "B_Jaw")
    ("B_MouthCorner_Left" "B_Neck") ("B_EyeBrow_Left" "B_Neck") ("B_UpperEyeLid_Left" "B_Neck")
    ("B_LowerEyeLid_Left" "B_Neck") ("B_Eye_Left" "B_Neck") ("B_Eye_Right" "B_Neck")
    ("B_LowerEyeLid_Right" "B_Neck") ("B_UpperEyeLid_Right" "B_Neck") ("B_EyeBrow_Right" "B_Neck")
    ("B_MouthCorner_Right" "B_Neck") ("B_Cheek_Left" "B_Neck") ("B_Cheek_Right" "B_Neck")))

(defparameter *bcn-roles*
  '((:neck . "B_Neck") (:hips . "B_Root_Pelvis_L") (:jaw . "B_Jaw")
    (:left-eye . "B_Eye_Left") (:right-eye . "B_Eye_Right")
    (:left-upper-lid . "B_UpperEyeLid_Left") (:right-upper-lid . "B_UpperEyeLid_Right")
    (:left-brow . "B_EyeBrow_Left") (:right-brow . "B_EyeBrow_Right")
    (:left-arm "B_UpperArm_Left" "B_ForeArm_Left" "B_Hand_Left")
    (:right-arm "B_UpperArm_Right" "B_ForeArm_Right" "B_Hand_Right")
    (:left-hand . "B_Hand_Left") (:right-hand . "B_Hand_Right")
    (:left-fingers "B_Thumb1_Left" "B_Finger1_Left") (:right-fingers "B_Thumb1_Right" "B_Finger1_Right")
    (:left-leg "B_Hip_Left" "B_Knee_Left" "B_Ankle_Left" "B_Toe_Left")
    (:right-leg "B_Hip_Right" "B_Knee_Right" "B_Ankle_Right" "B_Toe_Right")
    (:spine "B_Spine1" "B_Spine2" "B_Spine3" "B_Spine4" "B_Root_Neck_T" "B_Root_Neck_H" "B_Neck")))

(defparameter *role-cases*
  '((mixamo *mixamo-skeleton* *mixamo-roles*) (rigify *rigify-skeleton* *rigify-roles*)
    (biped *biped-skeleton* *biped-roles*) (cmu *cmu-skeleton* *cmu-roles*)
    (h-anim *h-anim-skeleton* *h-anim-roles*) (vrm *vrm-skeleton* *vrm-roles*)
    (plain *plain-skeleton* *plain-roles*) (unreal *unreal-skeleton* *unreal-roles*)
    (testwuson *testwuson-skeleton* *testwuson-roles*)
    (bcn-epileptic *bcn-skeleton* *bcn-roles*))
  "Each scheme's case: (NAME SKELETON-VARIABLE EXPECTED-ROLES-VARIABLE).")

;;; ---------------------------------------------------------------------------
;;; Helpers

(defun skeleton-names (skeleton)
  "The joint names of SKELETON, a list of (JOINT PARENT), as a vector."
  (map 'vector #'first skeleton))

(defun skeleton-parents (skeleton)
  "The parent indices of SKELETON's joints, -1 for the root, as a vector."
  (map 'vector (lambda (entry)
                 (if (second entry) (position (second entry) skeleton :key #'first :test #'equal) -1))
       skeleton))

(defun roles-by-name (roles names)
  "ROLES (indices) with each index replaced by its name from NAMES."
  (mapcar (lambda (entry)
            (cons (car entry)
                  (if (listp (cdr entry))
                      (mapcar (lambda (index) (aref names index)) (cdr entry))
                      (aref names (cdr entry)))))
          roles))

(defun guessed-role-names (skeleton &key (parents t) explicit)
  "SKELETON's guessed roles, by joint name; without its parents when PARENTS is NIL."
  (let ((names (skeleton-names skeleton)))
    (roles-by-name (player.model:guess-roles names :parents (and parents (skeleton-parents skeleton))
                                                   :explicit explicit)
                   names)))

(defun same-roles-p (expected actual)
  "Do the alists EXPECTED and ACTUAL name the same roles with the same joints?"
  (and (= (length expected) (length actual))
       (every (lambda (entry) (equal (cdr entry) (cdr (assoc (car entry) actual)))) expected)))

(defun left-marked-p (name side)
  "Does the joint NAME say it is on SIDE (:left or :right)?  Written apart from the
guesser: the side's word anywhere, or its letter standing alone or before a
capital (LThumb, Bip01 L Hand, eye.l, Hand_R)."
  (let* ((word (if (eq side :left) "left" "right"))
         (letter (char word 0))
         (words (uiop:split-string name :separator "_-.: ")))
    (or (search word (string-downcase name))
        (some (lambda (w) (and (= (length w) 1) (char-equal (char w 0) letter))) words)
        (some (lambda (w) (and (> (length w) 1) (char-equal (char w 0) letter)
                               (upper-case-p (char w 0)) (upper-case-p (char w 1))))
              words)
        (some (lambda (w) (and (> (length w) 1)
                               (char-equal (char w (1- (length w))) letter)
                               (upper-case-p (char w (1- (length w))))
                               (lower-case-p (char w (- (length w) 2)))))
              words))))

;;; ---------------------------------------------------------------------------
;;; Tests

(test normalised-joint-names
  (loop for (name core side) in '(("mixamorig:LeftForeArm" "forearm" :left) ("Bip01 L Toe0" "toe0" :left)
                                  ("spine.001" "spine1" nil) ("upper_arm.R" "upperarm" :right)
                                  ("l_eyeball_joint" "eyeballjoint" :left) ("LThumb" "thumb" :left)
                                  ("ArmL" "arm" :left) ("arm.l" "arm" :left) ("Hand_R" "hand" :right)
                                  ("leftarm" "arm" :left) ("Bip01 L Finger01" "finger01" :left)
                                  ("HUMANOID-ROOT" "humanoidroot" nil) ("B_Spine1" "spine1" nil)
                                  ("Leftover" "over" :left) ("L_Arm_R" nil nil)
                                  ("DEF-forearm.L" "forearm" :left) ("ORG-forearm.L" "orgforearm" :left)
                                  ("mixamorig_LeftHand" "hand" :left) ("neck_01" "neck1" nil))
        do (multiple-value-bind (c s) (player.model::normalised-joint-name name)
             (is (equal core c) "~S normalised to ~S, not ~S" name c core)
             (is (eq side s) "~S's side is ~S, not ~S" name s side))))

(test roles-per-scheme
  (loop for (scheme skeleton expected) in *role-cases*
        for actual = (guessed-role-names (symbol-value skeleton))
        do (is (same-roles-p (symbol-value expected) actual)
               "~A: guessed ~S~%expected ~S" scheme actual (symbol-value expected))))

(test roles-without-parents
  ;; Joints listed parent first, as importers list them, give the same roles
  ;; without the parent links for the schemes whose names are unambiguous
  ;; (not Biped's: without parents its thumb's Finger01 comes before Finger1).
  (dolist (case '((*mixamo-skeleton* *mixamo-roles*) (*rigify-skeleton* *rigify-roles*)
                  (*vrm-skeleton* *vrm-roles*) (*h-anim-skeleton* *h-anim-roles*)
                  (*unreal-skeleton* *unreal-roles*)))
    (is (same-roles-p (symbol-value (second case))
                      (guessed-role-names (symbol-value (first case)) :parents nil))
        "~A without parents" (first case)))
  (is (same-roles-p '((:left-arm "arm.l" "forearm.l" "hand.l") (:right-arm "ArmR" "ForearmR" "HandR")
                      (:left-hand . "hand.l") (:right-hand . "HandR"))
                    (guessed-role-names '(("arm.l") ("forearm.l") ("hand.l") ("ArmR") ("ForearmR") ("HandR"))
                                        :parents nil))))

(test roles-never-swap-sides
  (loop for (scheme skeleton) in *role-cases*
        do (loop for (role . target) in (guessed-role-names (symbol-value skeleton))
                 for side = (cond ((search "LEFT-" (symbol-name role)) :left)
                                  ((search "RIGHT-" (symbol-name role)) :right))
                 when side
                   do (dolist (name (alexandria:ensure-list target))
                        (is (left-marked-p name side) "~A: ~S of ~S is not marked ~(~A~)"
                            scheme name role side)
                        (is (not (left-marked-p name (if (eq side :left) :right :left)))
                            "~A: ~S of ~S is marked the other side" scheme name role)))))

(test roles-unknown-names-give-none
  (is (null (player.model:guess-roles
             #("Armature" "Bone" "Bone.001" "Cube" "Leftover" "Lamp" "Forehead" "Headlight"
               "Shoulderpad_L" "Handle" "Rarm" "Armor_L" "L_Arm_R")))))

(test roles-explicit-win
  (let* ((skeleton *mixamo-skeleton*)
         (roles (guessed-role-names skeleton
                                    :explicit '((:head . "mixamorig:HeadTop_End")
                                                (:left-arm "mixamorig:LeftShoulder" "mixamorig:LeftArm"
                                                 "mixamorig:LeftForeArm")
                                                (:jaw . "mixamorig:head")))))
    (is (equal "mixamorig:HeadTop_End" (cdr (assoc :head roles))))
    (is (equal '("mixamorig:LeftShoulder" "mixamorig:LeftArm" "mixamorig:LeftForeArm")
               (cdr (assoc :left-arm roles))))
    (is (equal "mixamorig:Head" (cdr (assoc :jaw roles))) "names match ignoring case")
    (is (= 1 (count :head roles :key #'car)))
    (is (equal "mixamorig:Neck" (cdr (assoc :neck roles))) "the other guesses stay")))

(test roles-missing-explicit-joint
  (let ((condition (handler-case (player.model:guess-roles (skeleton-names *mixamo-skeleton*)
                                                           :explicit '((:jaw . "mixamorig:Jaw")))
                     (player.model:role-error (c) c))))
    (is (typep condition 'player.base:player-error))
    (is (eq :jaw (player.model:role-error-role condition)))
    (is (equal "mixamorig:Jaw" (player.model:role-error-joint condition)))
    (let ((report (princ-to-string condition)))
      (is (search "JAW" report))
      (is (search "mixamorig:Jaw" report))))
  (signals player.model:role-error
    (player.model:guess-roles #("Head") :explicit '((:left-arm "Head" "LeftForeArm")))))

(defun guessed-drivers (skeleton &key morphs)
  "The drivers SKELETON's guessed roles enable, and those they leave disabled."
  (player.model:roles-enabling-drivers
   (player.model:guess-roles (skeleton-names skeleton) :parents (skeleton-parents skeleton))
   :morphs morphs))

(test roles-enable-drivers
  (multiple-value-bind (enabled disabled) (guessed-drivers *mixamo-skeleton*)
    (is (equal '(:gaze :head :facing :reach) enabled))
    (is (equal '((:visemes :jaw :mouth-morphs) (:blink :left-upper-lid :right-upper-lid :blink-morphs))
               disabled)))
  (multiple-value-bind (enabled disabled)
      (guessed-drivers *mixamo-skeleton* :morphs '("viseme_aa" "viseme_O" "eyeBlink_L" "eyeBlink_R"))
    (is (equal '(:gaze :head :facing :reach :visemes :blink) enabled))
    (is (null disabled)))
  (multiple-value-bind (enabled disabled) (guessed-drivers *testwuson-skeleton*)
    (is (equal '(:facing) enabled))
    (is (equal '((:gaze :left-eye :right-eye :head) (:head :head) (:reach :left-arm :right-arm)
                 (:visemes :jaw :mouth-morphs) (:blink :left-upper-lid :right-upper-lid :blink-morphs))
               disabled)))
  (multiple-value-bind (enabled disabled) (guessed-drivers *bcn-skeleton*)
    (is (equal '(:gaze :facing :reach :visemes :blink) enabled))
    (is (equal '((:head :head)) disabled)))
  (is (equal '(:visemes) (player.model:roles-enabling-drivers '() :morphs '("A" "I" "U" "E" "O")))))

(defun players-skeleton-roles (name)
  "Two values for Player's skeleton NAME: the roles its file declares and the
roles guessed from its joints, each an alist from role to joint name(s)."
  (let* ((skeleton (player.body::load-skeleton name))
         (joints (player.body::skeleton-joints skeleton))
         (names (map 'vector (lambda (joint) (symbol-name (player.body::body-joint-name joint))) joints))
         (parents (map 'vector (lambda (joint)
                                 (let ((parent (player.body::body-joint-parent joint)))
                                   (if parent (player.body::body-joint-index parent) -1)))
                       joints)))
    (flet ((joint-name (joint) (symbol-name (player.body::body-joint-name joint))))
      (values (loop for role in (player.body::skeleton-role-names skeleton)
                    for target = (player.body::skeleton-role skeleton role)
                    collect (cons role (if (listp target) (mapcar #'joint-name target) (joint-name target))))
              (roles-by-name (player.model:guess-roles names :parents parents) names)))))

(test roles-of-players-skeletons
  ;; Player's own skeletons (H-Anim names, uppercase as their files are read)
  ;; are guessed to every role their files declare, but the parrot's hands: its
  ;; wing tips, named primaries, which no scheme calls a hand.
  (dolist (case '((humanoid) (parrot :left-hand :right-hand)))
    (multiple-value-bind (declared guessed) (players-skeleton-roles (first case))
      (loop for (role . target) in declared
            unless (member role (rest case))
              do (is (equal target (cdr (assoc role guessed)))
                     "~(~A~) ~S: declared ~S, guessed ~S" (first case) role target
                     (cdr (assoc role guessed))))
      (is (equal (if (eq (first case) 'humanoid) "HUMANOID-ROOT" "PARROT-ROOT")
                 (cdr (assoc :hips guessed)))
          "the root turns for facing"))))
