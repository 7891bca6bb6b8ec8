;;;; peedy-scripts.lisp -- the script library of specs/peedy.lisp: a motion for
;;;; every op, autoscript and director Peedy's controller plays, on the parrot
;;;; skeleton (src/body/skeletons/parrot.lisp), with his scene.
;;;; The language is described at the top of src/performance/scripts/scripts.lisp.
;;;;
;;;; The scene: the world origin is the table top Peedy stands on (feet at
;;;; y = 0, his front +z, his left +x).  The camera looks at him along -z.
;;;;
;;;; Conventions that make the ops chain without jumps:
;;;; - Each script lasts exactly its op's :duration (bin/player check compares).
;;;; - Postures live in (:self position) and the legs: standing is the body at
;;;;   the origin, sitting 0.026 m lower with sit-legs, flying hovers at
;;;;   (0 0.25 0); the ops that change posture start from and end on these, and
;;;;   those that move in place (bow, hop, the lean of a search) come back to them.
;;;;   A channel nobody drives keeps its angle, so a posture persists.
;;;; - Gestures key their last frame at :start, so they return to whatever
;;;;   Peedy was doing (a note held in the right wing stays held).
;;;; - Autoscripts loop at priority 5, under every op (10 and up): an op takes
;;;;   the channels it needs and the loop resumes when it lets them go.
;;;; - Within a script, calls that share channels are staggered (:for) or at
;;;;   different priorities: between equal priorities the earlier call keeps them.
;;;; - Camera ops start from the home framing (0 0.25 1.1), looking along -z.
;;;; - Controls take absolute keys, so what leaves his wing (drop-note,
;;;;   give-note, play-cd, take-off-phones) flies from where the wing holds it
;;;;   when he stands, as he does whenever those ops run after a search.
;;;; Angles are degrees (signs: see peedy-poses.lisp); times seconds.

(poses "peedy-poses.lisp")

;;; Starting poses: the first whose state expression holds in the controller's
;;; initial state is Peedy's pose before anything plays (else his rest pose),
;;; at the position the posture's scripts leave him in.
(:pose-when posture.sit sit :position (0 -0.026 0))
(:pose-when posture.fly fly-body :position (0 0.25 0))

;;; ---------------------------------------------------------------------------
;;; The scene

(defobject table
  :kind :prop :position (0 -0.02 0)
  :properties ((colour :colour (0.55 0.38 0.22)) (size :vector (1.8 0.04 1.2)))
  :documentation "The table: its top face is the world's y = 0, where Peedy stands.")

(defobject note
  :kind :prop :position (-0.07 0.001 0.09) :dynamic t
  :properties ((colour :colour (1 1 0.85)) (size :vector (0.06 0.002 0.08)))
  :documentation "The note a search finds, lying on the table by his right foot; dropped, it falls (physics).")

(defobject phones
  :kind :prop :position (0.07 0.012 0.09)
  :properties ((colour :colour (0.15 0.15 0.18)) (size :vector (0.07 0.024 0.05)))
  :documentation "Headphones lying on the table by his left foot.")

(defobject jukebox
  :kind :prop :position (-0.45 0.2 -0.15)
  :properties ((colour :colour (0.7 0.2 0.15)) (size :vector (0.25 0.4 0.2))
               (playing :boolean nil))
  :documentation "The CD jukebox standing on the table behind him to his right (its centre half its height up); PLAYING while music plays.")

(defobject cd-title
  :kind :prop :position (0.3 0.25 0.1)
  :properties ((colour :colour (0.9 0.9 1)) (size :vector (0.16 0.08 0.005)))
  :documentation "The panel showing the found CD's title, to his left, facing the camera.")

(defobject camera
  :kind :camera :position (0 0.25 1.1)
  :properties ((fov :number 35))
  :documentation "The camera: at home it looks along -z at Peedy, 1.1 m away.")

(defobject user
  :kind :group :position (0 0.3 1.5)
  :documentation "Where the user sits, behind the camera: Peedy's gaze target.")

(defobject key-light
  :kind :light :position (0.8 1.2 1.0)
  :properties ((colour :colour (1 0.95 0.85)) (intensity :number 1)))

(defobject fill-light
  :kind :light :position (-1.0 0.6 0.8)
  :properties ((colour :colour (0.6 0.7 1)) (intensity :number 0.4)))

;;; ---------------------------------------------------------------------------
;;; Autoscripts (looping at priority 5 while their state value holds)

(defscript snore-loop (:duration 3 :loop t
                       :documentation "Deep sleep on the table: slow breaths of chest and neck, a snore with the beak rattling open.")
  ;; A snoring parrot is settled: the legs folded, the body at sitting height.
  (:at 0 :set (:self position) (:vec3 0 -0.026 0))
  ;; :blend 0: asleep from the first frame, and no crossfade between iterations,
  ;; which meet at the same pose.
  (:at 0 :motor (:keyframe :keys ((0 sleep) (1.3 sleep-inhale) (1.9 sleep-snore) (2.4 sleep-snore) (3 sleep))
                           :priority 5 :blend 0))
  (:at 0 :motor (:keyframe :keys ((0 ((:jaw open 0))) (1.75 ((:jaw open 1))) (1.95 ((:jaw open 15)))
                                  (2.05 ((:jaw open 9))) (2.15 ((:jaw open 16))) (2.25 ((:jaw open 10)))
                                  (2.4 ((:jaw open 13))) (2.9 ((:jaw open 0))))
                           :interpolation :linear :priority 5 :blend 0)))

(defscript doze-breathe (:duration 2.5 :loop t
                         :documentation "Dozing: shallow breaths, the head sagging and catching itself, lids heavy.")
  (:at 0 :set (:self position) (:vec3 0 -0.026 0))
  (:at 0 :motor (:keyframe :keys ((0 doze) (0.9 doze-inhale) (1.7 doze-sag) (2.5 doze))
                           :priority 5 :blend 0)))

(defscript flap-wings (:duration 0.4 :loop t
                       :documentation "Wing beats in flight: down, up, down again.")
  (:at 0 :motor (:keyframe :keys ((0 fly-down) (0.2 fly-up) (0.4 fly-down)) :priority 5)))

