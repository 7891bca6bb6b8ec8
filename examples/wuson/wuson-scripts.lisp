;;;; wuson-scripts.lisp -- the script library of wuson.lisp: the model, its
;;;; clips as the ops' motion, and the camera it looks at.
;;;; Testwuson.X keeps three animations (Wuson_Run, Wuson_Walk, Wuson_Bind),
;;;; clips named wuson-run, wuson-walk and wuson-bind; its joints are named
;;;; for a quadruped, so the roles the drivers need are given by hand.

(model "/usr/share/assimp/models/X/Testwuson.X"
  :height 0.8
  :roles ((:head "Neck") (:jaw "Mouth") (:tail "Tail01")))

(defobject camera :kind :camera :position (0.6 0.6 2.6))

;;; The gaits loop while the controller is in them; the ops between them fade
;;; from one clip to the other.
(defscript walk-loop (:loop t :duration 3.6)
  (:at 0 :clip wuson-walk :loop t :fade 0.3 :priority 5))

(defscript run-loop (:loop t :duration 0.966667)
  (:at 0 :clip wuson-run :loop t :fade 0.2 :priority 5))

(defscript start-walking (:duration 0.5)
  (:at 0 :clip wuson-walk :fade 0.5 :for 0.5))

(defscript speed-up (:duration 0.4)
  (:at 0 :clip wuson-run :fade 0.4 :for 0.4))

(defscript slow-down (:duration 0.4)
  (:at 0 :clip wuson-walk :fade 0.4 :for 0.4))

(defscript halt (:duration 0.6)
  (:at 0 :clip wuson-bind :fade 0.6 :for 0.6))

;;; Looking: the head turns to the camera over whatever the body is doing, and
;;; holds it until look-away takes the head back (its eyes are not joints, so
;;; it looks with its head).
(defscript look-up (:duration 0.8)
  (:at 0 :motor (:head :action :turn-to :target (:object camera) :duration 0.8 :priority 30)))

(defscript look-away (:duration 0.8)
  (:at 0 :clip wuson-bind :joints (:head) :fade 0.8 :priority 30 :for 0.8))
