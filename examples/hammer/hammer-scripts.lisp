;;;; hammer-scripts.lisp -- the strike of hammer.lisp: the arm comes down by
;;;; 0.55 s, its critical time STRIKE, when the nail is driven in.

(defobject camera :kind :camera :position (0 1.1 3.2))
(defobject nail :position (0.35 0.8 0.3) :properties ((colour :colour (0.6 0.6 0.6))))

(defscript strike (:duration 1 :critical ((strike . 0.55)))
  (:at 0 :motor (:pose :name arms-raised :duration 0.4))
  (:at 0.4 :motor (:pose :name neutral :duration 0.15))
  (:at strike :animate (nail position)
       (:keys ((0 :vec3 0.35 0.8 0.3) (0.05 :vec3 0.35 0.77 0.3)))))