(defscript tap-foot (:duration 1 :loop t :beats 2
                     :documentation "Music is playing: the right toes tap the beat (two a loop, at the track's tempo), the tail wags with it.")
  (:at 0 :motor (:keyframe :keys ((0 ((r_foot curl 40))) (0.12 ((r_foot curl 5))) (0.25 ((r_foot curl 40)))
                                  (0.62 ((r_foot curl 5))) (0.75 ((r_foot curl 40))) (1 ((r_foot curl 40))))
                           :priority 5))
  (:at 0 :motor (:keyframe :keys ((0 ((tail y 0))) (0.25 ((tail y 10))) (0.5 ((tail y 0)))
                                  (0.75 ((tail y -10))) (1 ((tail y 0))))
                           :priority 5)))

(defscript bob-head (:duration 0.8 :loop t :beats 2
                     :documentation "Headphones on: the head bobs to the music (two nods a loop, at its tempo), eyes half closed.")
  (:at 0 :motor (:keyframe :keys ((0 ((neck x 2) (head x -2) (:left-upper-lid close 25) (:right-upper-lid close 25)))
                                  (0.2 ((neck x 14) (head x 6)))
                                  (0.4 ((neck x 2) (head x -2)))
                                  (0.6 ((neck x 14) (head x 6)))
                                  (0.8 ((neck x 2) (head x -2))))
                           :priority 5)))

;;; ---------------------------------------------------------------------------
;;; Waking and sleeping

(defscript snort (:duration 1
                  :documentation "Snorting awake: the head snaps up, the beak pops open, the lids flash open, the wings twitch.")
  (:at 0 :motor (:keyframe :keys ((0 :start)
                                  (0.12 ((parrot-root x 6) (neck x 40) (head x 30)))
                                  (0.3 ((parrot-root x -3) (neck x 2) (head x -14) (head z 0)
                                        (:left-upper-lid close 15) (:right-upper-lid close 15)
                                        (:crest raise 35) (tail x -12)
                                        (l_shoulder z 14) (r_shoulder z -14)))
                                  (0.55 ((parrot-root x 0) (neck x 10) (head x -4)
                                         (:left-upper-lid close 35) (:right-upper-lid close 35)
                                         (:crest raise 12) (tail x 0)
                                         (l_shoulder z 0) (r_shoulder z 0)))
                                  (1 ((parrot-root x 1) (neck x 14) (head x 2)
                                      (:left-upper-lid close 45) (:right-upper-lid close 45)
                                      (:crest raise 6))))
                           :priority 20))
  (:at 0 :motor (:keyframe :keys ((0 :start) (0.26 ((:jaw open 0))) (0.32 ((:jaw open 24)))
                                  (0.45 ((:jaw open 6))) (0.6 ((:jaw open 0))))
                           :interpolation :linear :priority 20)))

(defscript exhale (:duration 0.75
                   :documentation "A long breath out: the beak opens, the chest sinks, the head sags a little, lids heavy.")
  (:at 0 :motor (:keyframe :keys ((0 :start)
                                  (0.45 ((parrot-root x 5) (neck x 22) (head x 8)
                                         (:left-upper-lid close 42) (:right-upper-lid close 42)
                                         (:crest raise 0) (tail x 4)))
                                  (0.75 ((parrot-root x 2) (neck x 16) (head x 4)
                                         (:left-upper-lid close 36) (:right-upper-lid close 36))))
                           :priority 20))
  (:at 0 :motor (:keyframe :keys ((0 :start) (0.2 ((:jaw open 12))) (0.55 ((:jaw open 7))) (0.75 ((:jaw open 0))))
                           :priority 20)))

(defscript focus (:duration 0.75
                  :documentation "Eyes open and head up, he looks into the camera; the crest lifts.")
  (:at 0 :motor (:keyframe :keys ((0 :start) (0.5 alert) (0.75 ((parrot-root x 0) (tail x 0) (:crest raise 10))))
                           :priority 20))
  (:at 0.15 :motor (:gaze :target (:object camera)))
  ;; Above the keyframe's priority, so the crest pops and settles back.
  (:at 0.4 :motor (:eyebrows :raise 0.5 :duration 0.12 :hold 0.1 :priority 25)))

(defscript blink (:duration 0.25
                  :documentation "A slow, deliberate blink out of a doze, the head lifting.")
  (:at 0 :motor (:keyframe :keys ((0 :start) (0.1 ((:left-upper-lid close 70) (:right-upper-lid close 70) (neck x 20)))
                                  (0.25 ((:left-upper-lid close 5) (:right-upper-lid close 5) (neck x 14) (head x 4))))
                           :priority 20)))

(defscript stretch (:duration 1.25
                    :documentation "A full stretch: wings high and wide, neck long, beak agape, then everything folds back.")
  (:at 0 :motor (:keyframe :keys ((0 :start)
                                  (0.45 ((:include wings-stretch) (tail x -15 spread 25) (neck x -18) (head x -12)
                                         (:left-upper-lid close 45) (:right-upper-lid close 45) (:crest raise 40)))
                                  (0.8 ((:include wings-stretch) (l_shoulder z 130) (r_shoulder z -130)
                                        (neck x -22) (head x -14) (:crest raise 45)))
                                  (1.25 ((:include folded-wings) (tail x 0 spread 0) (neck x 4) (head x 0)
                                         (:left-upper-lid close 5) (:right-upper-lid close 5) (:crest raise 8))))
                           :priority 20))
  (:at 0.2 :motor (:keyframe :keys ((0 :start) (0.35 ((:jaw open 22))) (0.7 ((:jaw open 18))) (0.95 ((:jaw open 0))))
                             :priority 20)))

(defscript doze (:duration 2
                 :documentation "Eyes closing on the perch: the lids droop, the head nods and catches itself, the crest goes down.")
  (:at 0 :motor (:keyframe :keys ((0 :start)
                                  (0.6 ((neck x 14) (head x 6)
                                        (:left-upper-lid close 38) (:right-upper-lid close 38) (:crest raise 4)))
                                  (0.85 ((neck x 6) (head x 0)
                                         (:left-upper-lid close 18) (:right-upper-lid close 18)))
                                  (1.5 ((neck x 20) (head x 10)
                                        (:left-upper-lid close 50) (:right-upper-lid close 50)))
                                  (2 doze))
                           :priority 10)))

