;;;; idle-life.lisp -- every character of a performance has idle life from the
;;;; start (src/body/idle-life.lisp: blinks, breathing, saccades, weight
;;;; shifts, relaxed hands), unless its library says (idle nil).  Seeded by
;;;; the performance's seed and the character's place, so a replay, a record
;;;; and its verify see the same blinks.

(in-package #:player.performance)

(defun start-performance-idle-life (performance)
  "Give each visible character of PERFORMANCE's scene its idle life from time 0,
unless the library switched it off."
  (when (script-library-idle (performance-library performance))
    (loop for spec in (performance-characters performance)
          for index from 0
          when (character-spec-visible spec)
            do (start-idle-life (find-object (performance-scene performance) (character-spec-name spec))
                                0 :seed (* 10 index)))))
