;;;; hammer.lisp -- Pantomime's critical time: the hammer hits the nail at
;;;; 0.55 s, and every output shows a frame at that instant (doc/animation.md).

(in-package :player-user)

(defspec hammer
  "A humanoid strikes a nail once; the script marks the strike as critical."
  (:scripts "hammer-scripts.lisp")
  (:body humanoid)
  (state-variable driven boolean false)
  (op strike :add driven :duration 1)
  (event ev-strike :op strike))