(defscript nod-off (:duration 1.5
                    :documentation "From a doze into deep sleep: the head sinks, jerks up once, sinks for good; lids shut.")
  (:at 0 :motor (:keyframe :keys ((0 :start) (0.5 doze-sag)
                                  (0.7 ((neck x 16) (head x 6) (:left-upper-lid close 40) (:right-upper-lid close 40)))
                                  (1.5 sleep))
                           :priority 10)))

;;; ---------------------------------------------------------------------------
;;; Posture

(defscript standup (:duration 1.5
                    :documentation "Up from sitting: lean forward over the feet, push up on the legs, wings out for balance, settle.")
  (:at 0 :motor (:keyframe :keys ((0 :start)
                                  (0.5 ((parrot-root x 18) (neck x -4) (head x -10)
                                        (l_hip x -33) (r_hip x -33) (l_knee x 45) (r_knee x 45)
                                        (l_ankle x -50) (r_ankle x -50)
                                        (l_shoulder z 18) (r_shoulder z -18)))
                                  (1.2 ((:include stand) (l_shoulder z 10) (r_shoulder z -10)))
                                  (1.5 ((:include stand) (l_shoulder z 0) (r_shoulder z 0))))
                           :priority 10))
  ;; The body rises by the legs' 0.026 m; while leaning it shifts forward to keep the toes put.
  (:at 0 :animate (:self position) (:keys ((0 :vec3 0 -0.026 0) (0.5 :vec3 0 -0.0264 0.0126)
                                           (1.2 :vec3 0 0 0) (1.5 :vec3 0 0 0))
                                          :interpolation :ease)))

(defscript sit (:duration 1.5
                :documentation "Settling down: the legs fold, the body sinks onto the table, the head draws in.")
  (:at 0 :motor (:keyframe :keys ((0 :start)
                                  (0.4 ((l_knee x 12) (r_knee x 12) (l_ankle x -12) (r_ankle x -12) (l_hip x -4) (r_hip x -4)))
                                  (1.1 sit)
                                  (1.5 sit))
                           :priority 10))
  (:at 0 :animate (:self position) (:keys ((0 :vec3 0 0 0) (0.4 :vec3 0 -0.006 0) (1.1 :vec3 0 -0.026 0)
                                           (1.5 :vec3 0 -0.026 0))
                                          :interpolation :ease)))

(defscript take-off (:duration 1.25
                     :documentation "Crouch, spring and climb to a hover: the wings beat fast, the legs tuck up.")
  (:at 0 :motor (:keyframe :keys ((0 :start)
                                  (0.35 ((:include crouch-legs) (parrot-root x 10) (l_hip x -24) (r_hip x -24)
                                         (neck x -6) (head x -6) (tail x -10 spread 15)))
                                  (0.55 ((:include stand-legs) (parrot-root x 18) (l_foot curl 10) (r_foot curl 10)))
                                  (0.95 fly-body)
                                  (1.25 fly-body))
                           :priority 10))
  (:at 0 :motor (:keyframe :keys ((0 :start) (0.3 fly-up) (0.5 fly-down) (0.68 fly-up) (0.86 fly-down)
                                  (1.05 fly-up) (1.25 fly-down))
                           :priority 10))
  (:at 0 :animate (:self position) (:keys ((0 :vec3 0 0 0) (0.35 :vec3 0 -0.03 0.007) (0.55 :vec3 0 0.01 0.01)
                                           (0.95 :vec3 0 0.17 0.01) (1.25 :vec3 0 0.25 0))
                                          :interpolation :catmull-rom)))

(defscript glance (:duration 0.6
                   :documentation "A glance toward a voice off to his left: the eyes alone, the head keeps its course.")
  (:at 0 :motor (:gaze :target (:point 0.8 0.3 0.5) :speed 1.5 :head-threshold 90) :for 0.45)
  (:at 0.45 :motor (:gaze :target (:object camera) :speed 1.5 :head-threshold 90) :for 0.15))

(defscript fly-loop (:duration 3
                     :documentation "A lap of the room: a banked circle out to his left and round behind, back to the hover.")
  ;; A circle of radius 0.45 m through the hover point, flown counter-clockwise
  ;; seen from above; the heading (yaw) turns with the circle's angle.
  (:at 0 :animate (:self position)
       (:keys ((0 :vec3 0 0.25 0) (0.375 :vec3 0.132 0.272 0.318) (0.75 :vec3 0.45 0.325 0.45)
               (1.125 :vec3 0.768 0.378 0.318) (1.5 :vec3 0.9 0.4 0) (1.875 :vec3 0.768 0.378 -0.318)
               (2.25 :vec3 0.45 0.325 -0.45) (2.625 :vec3 0.132 0.272 -0.318) (3 :vec3 0 0.25 0))
              :interpolation :catmull-rom))
  (:at 0 :animate (:self rotation)
       (:keys ((0 :euler 0 0 0) (0.375 :euler 0 0.7854 0) (0.75 :euler 0 1.5708 0)
               (1.125 :euler 0 2.3562 0) (1.5 :euler 0 3.1416 0) (1.875 :euler 0 3.927 0)
               (2.25 :euler 0 4.7124 0) (2.625 :euler 0 5.4978 0) (3 :euler 0 6.2832 0))
              :interpolation :catmull-rom))
  ;; Bank into the turn (his left side down), then level out for the hover.
  (:at 0 :motor (:keyframe :keys ((0 :start) (0.5 ((parrot-root x 30 z -16) (neck z 10) (tail y 8)))
                                  (2.4 ((parrot-root x 30 z -16) (neck z 10) (tail y 8)))
                                  (3 ((parrot-root x 25 z 0) (neck z 0) (tail y 0))))
                           :priority 10)))

