;;;; parrot-poses.lisp -- the poses shipped for Peedy, the parrot skeleton.
;;;; Data for LOAD-POSE-LIBRARY; read with *READ-EVAL* NIL, never loaded.
;;;; Format: see src/body/pose-library.lisp.  Degrees; signs as in
;;;; skeletons/parrot.lisp: +x pitches the neck and head down, +z raises the
;;;; left wing (-z the right), -x raises the tail, the beak opens +x, the
;;;; crest and lids rise and close with positive angles.  Every angle lies
;;;; within the joint limits (the tests check); wing poses were placed by
;;;; forward kinematics.

(defpose stand "Upright on the perch, wings folded, head level."
  (parrot-root x 0 y 0 z 0)
  (neck x 0 y 0 z 0) (head x 0 y 0 z 0)
  (l_shoulder x 0 y 0 z 0) (r_shoulder x 0 y 0 z 0)
  (l_elbow unfold 0) (r_elbow unfold 0) (l_wrist unfold 0 y 0) (r_wrist unfold 0 y 0)
  (l_hip x 0 z 0) (r_hip x 0 z 0) (l_knee x 0) (r_knee x 0) (l_ankle x 0) (r_ankle x 0)
  (l_foot curl 40) (r_foot curl 40))

(defpose perch-sit "Settled low on the perch: legs folded, toes gripping, head drawn in."
  (l_hip x -15) (r_hip x -15)
  (l_knee x 45) (r_knee x 45)
  (l_ankle x -50) (r_ankle x -50)
  (l_foot curl 80) (r_foot curl 80)
  (neck x 15) (head x -10))

(defpose left-wing-spread "The left wing spread out to the side, primaries fanned."
  (l_shoulder x -20 y 0 z 85)
  (l_elbow unfold 0) (l_wrist unfold 0 y 0)
  (l_primaries spread 35))
(defpose wings-spread "Both wings spread out to the sides, the tail fanned."
  (:include left-wing-spread) (:mirror left-wing-spread)
  (tail spread 20))

(defpose wing-to-ear-right
  "The right wing tip cupped at the right side of the head (approximate; the reach driver places it exactly)."
  (r_shoulder x 90 y 30 z -60)
  (r_elbow unfold 90)
  (r_wrist unfold 50 y 0))
(defpose wing-to-ear-left "The left wing tip at the left side of the head." (:mirror wing-to-ear-right))

(defpose bow "A bow: the body tips forward, neck and head down, the tail up."
  (parrot-root x 25)
  (neck x 20) (head x 20)
  (tail x -15))

(defpose beak-open "The beak wide open." (:jaw open 30))
(defpose beak-closed "The beak shut." (:jaw open 0))

(defpose crest-up "The crest raised upright." (:crest raise 50))
(defpose crest-down "The crest flat." (:crest raise 0))

(defpose sleep-tuck "Asleep: head sunk, lids shut, crest flat, toes locked on the perch."
  (neck x 40) (head x 30 y 0 z 0)
  (:left-upper-lid close 70) (:right-upper-lid close 70)
  (:crest raise -5)
  (l_foot curl 90) (r_foot curl 90))

;;; Wing beats: alternate them with the keyframe driver, e.g.
;;; (:keyframe :keys ((0 fly-down) (0.15 fly-up) (0.3 fly-down)) :loop t)

(defpose left-fly-up "Top of the left wing's stroke: raised high, fully open."
  (l_shoulder x -10 y 0 z 140)
  (l_elbow unfold 0) (l_wrist unfold 0 y 0)
  (l_primaries spread 30))
(defpose fly-up "Top of the wing stroke: both wings raised high, the tail fanned."
  (:include left-fly-up) (:mirror left-fly-up) (tail spread 25))

(defpose left-fly-down "Bottom of the left wing's stroke: below the horizontal, primaries closed."
  (l_shoulder x -10 y 0 z 50)
  (l_elbow unfold 0) (l_wrist unfold 0 y 0)
  (l_primaries spread 10))
(defpose fly-down "Bottom of the wing stroke: both wings swept down."
  (:include left-fly-down) (:mirror left-fly-down) (tail spread 25))
