;;;; spheres-scripts.lisp -- specs/bouncing-spheres-scripts.lisp: the script
;;;; library that draws specs/bouncing-spheres.lisp, written from the spec's
;;;; own state graph (one script per op, named as the op).
;;;;
;;;; The scene is props alone (the spec says (:body none)): the two horizontal
;;;; surfaces and two balls. A grid place (X, Y) is a point in the plane z = 0,
;;;; *SPHERES-CELL* apart; each op's script lasts one second, one step, and
;;;; moves each ball in a straight line at constant speed from its place in
;;;; the op's source state to its place in the target (the paper assumes
;;;; "constant sphere velocity"). A ball going round from one end of the
;;;; surfaces to the other leaves by one side and comes back by the other.

(in-package #:player.compose)

(defparameter *spheres-cell* 0.12d0 "The distance between two grid places, in metres.")
(defparameter *spheres-columns* 6 "How many columns the grid has (X from 0, going round).")
(defparameter *spheres-surfaces* '(0 2) "The rows of the lower and the upper surface.")
(defparameter *spheres-colours* '((0.75 0.18 0.15) (0.15 0.35 0.75)) "The balls' colours, leftmost sphere first.")

(defun grid-name-spheres (name)
  "The grid spheres ((X . Y) . (DX . DY)) a state name such as X0Y1NW-X4Y1NE
(GRID-SPHERE-NAME) stands for."
  (loop for part in (uiop:split-string (string-upcase name) :separator "-")
        collect (flet ((number-at (start)
                         (let* ((negative (char= (char part start) #\M))
                                (from (if negative (1+ start) start))
                                (end (or (position-if-not #'digit-char-p part :start from) (length part))))
                           (values (* (if negative -1 1) (parse-integer part :start from :end end)) end))))
                  (multiple-value-bind (x after-x) (number-at 1)
                    (multiple-value-bind (y after-y) (number-at (1+ after-x))
                      (cons (cons x y)
                            (cons (if (char= (char part (1+ after-y)) #\E) 1 -1)
                                  (if (char= (char part after-y) #\N) 1 -1))))))))

(defun grid-point (x y)
  "The scene position (a list X Y Z) of grid place X, Y."
  (list (rounded (* *spheres-cell* (- x (/ (1- *spheres-columns*) 2))))
        (rounded (+ 0.1d0 (* *spheres-cell* y)))
        0))

(defun spheres-scene-forms ()
  "The DEFOBJECT forms of the surfaces, the balls, the camera and lights."
  (let* ((width (rounded (* *spheres-cell* (1+ *spheres-columns*))))
         (half (rounded (/ *spheres-cell* 2))))
    (flet ((prop (name position colour size documentation)
             `(,(spec-symbol "defobject") ,(spec-symbol name) :kind :prop :position ,position
                :properties ((,(spec-symbol "colour") :colour ,colour) (,(spec-symbol "size") :vector ,size))
                :documentation ,documentation)))
      (append
       (list (prop "lower-surface" (list 0 (rounded (- (second (grid-point 0 (first *spheres-surfaces*))) half)) 0)
                   '(0.3 0.22 0.16) (list width 0.01 0.3) "The lower horizontal surface.")
             (prop "upper-surface" (list 0 (rounded (+ (second (grid-point 0 (second *spheres-surfaces*))) half)) 0)
                   '(0.35 0.35 0.38) (list width 0.01 0.3) "The upper horizontal surface."))
       (loop for colour in *spheres-colours*
             for k from 1
             collect (prop (format nil "ball-~D" k) (grid-point 0 0) colour '(0.1 0.1 0.1)
                           (format nil "Sphere ~D." k)))
       (list `(,(spec-symbol "defobject") ,(spec-symbol "camera") :kind :camera :position (0 0.22 1.1)
                :properties ((,(spec-symbol "fov") :number 35)) :documentation "The camera, in front of the surfaces.")
             `(,(spec-symbol "defobject") ,(spec-symbol "key-light") :kind :light :position (0.8 1.2 1.0)
                :properties ((,(spec-symbol "colour") :colour (1 0.95 0.85)) (,(spec-symbol "intensity") :number 1))))))))

(defun ball-keys (before after)
  "The position keys of one ball moving from grid sphere BEFORE to AFTER in one
second; a move going round the grid leaves on one side and comes in on the other."
  (let* ((x (caar before)) (y (cdar before)) (x2 (caar after)) (y2 (cdar after))
         (dx (- x2 x)))
    (if (<= (abs dx) 1)
        `((0 :vec3 ,@(grid-point x y)) (1 :vec3 ,@(grid-point x2 y2)))
        (let ((off (if (plusp dx) (1- x) (1+ x))))  ; where it would be, off the grid
          `((0 :vec3 ,@(grid-point x y)) (0.999 :vec3 ,@(grid-point off y2)) (1 :vec3 ,@(grid-point x2 y2)))))))

(defun spheres-move-script (name source target)
  "The DEFSCRIPT form NAME: one second moving each ball from its place in the
state named SOURCE to its place in the state named TARGET."
  `(,(spec-symbol "defscript") ,(spec-symbol "~A" name) (:duration 1 :documentation ,(format nil "~(~A to ~A~)" source target))
     ,@(loop for before in (grid-name-spheres source)
             for after in (grid-name-spheres target)
             for k from 1
             collect `(:at 0 :animate (,(spec-symbol "ball-~D" k) ,(spec-symbol "position"))
                           (:keys ,(ball-keys before after) :interpolation :linear)))))

(defun spheres-script-forms (spec)
  "The forms of the script library of SPEC (specs/bouncing-spheres.lisp): the
scene, then a script per op, named as the op."
  (multiple-value-bind (graph ops) (spec->graph spec)
    (double-floats
     (append (spheres-scene-forms)
             (loop for (source . target) in (graph-edges graph)
                   append (loop for op in (gethash (cons source target) ops)
                                collect (spheres-move-script (symbol-name op) (symbol-name source) (symbol-name target))))))))

(defun write-spheres-scripts-file (spec file)
  "Write the script library of SPEC (specs/bouncing-spheres-scripts.lisp) to FILE."
  (with-atomic-output-file (out file :follow-links t)
    (with-library-print-syntax ()
        (format out ";;;; bouncing-spheres-scripts.lisp -- the script library of specs/bouncing-spheres.lisp:~%~
;;;; two surfaces and two balls as props, and one script per op moving the balls~%~
;;;; for one second.  Generated by src/compose/spheres-scripts.lisp from the spec's~%~
;;;; state graph; regenerate it with write-spheres-scripts-file (same file).~%~
;;;; Draw it: make demo-spheres~%")
        (dolist (form (spheres-script-forms spec))
          (format out "~%~S~%" form))))
  file)
