;;;; peedy-poses.lisp -- the poses of Peedy's scripts (specs/peedy-scripts.lisp
;;;; names this file with its (poses ...) form), kept beside his spec.
;;;; Data for PLAYER::LOAD-POSE-LIBRARY; read with *READ-EVAL* NIL, never loaded.
;;;;
;;;; Degrees; signs as in src/body/skeletons/parrot.lisp: +x pitches the
;;;; root, neck and head forward (down), +y turns the head to his left, +z tilts
;;;; its top to his right; +z raises the left wing, -z the right; -x on a
;;;; shoulder swings the wing forward, +x back; the elbows and wrists unfold
;;;; with +; -x raises the tail; the beak opens, the lids close and the crest
;;;; rises with +.  Leg poses were placed by planar forward kinematics so the
;;;; toes stay where they stood: a root pitched forward by A is met by the hips
;;;; turning -A, and a crouch of D metres (the scripts lower (:self position)
;;;; by D) by knees and ankles folding.  Every angle lies within the limits.

;;; ---------------------------------------------------------------------------
;;; Whole-body bases

(defpose neutral-face "Eyes open and level, beak shut, crest resting."
  (l_eye pitch 0 yaw 0) (r_eye pitch 0 yaw 0)
  (:left-upper-lid close 0) (:right-upper-lid close 0)
  (:jaw open 0) (:crest raise 0))

(defpose folded-wings "Both wings folded along the body, primaries closed."
  (l_shoulder x 0 y 0 z 0) (r_shoulder x 0 y 0 z 0)
  (l_elbow unfold 0) (r_elbow unfold 0)
  (l_wrist unfold 0 y 0) (r_wrist unfold 0 y 0)
  (l_primaries spread 0) (r_primaries spread 0))

(defpose right-wing-folded "The right wing folded along the body."
  (r_shoulder x 0 y 0 z 0) (r_elbow unfold 0) (r_wrist unfold 0 y 0) (r_primaries spread 0))

(defpose left-wing-folded "The left wing folded along the body." (:mirror right-wing-folded))

(defpose stand-legs "Legs straight under the body, toes round the perch."
  (l_hip x 0 z 0) (r_hip x 0 z 0) (l_knee x 0) (r_knee x 0)
  (l_ankle x 0) (r_ankle x 0) (l_foot curl 40) (r_foot curl 40))

(defpose stand "Upright and level on straight legs, toes gripping (the wings left as they are)."
  (parrot-root x 0 y 0 z 0)
  (neck x 0 y 0 z 0) (head x 0 y 0 z 0)
  (tail x 0 y 0 spread 0)
  (:include stand-legs))

(defpose sit-legs
  "Legs folded under the body, the root 0.026 m lower (the scripts lower (:self position))."
  (l_hip x -15 z 0) (r_hip x -15 z 0) (l_knee x 45) (r_knee x 45)
  (l_ankle x -50) (r_ankle x -50) (l_foot curl 80) (r_foot curl 80))

(defpose sit "Settled on the table: legs folded, head drawn in a little (the wings left as they are)."
  (parrot-root x 0 y 0 z 0)
  (neck x 8 y 0 z 0) (head x -8 y 0 z 0)
  (:include sit-legs))

(defpose alert "Awake and attentive: head up and level, eyes wide, crest a little up."
  (neck x 0 y 0 z 0) (head x 0 y 0 z 0)
  (:left-upper-lid close 0) (:right-upper-lid close 0)
  (:jaw open 0) (:crest raise 12))

;;; ---------------------------------------------------------------------------
;;; Sleep

(defpose sleep "Deep sleep on the table: head sunk onto the chest, lids shut, crest flat."
  (parrot-root x 4 y 0 z 0)
  (neck x 38 y 0 z 0) (head x 28 y 0 z 6)
  (:left-upper-lid close 70) (:right-upper-lid close 70)
  (l_eye pitch 0 yaw 0) (r_eye pitch 0 yaw 0)
  (:jaw open 0) (:crest raise -8)
  (tail x 6 y 0 spread 0)
  (:include folded-wings)
  (:include sit-legs)
  (l_foot curl 90) (r_foot curl 90))