(defscript land (:duration 1.5
                 :documentation "Down from the hover: fast wing beats, wings spread to brake, legs reach, a knee-bend on touching down.")
  (:at 0 :motor (:keyframe :keys ((0 :start) (0.15 fly-up) (0.3 fly-down) (0.45 fly-up) (0.6 fly-down)
                                  (0.85 wings-spread) (1.1 wings-spread) (1.5 folded-wings))
                           :priority 10))
  (:at 0 :motor (:keyframe :keys ((0 :start)
                                  (0.6 ((:include stand-legs) (parrot-root x 8 z 0) (neck x -4) (head x -4)
                                        (tail x -15 spread 25)))
                                  (1.1 ((:include stand-legs) (parrot-root x 0 y 0 z 0) (neck x 0 z 0) (head x 0)))
                                  (1.25 ((l_hip x -10) (r_hip x -10) (l_knee x 30) (r_knee x 30)
                                         (l_ankle x -26) (r_ankle x -26) (neck x 8)))
                                  (1.5 ((:include stand) (tail x 0 y 0 spread 0))))
                           :priority 10))
  (:at 0 :animate (:self position) (:keys ((0 :vec3 0 0.25 0) (0.6 :vec3 0 0.12 0) (1.1 :vec3 0 0 0)
                                           (1.25 :vec3 0 -0.015 0) (1.5 :vec3 0 0 0))
                                          :interpolation :ease)))

(defscript hop (:duration 0.5
                :documentation "A little hop on the spot: crouch, spring, tuck, land on bent legs.")
  (:at 0 :motor (:keyframe :keys ((0 :start)
                                  (0.12 ((l_hip x -12) (r_hip x -12) (l_knee x 40) (r_knee x 40) (l_ankle x -34) (r_ankle x -34)
                                         (tail x -8)))
                                  (0.22 ((:include stand-legs) (l_foot curl 10) (r_foot curl 10)))
                                  (0.32 ((l_hip x 10) (r_hip x 10) (l_knee x 30) (r_knee x 30) (l_ankle x -30) (r_ankle x -30)))
                                  (0.42 ((l_hip x -10) (r_hip x -10) (l_knee x 30) (r_knee x 30) (l_ankle x -26) (r_ankle x -26)
                                         (l_foot curl 40) (r_foot curl 40)))
                                  (0.5 ((:include stand-legs) (tail x 0))))
                           :priority 10))
  (:at 0.1 :motor (:keyframe :keys ((0 :start) (0.12 ((l_shoulder z 35) (r_shoulder z -35) (l_primaries spread 20) (r_primaries spread 20)))
                                    (0.35 :start))
                             :priority 10))
  (:at 0 :animate (:self position) (:keys ((0 :vec3 0 0 0) (0.12 :vec3 0 -0.02 0) (0.22 :vec3 0 0.03 0)
                                           (0.3 :vec3 0 0.05 0) (0.38 :vec3 0 0.03 0) (0.43 :vec3 0 -0.015 0)
                                           (0.5 :vec3 0 0 0))
                                          :interpolation :linear)))

;;; ---------------------------------------------------------------------------
;;; The wing at the ear

(defscript raise-wing (:duration 0.75
                       :documentation "\"I can't hear you\": the right wing tip cupped at the side of the head, the head turned to listen.")
  ;; The wrist folds the wing short so the reach can bring its tip up to the head.
  (:at 0 :motor (:keyframe :keys ((0 :start) (0.4 ((r_wrist unfold 50 y 0) (r_primaries spread 25)))) :priority 10))
  (:at 0.05 :motor (:keyframe :keys ((0 :start) (0.5 ((head y 12 z -8) (neck x -4)))) :priority 10))
  (:at 0 :motor (:reach :arm :right :target (:joint :self head :offset (-0.05 0 0)) :duration 0.6 :hold t)))

(defscript lower-wing (:duration 0.75
                       :documentation "The right wing comes down from the ear and folds; the head turns back.")
  (:at 0 :motor (:keyframe :keys ((0 :start) (0.65 ((:include right-wing-folded) (head y 0 z 0 x 0) (neck x 0)))
                                  (0.75 ((head y 0 z 0 x 0))))
                           :priority 10)))

(defscript huh (:duration 1
                :documentation "Huh?: the head tilts, the crest shoots up, he says it, the wing stays at the ear.")
  (:at 0 :motor (:reach :arm :right :target (:joint :self head :offset (-0.05 0 0)) :duration 0.3 :hold t))
  (:at 0 :motor (:keyframe :keys ((0 :start) (0.25 ((head x -8 y 14 z -18) (neck x -6)
                                                     (:left-upper-lid close -8) (:right-upper-lid close -8)))
                                  (0.8 ((head x -8 y 14 z -18) (neck x -6)))
                                  (1 ((head x -4 y 12 z -10) (neck x -4)
                                      (:left-upper-lid close 0) (:right-upper-lid close 0))))
                           :priority 10))
  (:at 0.1 :motor (:eyebrows :raise 0.9 :duration 0.15 :hold 0.55))
  (:at 0.15 :say "Huh?")
  (:at 0.05 :motor (:gaze :target (:object user))))

;;; ---------------------------------------------------------------------------
;;; The note: searching (the director STREAM), dropping, giving

