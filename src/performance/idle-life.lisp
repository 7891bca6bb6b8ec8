;;;; idle-life.lisp -- every character of a performance has idle life from the
;;;; start (src/body/idle-life.lisp: blinks, breathing, saccades, weight
;;;; shifts, relaxed hands), unless its library says (idle nil).  Seeded by
;;;; the performance's seed and the character's name, so a replay, a record
;;;; and its verify see the same blinks, and two characters blink apart.

(in-package #:player.performance)

(defun name-seed (name)
  "A seed from the character's NAME (a symbol or string, case aside): the same
in every run, different for the members of a cast, so they do not blink as one."
  (reduce (lambda (hash char) (mod (+ (* hash 31) (char-code char)) 1000003))
          (string-downcase (string name)) :initial-value 7))

(defun start-performance-idle-life (performance)
  "Give each visible character of PERFORMANCE's scene its idle life from time 0,
unless the library switched it off."
  (when (script-library-idle (performance-library performance))
    (loop for spec in (performance-characters performance)
          for name = (character-spec-name spec)
          when (character-spec-visible spec)
            do (start-idle-life (find-object (performance-scene performance) name)
                                0 :seed (name-seed name)))))
