;;;; cradle-scripts.lisp -- specs/newtons-cradle-scripts.lisp: the script
;;;; library that draws specs/newtons-cradle.lisp, written from the same graph
;;;; so the two stay in step (one script per op, named as the op).
;;;;
;;;; The scene is props alone (the spec says (:body none)): a base, two posts
;;;; and a rod; under the rod one PIVOT-K group per sphere, at the top of its
;;;; string, holding STRING-K and BALL-K. A sphere's position -1, 0 or 1 is its
;;;; pivot turned about z by -θ, 0 or θ (*CRADLE-SWING*), so a sphere moves on
;;;; its arc. Each op's script lasts as long as the op's move (cradle-timing.lisp)
;;;; and turns every pivot from the angle of the op's source state to that of
;;;; its target through the pendulum's intermediate angles: the spheres swing,
;;;; fastest at the bottom, never jump.

(in-package #:player.compose)

(defparameter *cradle-geometry*
  '(:ball 0.1 :string 0.35 :rod-height 0.6 :swing-degrees 35)
  "The cradle's sizes in metres: sphere diameter (also the spacing of the
strings, so resting spheres touch), string length, height of the rod above
the floor; and the angle of a lifted sphere's string, in degrees.")

(defun cradle-geometry (key)
  "The value of KEY in *CRADLE-GEOMETRY*."
  (getf *cradle-geometry* key))

(defun cradle-pivot-x (k n)
  "The x of the K-th (from 0) of N pivots: the row is centred on x = 0."
  (* (cradle-geometry :ball) (- k (/ (1- n) 2))))

(defun cradle-angle (position)
  "The angle (radians, about z) of a pivot whose sphere is at POSITION -1, 0 or 1."
  (* position (cradle-geometry :swing-degrees) (/ pi 180)))

(defun rounded (x)
  "X rounded to 4 decimals, as a double-float (so the file prints it short)."
  (/ (round x 1d-4) 1d4))

(defun cradle-object-name (control &rest arguments)
  "A PLAYER-USER symbol for a scene object."
  (apply #'spec-symbol control arguments))

(defun cradle-frame-forms (n)
  "The DEFOBJECT forms of the stand, the camera and the lights for N spheres."
  (let* ((height (cradle-geometry :rod-height))
         (width (rounded (+ (* n (cradle-geometry :ball)) 0.3d0)))
         (post-x (rounded (/ width 2))))
    (flet ((box (name position size colour documentation)
             `(,(spec-symbol "defobject") ,(cradle-object-name name) :kind :prop :position ,position
                :properties ((,(spec-symbol "colour") :colour ,colour) (,(spec-symbol "size") :vector ,size))
                :documentation ,documentation)))
      (list
       (box "base" '(0 0.01 0) (list width 0.02 0.3) '(0.3 0.22 0.16) "The wooden base the stand rests on.")
       (box "left-post" (list (- post-x) (rounded (/ height 2)) 0) (list 0.02 height 0.02) '(0.35 0.35 0.38)
            "The left post of the stand.")
       (box "right-post" (list post-x (rounded (/ height 2)) 0) (list 0.02 height 0.02) '(0.35 0.35 0.38)
            "The right post of the stand.")
       (box "rod" (list 0 height 0) (list width 0.02 0.02) '(0.35 0.35 0.38)
            "The rod the strings hang from.")
       `(,(spec-symbol "defobject") ,(cradle-object-name "camera") :kind :camera :position (0 0.45 1.3) :rotation (:euler -6 0 0)
          :properties ((,(spec-symbol "fov") :number 35))
          :documentation "The camera, in front of the cradle, looking a little down.")
       `(,(spec-symbol "defobject") ,(cradle-object-name "key-light") :kind :light :position (0.8 1.2 1.0)
          :properties ((,(spec-symbol "colour") :colour (1 0.95 0.85)) (,(spec-symbol "intensity") :number 1)))
       `(,(spec-symbol "defobject") ,(cradle-object-name "fill-light") :kind :light :position (-1.0 0.6 0.8)
          :properties ((,(spec-symbol "colour") :colour (0.6 0.7 1)) (,(spec-symbol "intensity") :number 0.4)))))))

(defun cradle-sphere-forms (n)
  "The DEFOBJECT forms of each sphere's pivot, string and ball, leftmost first."
  (let ((length (cradle-geometry :string))
        (ball (cradle-geometry :ball)))
    (loop for k below n
          for pivot = (cradle-object-name "pivot-~D" (1+ k))
          append `((,(spec-symbol "defobject") ,pivot :kind :group
                     :position (,(rounded (cradle-pivot-x k n)) ,(cradle-geometry :rod-height) 0)
                     :documentation ,(format nil "Where string ~D hangs from the rod; turning it about z swings ball ~D." (1+ k) (1+ k)))
                   (,(spec-symbol "defobject") ,(cradle-object-name "string-~D" (1+ k)) :kind :prop :parent ,pivot
                     :position (0 ,(rounded (- (/ length 2))) 0)
                     :properties ((,(spec-symbol "colour") :colour (0.92 0.92 0.88))
                                  (,(spec-symbol "size") :vector (0.004 ,length 0.004))))
                   (,(spec-symbol "defobject") ,(cradle-object-name "ball-~D" (1+ k)) :kind :prop :parent ,pivot
                     :position (0 ,(- length) 0)
                     :properties ((,(spec-symbol "colour") :colour (0.75 0.18 0.15))
                                  (,(spec-symbol "size") :vector (,ball ,ball ,ball))))))))

(defparameter *cradle-script-steps* 8
  "How many intervals of its move a script's keys sample (CRADLE-REFINEMENT).")

(defun cradle-swing-script (name source target seconds)
  "The DEFSCRIPT form NAME: SECONDS turning every pivot from its angle in the
cradle node SOURCE to its angle in TARGET through the pendulum's intermediate
angles (CRADLE-REFINEMENT), fastest at the bottom."
  (let ((samples (cradle-refinement source target *cradle-script-steps*)))
    `(,(spec-symbol "defscript") ,name (:duration ,seconds :documentation ,(format nil "~A to ~A" (cradle-node-name source) (cradle-node-name target)))
       ,@(loop for k from 0 below (length (cradle-spheres source))
               collect `(:at 0 :animate (,(cradle-object-name "pivot-~D" (1+ k)) ,(spec-symbol "rotation"))
                             (:keys ,(loop for (u . angles) in (if (= (car (nth k (cradle-spheres source)))
                                                                      (car (nth k (cradle-spheres target))))
                                                                   ;; a sphere that stays needs its two ends only
                                                                   (list (first samples) (car (last samples)))
                                                                   samples)
                                           collect `(,(rounded (* u seconds)) :euler 0 0 ,(rounded (nth k angles))))
                              :interpolation :linear))))))

(defun double-floats (tree)
  "TREE with every float ROUNDED to a double-float, so it prints without an
exponent marker when doubles are the default format."
  (cond ((floatp tree) (rounded tree))
        ((consp tree) (cons (double-floats (car tree)) (double-floats (cdr tree))))
        (t tree)))

(defun cradle-script-forms (&key (n 5))
  "The forms of specs/newtons-cradle-scripts.lisp for the spec CRADLE-SPEC-FORMS
makes with N: the scene, then a script per op, named as the op."
  (multiple-value-bind (graph rest lifts) (cradle-spec-graph :n n)
    (let ((namer (cradle-op-namer rest lifts)))
      (double-floats
       (append (cradle-frame-forms n)
               (cradle-sphere-forms n)
               (loop for (source . target) in (graph-edges graph)
                     collect (cradle-swing-script (funcall namer source target) source target
                                                  (graph-edge-duration graph source target))))))))

(defmacro with-library-print-syntax (() &body body)
  "Run BODY printing forms as a generated script library holds them: read back
in PLAYER-USER, lower case, doubles without a marker, pretty, 110 columns."
  `(with-standard-io-syntax
     (let ((*package* (find-package '#:player-user))
           (*print-case* :downcase)
           (*print-readably* nil)
           (*read-default-float-format* 'double-float)
           (*print-pretty* t)
           (*print-right-margin* 110))
       ,@body)))

(defun cradle-scripts-text (&key (n 5))
  "The text of specs/newtons-cradle-scripts.lisp (see CRADLE-SCRIPT-FORMS)."
  (with-output-to-string (out)
    (with-library-print-syntax ()
        (format out ";;;; newtons-cradle-scripts.lisp -- the script library of specs/newtons-cradle.lisp:~%~
;;;; the cradle as props, and one script per op swinging the spheres for one~%~
;;;; second.  Generated by src/compose/cradle-scripts.lisp from the graph the spec~%~
;;;; is made of; regenerate with~%~
;;;;   (player.compose:write-cradle-scripts-file \"specs/newtons-cradle-scripts.lisp\")~%~
;;;; Draw it: make demo-cradle~%")
        (dolist (form (cradle-script-forms :n n))
          (format out "~%~S~%" form)))))

(defun write-cradle-scripts-file (file)
  "Write specs/newtons-cradle-scripts.lisp (to FILE) from CRADLE-SCRIPTS-TEXT."
  (with-atomic-output-file (out file :follow-links t)
    (write-string (cradle-scripts-text) out))
  file)