(defscript look-for-note (:duration 1.5 :critical ((spotted . 1.1))
                          :documentation "Looking about for the note: left, right, then down at it (SPOTTED), the crest up.")
  ;; A search finds a fresh note on the table, wherever the last one went (set
  ;; just after the detach, so the position is the world's).
  (:at 0 :attach note :to nil)
  (:at 0.02 :set (note position) (:vec3 -0.07 0.001 0.09))
  (:at 0.02 :set (note rotation) (:quat 1 0 0 0))
  (:at 0.02 :set (note visible) t)
  (:at 0.05 :motor (:gaze :target (:point 0.3 0.05 0.4) :speed 1.4) :for 0.45)
  (:at 0.5 :motor (:gaze :target (:point -0.3 0.05 0.4) :speed 1.4) :for 0.5)
  (:at 1.0 :motor (:gaze :target (:object note)))
  (:at spotted :motor (:eyebrows :raise 0.8 :duration 0.12 :hold 0.3)))

(defscript fetch-note (:duration 1.9 :critical ((grab . 0.95))
                       :documentation "Bend down, reach the right wing to the note, take it at GRAB, straighten and hold it up.")
  ;; The lean of lean-to-note moves the body 0.030 m down and 0.0105 m forward so the toes stay put.
  (:at 0 :motor (:keyframe :keys ((0 :start) (0.85 lean-to-note) (1.05 lean-to-note)
                                  (1.75 ((:include stand) (tail spread 0)))
                                  (1.9 ((neck x 0))))
                           :priority 10))
  (:at 0 :animate (:self position) (:keys ((0 :vec3 0 0 0) (0.85 :vec3 0 -0.0301 0.0105) (1.05 :vec3 0 -0.0301 0.0105)
                                           (1.75 :vec3 0 0 0) (1.9 :vec3 0 0 0))
                                          :interpolation :ease))
  (:at 0.4 :motor (:gaze :target (:object note)) :for 0.55)
  ;; The wing swings forward and down as he bends (the pick-up shape), then the
  ;; reach puts its tip exactly on the note.
  (:at 0 :motor (:keyframe :keys ((0 :start) (0.75 pick-up-right)) :priority 10))
  (:at 0.65 :motor (:reach :arm :right :target (:object note :offset (0 0.008 0)) :duration 0.25 :hold t) :for 0.3)
  (:at grab :attach note :to (:self :right-hand))
  ;; Lift: the wing holds the note out in front of him, low, as far as a wing goes forward.
  (:at grab :motor (:reach :arm :right :target (:joint :self parrot-root :offset (-0.05 -0.04 0.15))
                           :duration 0.75 :hold t))
  (:at 1.35 :motor (:gaze :target (:object camera))))

(defdirector stream
  "The search: look about for the note; the moment he spots it, fetch it."
  (:start look-for-note :as look)
  (:start fetch-note :as fetch :at (:critical look spotted)))

(defscript drop-note (:duration 0.5
                      :documentation "Put the note back: the right wing dips forward, lets go, and the note drops flat onto the table.")
  (:at 0 :motor (:keyframe :keys ((0 :start) (0.25 ((r_shoulder x -70 y 10 z 0) (r_elbow unfold 0) (r_wrist unfold 0 y 0)
                                                    (neck x 22) (head x 12)))
                                  (0.5 ((:include right-wing-folded) (neck x 0) (head x 0))))
                           :priority 10))
  ;; Released about 5 cm above the table, the note (a dynamic prop) falls and
  ;; comes to rest on it.
  (:at 0.25 :attach note :to nil))

(defscript give-note (:duration 1
                      :documentation "Hand the note to the user: the wing holds it out to the camera, lets go, and the user takes it.")
  (:at 0 :motor (:gaze :target (:object camera)))
  (:at 0 :motor (:reach :arm :right :target (:joint :self parrot-root :offset (-0.05 -0.04 0.15)) :duration 0.5 :hold t)
       :for 0.65)
  (:at 0.6 :attach note :to nil)
  ;; The first keys are where the wing holds the note then (he always stands here).
  (:at 0.6 :animate (note position) (:keys ((0 :vec3 -0.0494 0.0939 0.1549) (0.35 :vec3 0 0.3 1.4)) :interpolation :ease))
  (:at 0.6 :animate (note rotation) (:keys ((0 :quat 0.9373 -0.3365 0.0903 0.0049) (0.35 :quat 1 0 0 0)) :interpolation :ease))
  (:at 0.95 :set (note visible) nil)
  (:at 0.65 :motor (:keyframe :keys ((0 :start) (0.35 right-wing-folded)) :priority 10))
  (:at 0.5 :motor (:lips :visemes ((0.05 :ih) (0.15 :ee) (0.3 :rr) (0.4 :rest)))))

;;; ---------------------------------------------------------------------------
;;; Music and headphones

(defscript play-cd (:duration 2
                    :documentation "Turn to the jukebox, flick the note into its slot, the music starts; turn back to the camera.")
  (:at 0 :motor (:facing :target (:object jukebox) :duration 0.6))
  (:at 0.1 :motor (:gaze :target (:object jukebox) :speed 1.5) :for 1.3)
  (:at 0.5 :motor (:reach :arm :right :target (:joint :self parrot-root :offset (-0.05 -0.04 0.15)) :duration 0.45 :hold t)
       :for 0.8)
  (:at 1.0 :attach note :to nil)
  ;; The first keys are where the wing holds the note then, facing the jukebox.
  (:at 1.0 :animate (note position) (:keys ((0 :vec3 -0.1314 0.0939 -0.0959) (0.35 :vec3 -0.4 0.32 -0.05)) :interpolation :ease))
  (:at 1.0 :animate (note rotation) (:keys ((0 :quat 0.6213 -0.2007 -0.7076 -0.2701) (0.35 :quat 0.7071 0 -0.7071 0))
                                           :interpolation :ease))
  (:at 1.35 :set (note visible) nil)
  (:at 1.35 :set (jukebox playing) t)
  (:at 1.3 :motor (:keyframe :keys ((0 :start) (0.5 right-wing-folded)) :priority 10))
  (:at 1.3 :motor (:facing :target (:object camera) :duration 0.7))
  (:at 1.45 :motor (:gaze :target (:object camera) :speed 1.5)))

(defscript stop-cd (:duration 1
                    :documentation "Stop the music: a look at the jukebox and a raised wing, palm out; it stops.")
  ;; He turns to the jukebox himself: the body settles facing front after an
  ;; op, and from there the jukebox is beyond the reach of his eyes and head.
  (:at 0 :motor (:facing :target (:object jukebox) :duration 0.4))
  (:at 0 :motor (:gaze :target (:object jukebox) :speed 2) :for 0.6)
  (:at 0 :motor (:keyframe :keys ((0 :start) (0.35 ((r_shoulder x -30 y -20 z -70) (r_elbow unfold 20) (r_wrist unfold 10 y 0)
                                                    (r_primaries spread 35)))
                                  (0.6 ((r_shoulder x -30 y -20 z -70)))
                                  (1 :start))
                           :priority 10))
  (:at 0.4 :set (jukebox playing) nil)
  (:at 0.6 :motor (:facing :target (:object camera) :duration 0.4))
  (:at 0.6 :motor (:gaze :target (:object camera) :speed 2)))

(defscript next-track (:duration 0.75
                       :documentation "Next track: a quick flick of the left wing and a click of the beak, eyes on the jukebox.")
  (:at 0 :motor (:gaze :target (:object jukebox) :speed 2.5) :for 0.4)
  (:at 0 :motor (:keyframe :keys ((0 :start) (0.2 ((l_shoulder x -30 z 55) (l_elbow unfold 15) (l_primaries spread 30)))
                                  (0.35 ((l_shoulder x -10 z 25))) (0.75 :start))
                           :priority 10))
  (:at 0.1 :motor (:lips :visemes ((0.1 :dd) (0.2 :ee) (0.3 :kk) (0.4 :rest))))
  (:at 0.4 :motor (:gaze :target (:object camera) :speed 2.5)))

(defscript dance (:duration 4
                  :documentation "Dancing to the music: the body sways and bounces on the knees, wings pump, head bobs and looks about.")
  (:at 0 :motor (:keyframe :keys ((0 :start)
                                  (0.5 ((parrot-root x 4 z 8) (l_hip z -8) (r_hip z -8) (neck x 10 y 12) (head x 4 z -6) (tail y 12)
                                        (l_hip x -7) (r_hip x -7) (l_knee x 24) (r_knee x 24) (l_ankle x -22) (r_ankle x -22)))
                                  (1 ((parrot-root x 0 z 0) (l_hip z 0) (r_hip z 0) (neck x -2 y 0) (head x -4 z 0) (tail y 0)
                                      (l_hip x 0) (r_hip x 0) (l_knee x 0) (r_knee x 0) (l_ankle x 0) (r_ankle x 0)))
                                  (1.5 ((parrot-root x 4 z -8) (l_hip z 8) (r_hip z 8) (neck x 10 y -12) (head x 4 z 6) (tail y -12)
                                        (l_hip x -7) (r_hip x -7) (l_knee x 24) (r_knee x 24) (l_ankle x -22) (r_ankle x -22)))
                                  (2 ((parrot-root x 0 z 0) (l_hip z 0) (r_hip z 0) (neck x -2 y 0) (head x -4 z 0) (tail y 0)
                                      (l_hip x 0) (r_hip x 0) (l_knee x 0) (r_knee x 0) (l_ankle x 0) (r_ankle x 0)))
                                  (2.5 ((parrot-root x 4 z 8) (l_hip z -8) (r_hip z -8) (neck x 10 y 12) (head x 4 z -6) (tail y 12)
                                        (l_hip x -7) (r_hip x -7) (l_knee x 24) (r_knee x 24) (l_ankle x -22) (r_ankle x -22)))
                                  (3 ((parrot-root x 0 z 0) (l_hip z 0) (r_hip z 0) (neck x -2 y 0) (head x -4 z 0) (tail y 0)
                                      (l_hip x 0) (r_hip x 0) (l_knee x 0) (r_knee x 0) (l_ankle x 0) (r_ankle x 0)))
                                  (3.5 ((parrot-root x 4 z -8) (l_hip z 8) (r_hip z 8) (neck x 10 y -12) (head x 4 z 6) (tail y -12)
                                        (l_hip x -7) (r_hip x -7) (l_knee x 24) (r_knee x 24) (l_ankle x -22) (r_ankle x -22)))
                                  (4 :start))
                           :interpolation :catmull-rom :priority 10))
  (:at 0 :motor (:keyframe :keys ((0 :start)
                                  (0.5 ((l_shoulder x -20 z 55) (r_shoulder x -20 z -20) (l_primaries spread 30) (r_primaries spread 10)))
                                  (1 ((l_shoulder x -10 z 20) (r_shoulder x -10 z -20) (l_primaries spread 10) (r_primaries spread 10)))
                                  (1.5 ((l_shoulder x -20 z 20) (r_shoulder x -20 z -55) (l_primaries spread 10) (r_primaries spread 30)))
                                  (2 ((l_shoulder x -10 z 20) (r_shoulder x -10 z -20) (l_primaries spread 10) (r_primaries spread 10)))
                                  (2.5 ((l_shoulder x -20 z 70) (r_shoulder x -20 z -70) (l_primaries spread 35) (r_primaries spread 35)))
                                  (3 ((l_shoulder x -10 z 20) (r_shoulder x -10 z -20) (l_primaries spread 10) (r_primaries spread 10)))
                                  (3.5 ((l_shoulder x -20 z 70) (r_shoulder x -20 z -70) (l_primaries spread 35) (r_primaries spread 35)))
                                  (4 :start))
                           :interpolation :catmull-rom :priority 10))
  ;; The knee bends lower the body 0.012 m on the off-beats.
  (:at 0 :animate (:self position) (:keys ((0 :vec3 0 0 0) (0.5 :vec3 0 -0.012 0) (1 :vec3 0 0 0) (1.5 :vec3 0 -0.012 0)
                                           (2 :vec3 0 0 0) (2.5 :vec3 0 -0.012 0) (3 :vec3 0 0 0) (3.5 :vec3 0 -0.012 0)
                                           (4 :vec3 0 0 0))
                                          :interpolation :ease))
  (:at 0 :motor (:blink :mean-interval 2.5)))

(defscript put-on-phones (:duration 2
                          :documentation "Bend to the headphones by his left foot, take them in the left wing, set them on his head.")
  (:at 0 :motor (:keyframe :keys ((0 :start) (0.8 lean-to-phones) (0.95 lean-to-phones)
                                  (1.5 stand) (2 ((:include stand) (tail spread 0))))
                           :priority 10))
  (:at 0 :animate (:self position) (:keys ((0 :vec3 0 0 0) (0.8 :vec3 0 -0.0301 0.0105) (0.95 :vec3 0 -0.0301 0.0105)
                                           (1.5 :vec3 0 0 0) (2 :vec3 0 0 0))
                                          :interpolation :ease))
  ;; As in fetch-note: the wing swings down as he bends, the reach puts its tip on the phones.
  (:at 0 :motor (:keyframe :keys ((0 :start) (0.7 pick-up-left)) :priority 10))
  (:at 0.6 :motor (:reach :arm :left :target (:object phones :offset (0 -0.003 0)) :duration 0.25 :hold t) :for 0.3)
  (:at 0.9 :attach phones :to (:self :left-hand))
  (:at 0.9 :motor (:reach :arm :left :target (:joint :self head :offset (0.03 0.04 -0.02)) :duration 0.6 :hold t) :for 0.65)
  ;; Hung from the head, they settle onto it; the first keys are where the wing
  ;; left them, in the head's frame.
  (:at 1.55 :attach phones :to (:self head))
  (:at 1.56 :animate (phones position) (:keys ((0 :vec3 0.0368 0.0109 -0.0178) (0.35 :vec3 0 0.03 0)) :interpolation :ease))
  (:at 1.56 :animate (phones rotation) (:keys ((0 :quat 0.0099 0.9662 0.1195 0.2284) (0.35 :quat 1 0 0 0))
                                              :interpolation :ease))
  (:at 1.55 :motor (:keyframe :keys ((0 :start) (0.45 left-wing-folded)) :priority 10)))

(defscript take-off-phones (:duration 1.5
                            :documentation "The left wing lifts the headphones off his head and drops them on the table by his foot.")
  (:at 0 :motor (:reach :arm :left :target (:joint :self head :offset (0.03 0.04 -0.02)) :duration 0.45 :hold t) :for 0.5)
  (:at 0.5 :attach phones :to (:self :left-hand))
  (:at 0.5 :motor (:reach :arm :left :target (:joint :self parrot-root :offset (0.05 -0.04 0.15)) :duration 0.45 :hold t)
       :for 0.5)
  ;; Let go 9 cm above the table: the phones drop to their place (the first
  ;; keys are where the wing holds them then when he stands).
  (:at 1.0 :attach phones :to nil)
  (:at 1.0 :animate (phones position) (:keys ((0 :vec3 0.061 0.105 0.1225) (0.2 :vec3 0.07 0.012 0.09)) :interpolation :linear))
  (:at 1.0 :animate (phones rotation) (:keys ((0 :quat 0.7047 -0.6456 -0.2941 0.0087) (0.2 :quat 1 0 0 0)) :interpolation :linear))
  (:at 1.0 :motor (:keyframe :keys ((0 :start) (0.5 left-wing-folded)) :priority 10)))

;;; ---------------------------------------------------------------------------
;;; Gestures

(defscript greet (:duration 1.5
                  :documentation "Hello: the left wing goes up and waves, the crest rises, he says hello.")
  (:at 0 :motor (:keyframe :keys ((0 :start) (0.35 left-wing-wave-out) (0.55 left-wing-wave-in) (0.75 left-wing-wave-out)
                                  (0.95 left-wing-wave-in) (1.15 left-wing-wave-out) (1.5 :start))
                           :priority 10))
  (:at 0.1 :motor (:keyframe :keys ((0 :start) (0.3 ((head z 10) (neck x -4))) (1.05 ((head z 10) (neck x -4))) (1.4 :start))
                             :priority 10))
  (:at 0 :motor (:gaze :target (:object camera)))
  (:at 0.2 :motor (:eyebrows :raise 0.8 :duration 0.15 :hold 0.8))
  (:at 0.25 :say "Hello!"))

(defscript bow (:duration 1.25 :critical ((stroke . 0.6))
                :documentation "A real bow: body, neck and head pitch forward to the lowest point (STROKE), wings spread a little, and back up.")
  (:at 0 :motor (:keyframe :keys ((0 :start) (0.6 bow-low) (0.75 bow-low)
                                  (1.25 ((:include stand) (:include folded-wings)
                                         (tail x 0 y 0 spread 0)
                                         (:left-upper-lid close 0) (:right-upper-lid close 0))))
                           :priority 10))
  ;; Pitching the root forward swings the hips back: the body moves forward to keep the toes planted.
  (:at 0 :animate (:self position) (:keys ((0 :vec3 0 0 0) (0.6 :vec3 0 -0.0023 0.0194) (0.75 :vec3 0 -0.0023 0.0194)
                                           (1.25 :vec3 0 0 0))
                                          :interpolation :ease)))

(defscript shrug (:duration 1
                  :documentation "Who knows?: wings lift a little from the body, head tilts, crest half up, beak ajar.")
  (:at 0 :motor (:keyframe :keys ((0 :start) (0.35 ((:include shrug-wings) (head z 12 x -4) (neck x -6) (:jaw open 8)))
                                  (0.65 ((:include shrug-wings) (head z 12 x -4) (neck x -6) (:jaw open 6)))
                                  (1 :start))
                           :priority 10))
  (:at 0.1 :motor (:eyebrows :raise 0.5 :duration 0.2 :hold 0.4)))

(defscript nod (:duration 0.5
                :documentation "Yes: one nod of the head.")
  (:at 0 :motor (:head :action :nod :count 1 :amplitude 15 :duration 0.5)))

(defscript shake-head (:duration 0.75
                       :documentation "No: the head shakes twice.")
  (:at 0 :motor (:head :action :shake :count 2 :amplitude 20 :duration 0.75)))

(defscript whistle (:duration 1.5
                    :documentation "A jaunty whistle: the beak pipes a tune, the head sways, eyes half closed, crest up.")
  (:at 0 :motor (:lips :visemes ((0.1 :oo) (0.25 :ss) (0.4 :oo) (0.5 :ss) (0.65 :oo) (0.8 :ss)
                                 (0.95 :oo) (1.1 :ss) (1.25 :oo) (1.45 :rest))))
  (:at 0 :motor (:keyframe :keys ((0 :start)
                                  (0.3 ((head z 8 x -6) (neck x -4) (:left-upper-lid close 30) (:right-upper-lid close 30) (tail y 8)))
                                  (0.7 ((head z -8 x -6) (neck x -4) (tail y -8)))
                                  (1.1 ((head z 8 x -6) (neck x -4) (tail y 8)))
                                  (1.5 :start))
                           :priority 10))
  (:at 0.1 :motor (:eyebrows :raise 0.6 :duration 0.2 :hold 1.0)))

(defscript look-around (:duration 2
                        :documentation "A look round the room: to his left, to his right and up, back to the camera.")
  (:at 0 :motor (:gaze :target (:point 0.7 0.3 0.5) :speed 1.4) :for 0.6)
  (:at 0.6 :motor (:gaze :target (:point -0.7 0.45 0.4) :speed 1.4) :for 0.7)
  (:at 1.3 :motor (:gaze :target (:object camera)))
  (:at 0 :motor (:blink :mean-interval 1.5)))

(defscript scratch-head (:duration 1.5
                         :documentation "Thinking: the right wing tip scratches the side of the head, eyes up, beak ajar.")
  (:at 0 :motor (:keyframe :keys ((0 :start) (0.3 ((r_wrist unfold 50 y 0)))) :priority 10))
  (:at 0 :motor (:reach :arm :right :target (:joint :self head :offset (-0.045 0.03 -0.01)) :duration 0.45 :hold t) :for 0.6)
  (:at 0.6 :motor (:reach :arm :right :target (:joint :self head :offset (-0.045 0.035 -0.02)) :duration 0.12 :hold t) :for 0.15)
  (:at 0.75 :motor (:reach :arm :right :target (:joint :self head :offset (-0.045 0.02 0)) :duration 0.12 :hold t) :for 0.15)
  (:at 0.9 :motor (:reach :arm :right :target (:joint :self head :offset (-0.045 0.035 -0.02)) :duration 0.12 :hold t) :for 0.15)
  (:at 1.05 :motor (:reach :arm :right :target (:joint :self head :offset (-0.045 0.02 0)) :duration 0.12 :hold t) :for 0.15)
  (:at 1.2 :motor (:keyframe :keys ((0 :start) (0.3 right-wing-folded)) :priority 10))
  (:at 0.1 :motor (:keyframe :keys ((0 :start) (0.3 ((head z -12 x -10) (neck x -4) (:jaw open 5))) (1.1 ((head z -12 x -10) (neck x -4) (:jaw open 5)))
                                    (1.4 :start))
                             :priority 10))
  (:at 0.1 :motor (:gaze :target (:point 0.15 0.7 0.6)) :for 1.1))

(defscript yawn (:duration 1.5
                 :documentation "A big yawn: head back, beak wide, lids squeezed, wings out a little; then it all settles.")
  (:at 0 :motor (:keyframe :keys ((0 :start)
                                  (0.5 ((neck x -20) (head x -14) (:left-upper-lid close 45) (:right-upper-lid close 45)
                                        (:crest raise 30) (l_shoulder z 15) (r_shoulder z -15)))
                                  (0.95 ((neck x -24) (head x -16) (:left-upper-lid close 55) (:right-upper-lid close 55)
                                         (:crest raise 35) (l_shoulder z 18) (r_shoulder z -18)))
                                  (1.5 :start))
                           :priority 10))
  (:at 0 :motor (:keyframe :keys ((0 :start) (0.3 ((:jaw open 10))) (0.6 ((:jaw open 35))) (1 ((:jaw open 32))) (1.3 ((:jaw open 0))))
                           :priority 10)))

(defscript point (:duration 1
                  :documentation "There: the left wing points out to the CD title beside him; he looks at it, then back at the camera.")
  (:at 0 :motor (:gaze :target (:object cd-title) :speed 1.5) :for 0.6)
  (:at 0 :motor (:keyframe :keys ((0 :start) (0.3 point-left) (0.6 point-left) (1 :start)) :priority 10))
  (:at 0.6 :motor (:facing :target (:object camera) :duration 0.4))
  (:at 0.6 :motor (:gaze :target (:object camera) :speed 2)))

(defscript preen (:duration 2.5
                  :documentation "Preening on the perch: the head turns to the raised left wing and the beak nibbles its feathers.")
  (:at 0 :motor (:keyframe :keys ((0 :start)
                                  (0.6 ((neck x 28 y 35) (head x 25 y 60 z 0) (l_shoulder x 10 z 28) (l_primaries spread 20)
                                        (:left-upper-lid close 20) (:right-upper-lid close 20)))
                                  (1.1 ((head z 6)))
                                  (1.5 ((head z -6)))
                                  (1.9 ((neck x 28 y 35) (head x 25 y 60 z 0) (l_shoulder x 10 z 28) (l_primaries spread 20)))
                                  (2.5 :start))
                           :priority 10))
  (:at 0.6 :motor (:keyframe :keys ((0 :start) (0.15 ((:jaw open 12))) (0.3 ((:jaw open 2))) (0.45 ((:jaw open 12)))
                                    (0.6 ((:jaw open 2))) (0.75 ((:jaw open 12))) (0.9 ((:jaw open 2)))
                                    (1.05 ((:jaw open 10))) (1.25 ((:jaw open 0))))
                             :interpolation :linear :priority 10)))

(defscript wave-goodbye (:duration 1.5
                         :documentation "Goodbye: a slow, broad wave of the left wing, head tilted, the beak says bye.")
  (:at 0 :motor (:keyframe :keys ((0 :start) (0.35 left-wing-wave-out) (0.65 left-wing-wave-in) (0.95 left-wing-wave-out)
                                  (1.2 left-wing-wave-in) (1.5 :start))
                           :priority 10))
  (:at 0.1 :motor (:keyframe :keys ((0 :start) (0.3 ((head z -10 x 4))) (1.1 ((head z -10 x 4))) (1.4 :start)) :priority 10))
  (:at 0 :motor (:gaze :target (:object camera)))
  (:at 0.3 :motor (:lips :visemes ((0.1 :mm) (0.25 :aa) (0.4 :ee) (0.6 :rest)))))

;;; ---------------------------------------------------------------------------
;;; Camera moves (each starts from the home framing)

(defscript camhello (:duration 1.5
                     :documentation "Push in from the home framing to a close-up of Peedy.")
  (:at 0 :animate (camera position) (:keys ((0 :vec3 0 0.25 1.1) (1.5 :vec3 0 0.24 0.6)) :interpolation :ease))
  (:at 0 :animate (camera rotation) (:keys ((0 :quat 1 0 0 0) (1.5 :euler -0.04 0 0)) :interpolation :ease)))

(defscript camgoodbye (:duration 1.5
                       :documentation "Pull back from the home framing to the goodbye shot, high and wide, tilted down at him, as he answers the thanks.")
  (:at 0 :animate (camera position) (:keys ((0 :vec3 0 0.25 1.1) (1.5 :vec3 0 0.36 1.9)) :interpolation :ease))
  (:at 0 :animate (camera rotation) (:keys ((0 :quat 1 0 0 0) (1.5 :euler -0.1 0 0)) :interpolation :ease))
  ;; Only ev-thanks plays this shot.
  (:at 0.1 :say "You're welcome!"))

(defscript camwide (:duration 2
                    :documentation "Crane up and out to his left to take in the whole room, jukebox and all.")
  (:at 0 :animate (camera position) (:keys ((0 :vec3 0 0.25 1.1) (2 :vec3 0.7 1.0 2.6)) :interpolation :ease))
  (:at 0 :animate (camera rotation) (:keys ((0 :quat 1 0 0 0) (2 :euler -0.306 0.263 0)) :interpolation :ease)))