(defpose sleep-inhale "Deep sleep, breathing in: chest up, head lifted a little, wings out."
  (:include sleep)
  (parrot-root x 1) (neck x 32) (head x 25)
  (l_shoulder z 4) (r_shoulder z -4) (tail x 3))

(defpose sleep-snore "Deep sleep, snoring out: beak open, head rocked down."
  (:include sleep)
  (parrot-root x 5) (neck x 42) (head x 30) (:jaw open 14))

(defpose doze "Dozing: head drooped, lids heavy but not shut, crest down."
  (parrot-root x 2 y 0 z 0)
  (neck x 24 y 0 z 0) (head x 12 y 0 z 3)
  (:left-upper-lid close 56) (:right-upper-lid close 56)
  (l_eye pitch 0 yaw 0) (r_eye pitch 0 yaw 0)
  (:jaw open 0) (:crest raise -4)
  (:include folded-wings)
  (:include sit-legs))

(defpose doze-inhale "Dozing, breathing in: chest and head up a little, lids flickering."
  (:include doze)
  (parrot-root x 0) (neck x 20) (head x 10)
  (:left-upper-lid close 50) (:right-upper-lid close 50)
  (l_shoulder z 3) (r_shoulder z -3))

(defpose doze-sag "Dozing: the head sags lower before it catches itself."
  (:include doze)
  (neck x 32) (head x 18)
  (:left-upper-lid close 64) (:right-upper-lid close 64))

;;; ---------------------------------------------------------------------------
;;; Leaning and crouching (toes planted; see the file header)

(defpose crouch-legs "Knees bent for a crouch of 0.03 m, the body upright."
  (l_hip x -14 z 0) (r_hip x -14 z 0) (l_knee x 54) (r_knee x 54)
  (l_ankle x -50) (r_ankle x -50) (l_foot curl 60) (r_foot curl 60))

(defpose lean-to-note
  "Bent over the table to pick something up in front of the right foot: the
root pitched 15 degrees and turned a little right, the body 0.030 m lower and
0.0105 m forward (as the scripts move (:self position)), the head down."
  (parrot-root x 15 y -8 z 0)
  (neck x 30 y 0 z 0) (head x 20 y 0 z 0)
  (l_hip x -29 z 0) (r_hip x -29 z 0) (l_knee x 54) (r_knee x 54)
  (l_ankle x -50) (r_ankle x -50) (l_foot curl 60) (r_foot curl 60)
  (tail x -10 y 0 spread 10))

(defpose lean-to-phones
  "As lean-to-note, turned a little left instead, to pick up what lies in front of the left foot."
  (:include lean-to-note) (parrot-root y 8))

(defpose pick-up-right
  "The right wing swung forward and down to the table, as it is in lean-to-note
when its tip is on the note (the reach driver's solution for the note at
\(-0.07 0.001 0.09))."
  (r_shoulder x -85.6 y 6.5 z 2.1) (r_elbow unfold 19) (r_wrist unfold 0 y 0) (r_primaries spread 10))

(defpose pick-up-left "The left wing swung down to the table, as lean-to-phones needs." (:mirror pick-up-right))

(defpose point-left
  "The left wing held straight out to his left and a little forward, pointing
\(at the CD title panel beside him)."
  (l_shoulder x -30 y -60 z 80) (l_elbow unfold 0) (l_wrist unfold 0 y 0) (l_primaries spread 5))

;;; ---------------------------------------------------------------------------
;;; The bow

