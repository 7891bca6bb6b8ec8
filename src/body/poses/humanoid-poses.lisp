;;;; humanoid-poses.lisp -- the poses shipped for the humanoid skeleton.
;;;; Data for LOAD-POSE-LIBRARY; read with *READ-EVAL* NIL, never loaded.
;;;; Format: see src/body/pose-library.lisp.  Degrees; signs as in
;;;; skeletons/humanoid.lisp: shoulder flexion is -x, left abduction +z (the
;;;; right side mirrors it), elbow flexion -x, trunk and neck flexion +x, a
;;;; finger curl of 90 closes it.  Every angle lies within the joint limits
;;;; (the tests check); arm poses were placed by forward kinematics.

(defpose neutral
  "Standing at ease: trunk and head straight, arms hanging, elbows and fingers a little bent."
  (:spine x 0 y 0 z 0)
  (:left-arm x 0) (:right-arm x 0)
  (l_shoulder y 0 z 0) (r_shoulder y 0 z 0)
  (l_elbow x -10 y 0) (r_elbow x -10 y 0)
  (l_wrist z 0) (r_wrist z 0)
  (:left-fingers curl 20) (:right-fingers curl 20))

;;; Hand shapes: partial poses over the fingers alone, so they layer over any arm pose.

(defpose left-fist "The left hand closed, the thumb over the fingers."
  (:left-fingers curl 45)
  (l_index1 curl 90) (l_middle1 curl 90) (l_ring1 curl 90) (l_pinky1 curl 90))
(defpose right-fist "The right hand closed." (:mirror left-fist))
(defpose fist "Both hands closed." (:include left-fist) (:mirror left-fist))

(defpose left-open "The left hand open flat, the fingers a little bent back."
  (:left-fingers curl 0)
  (l_index1 curl -10) (l_middle1 curl -10) (l_ring1 curl -10) (l_pinky1 curl -10))
(defpose right-open "The right hand open flat." (:mirror left-open))
(defpose open "Both hands open flat." (:include left-open) (:mirror left-open))

(defpose left-point "The left index finger straight, the others closed."
  (:include left-fist) (l_index1 curl 0))
(defpose right-point "The right index finger straight, the others closed." (:mirror left-point))

;;; Arm poses

(defpose left-hand-on-hip
  "The left hand on the hip, the elbow out to the side and a little back."
  (l_shoulder x 40 y -40 z 35)
  (l_elbow x -80 y 0)
  (l_wrist x 0 z 0))
(defpose right-hand-on-hip "The right hand on the hip." (:mirror left-hand-on-hip))
(defpose hands-on-hips "Both hands on the hips, elbows out."
  (:include left-hand-on-hip) (:mirror left-hand-on-hip))

(defpose arms-raised "Both arms raised overhead in a V, elbows nearly straight."
  (l_shoulder x -20 y 0 z 155)
  (r_shoulder x -20 y 0 z -155)
  (l_elbow x -10 y 0) (r_elbow x -10 y 0))

(defpose bow-down "A bow from the waist: trunk and head forward, arms hanging plumb."
  (vl5 x 45 y 0 z 0)
  (skullbase x 20 y 0 z 0)
  (l_shoulder x -40 y 0 z 0) (r_shoulder x -40 y 0 z 0)
  (l_elbow x -10) (r_elbow x -10))
