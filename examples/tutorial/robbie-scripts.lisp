;;;; robbie-scripts.lisp -- Robbie's scripts (doc/tutorial.md): one per op, on
;;;; the humanoid body and the poses shipped for it.

(defobject camera :kind :camera :position (0 1.1 3.2))

(defscript wake-up (:duration 1)
  (:at 0 :motor (:head :action :nod :count 1 :amplitude 10 :duration 0.8))
  (:at 0.2 :motor (:eyebrows :raise 1 :duration 0.2 :hold 0.4)))

(defscript doze-off (:duration 1.5)
  (:at 0 :motor (:head :action :nod :count 1 :amplitude 20 :duration 1.4)))

(defscript raise-arms (:duration 0.8)
  (:at 0 :motor (:pose :name arms-raised :duration 0.8)))

(defscript lower-arms (:duration 0.8)
  (:at 0 :motor (:pose :name neutral :duration 0.8)))

(defscript wave (:duration 2)
  (:at 0 :motor (:beat :arm :right :times (0.3 0.8 1.3 1.8) :amplitude 1.5))
  (:at 0 :motor (:gaze :target (:object camera)) :for 2))

(defscript hands-on-hips (:duration 1)
  (:at 0 :motor (:pose :name hands-on-hips :duration 1)))

(defscript relax (:duration 0.6)
  (:at 0 :motor (:pose :name neutral :duration 0.6)))

(defscript bow (:duration 1.5)
  (:at 0 :motor (:keyframe :keys ((0 :start) (0.6 bow-down) (1.5 neutral)))))

(defscript point (:duration 1.2)
  (:at 0 :motor (:pose :name right-point :duration 0.5))
  (:at 0 :motor (:gaze :target (:point 1 1.2 1)) :for 1)
  (:at 0.9 :motor (:pose :name neutral :duration 0.3)))