(defpose bow-low
  "The lowest point of the bow: body pitched 28 degrees (the body 0.019 m
forward and 0.002 m lower, as the script moves (:self position)), neck and
head down, wings spread a little, tail up, eyes lowered."
  (parrot-root x 28 y 0 z 0)
  (neck x 24 y 0 z 0) (head x 22 y 0 z 0)
  (l_hip x -28 z 0) (r_hip x -28 z 0) (l_knee x 0) (r_knee x 0) (l_ankle x 0) (r_ankle x 0)
  (l_shoulder x -15 y 0 z 32) (r_shoulder x -15 y 0 z -32)
  (l_elbow unfold 10) (r_elbow unfold 10)
  (l_primaries spread 22) (r_primaries spread 22)
  (tail x -22 y 0 spread 18)
  (:left-upper-lid close 35) (:right-upper-lid close 35))

;;; ---------------------------------------------------------------------------
;;; Wings (wings only, so a script can beat them while another call moves the body)

(defpose wings-spread "Both wings spread out to the sides, primaries fanned."
  (l_shoulder x -20 y 0 z 85) (r_shoulder x -20 y 0 z -85)
  (l_elbow unfold 0) (r_elbow unfold 0) (l_wrist unfold 0 y 0) (r_wrist unfold 0 y 0)
  (l_primaries spread 35) (r_primaries spread 35))

(defpose wings-stretch "A full stretch: wings high over the back, primaries wide open."
  (l_shoulder x 20 y 0 z 125) (r_shoulder x 20 y 0 z -125)
  (l_elbow unfold 0) (r_elbow unfold 0) (l_wrist unfold 0 y 0) (r_wrist unfold 0 y 0)
  (l_primaries spread 40) (r_primaries spread 40))

(defpose fly-up "Top of the wing stroke: both wings raised high, fully open."
  (l_shoulder x -10 y 0 z 140) (r_shoulder x -10 y 0 z -140)
  (l_elbow unfold 0) (r_elbow unfold 0) (l_wrist unfold 0 y 0) (r_wrist unfold 0 y 0)
  (l_primaries spread 30) (r_primaries spread 30))

(defpose fly-down "Bottom of the wing stroke: both wings swept down, primaries closing."
  (l_shoulder x -10 y 0 z 45) (r_shoulder x -10 y 0 z -45)
  (l_elbow unfold 10) (r_elbow unfold 10) (l_wrist unfold 15 y 0) (r_wrist unfold 15 y 0)
  (l_primaries spread 10) (r_primaries spread 10))

(defpose fly-body "In flight: body pitched forward, legs tucked up, head level with the horizon."
  (parrot-root x 25 y 0 z 0)
  (neck x -15 y 0 z 0) (head x -10 y 0 z 0)
  (l_hip x 50 z 0) (r_hip x 50 z 0) (l_knee x 90) (r_knee x 90)
  (l_ankle x -100) (r_ankle x -100) (l_foot curl 85) (r_foot curl 85)
  (tail x -10 y 0 spread 20))

(defpose left-wing-wave-out "The left wing raised high to wave, tip out to the side."
  (l_shoulder x -10 y -30 z 105) (l_elbow unfold 15) (l_wrist unfold 10 y 0) (l_primaries spread 30))

(defpose left-wing-wave-in "The left wing raised high to wave, tip in over the head."
  (l_shoulder x -10 y -30 z 145) (l_elbow unfold 30) (l_wrist unfold 35 y 0) (l_primaries spread 30))

(defpose shrug-wings "Wings lifted a little away from the body, primaries open: who knows?"
  (l_shoulder x -15 y 0 z 30) (r_shoulder x -15 y 0 z -30)
  (l_elbow unfold 25) (r_elbow unfold 25) (l_wrist unfold 20 y 0) (r_wrist unfold 20 y 0)
  (l_primaries spread 30) (r_primaries spread 30))

;;; ---------------------------------------------------------------------------
;;; The face

(defpose beak-open "The beak wide open." (:jaw open 30))
(defpose beak-closed "The beak shut." (:jaw open 0))
(defpose crest-up "The crest raised upright." (:crest raise 50))
(defpose crest-down "The crest flat." (:crest raise 0))
(defpose eyes-shut "Both lids shut." (:left-upper-lid close 70) (:right-upper-lid close 70))
(defpose eyes-open "Both lids open." (:left-upper-lid close 0) (:right-upper-lid close 0))
