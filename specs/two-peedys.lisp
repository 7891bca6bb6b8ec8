;;;; two-peedys.lisp -- two Peedys in one scene (issue 16, item 4), each with
;;;; his own controller over Peedy's one compiled machine, in one set (issue
;;;; 27): left beside the jukebox, right past the panel, each with his own note.
;;;; The spec is specs/peedy.lisp, found beside this file.  Try:
;;;;   bin/player run specs/two-peedys.lisp --events left/ev-search@0,right/ev-thanks@1
;;;;   bin/player render specs/two-peedys.lisp --events duet-search,all/ev-thanks --out two

(in-package :player-user)

(defscene two-peedys
  "Two Peedys side by side, the right one asleep."
  (peedy :as left :at (-0.2 0 0))
  (peedy :as right :at (0.5 0 0) :initial ((alert . snore) (posture . sit)))
  ;; A scene event addresses several members at once ...
  (event duet-search left/ev-search right/ev-search)
  ;; ... and, like a director, may stagger them: sent at T (duet-hop@T),
  ;; left hops at T and right half a second later.
  (event duet-hop (left/ev-hop :after 0) (right/ev-hop :after 0.5)))
