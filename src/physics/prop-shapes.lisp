;;;; prop-shapes.lisp -- the collision shape of a prop, read as the renderer
;;;; draws it: a name with NOTE is a card, with FLOOR a plane, with BALL a
;;;; sphere, anything else a box; the SIZE property (a real or a vector,
;;;; metres) sizes it, else the renderer's default (src/render/scene-mesh.lisp
;;;; keeps the same table for drawing).

(in-package #:player.physics)

(defparameter *prop-shape-kinds* '(("NOTE" . :note) ("FLOOR" . :floor) ("BALL" . :sphere))
  "The shape kind of a prop whose name contains the key; any other prop is a :box.")

(defparameter *prop-default-sizes* '((:note 0.09 0.12 0.003) (:box 0.1 0.1 0.1) (:sphere 0.1))
  "Each shape kind's size when the prop declares none (as the renderer draws it).")

(defparameter *prop-density* 600d0
  "Kilograms per cubic metre of a dynamic prop that declares no MASS: light wood, card.")

(defun prop-shape-kind (object)
  "OBJECT's shape kind, from its name (*PROP-SHAPE-KINDS*)."
  (or (cdr (assoc-if (lambda (key) (search key (string (object-name object)) :test #'char-equal))
                     *prop-shape-kinds*))
      :box))

(defun declared-property (object name)
  "OBJECT's property NAME, or NIL when it has none."
  (and (property-type object name nil) (property-value object name)))

(defun prop-size (object kind)
  "OBJECT's size as a list of reals: its SIZE property (a real is a cube's edge,
a card's width) or KIND's default."
  (let ((size (declared-property object 'size)))
    (typecase size
      (vec3 (list (vec3-x size) (vec3-y size) (vec3-z size)))
      (real (if (eq kind :note) (list size (* 4/3 size) 0.003) (list size size size)))
      (t (rest (assoc kind *prop-default-sizes*))))))

(defun prop-shape (object)
  "The collision shape (a list, see src/ode/shapes.lisp) of the prop OBJECT in its
own frame, or NIL when it has none (a model prop, a degenerate size).  A floor
is the plane y = 0 of its frame, (:plane 0 1 0 0)."
  (check-argument 'prop-shape 'object object (lambda (x) (typep x 'scene-object)) "a scene object")
  (let ((kind (prop-shape-kind object)))
    (if (eq kind :floor)
        (list :plane 0 1 0 0)
        (let ((size (mapcar (lambda (x) (float x 1d0)) (prop-size object kind))))
          (when (every #'plusp size)
            (if (eq kind :sphere)
                (list :sphere (/ (first size) 2))
                (list* :box size)))))))

(defun shape-volume (shape)
  "The volume of SHAPE, cubic metres."
  (ecase (first shape)
    (:sphere (* 4/3 pi (expt (second shape) 3)))
    (:box (* (second shape) (third shape) (fourth shape)))
    (:capsule (destructuring-bind (r length) (rest shape)
                (+ (* pi r r length) (* 4/3 pi r r r))))))

(defun prop-mass (object shape)
  "OBJECT's mass in kilograms: its MASS property, or SHAPE's volume at *PROP-DENSITY*."
  (let ((mass (declared-property object 'mass)))
    (if (and (realp mass) (plusp mass))
        mass
        (max 1d-4 (* *prop-density* (shape-volume shape))))))

(defun prop-dynamic-p (object)
  "Is OBJECT a prop declared (defobject NAME ... :dynamic t) and still dynamic
\(its DYNAMIC property true)?"
  (and (typep object 'scene-object) (eq (object-kind object) :prop)
       (property-type object 'dynamic nil)
       (property-value object 'dynamic)
       t))

(defun dynamic-prop-p (object)
  "Was OBJECT declared dynamic (it has the DYNAMIC property, whatever its value)?"
  (and (typep object 'scene-object) (eq (object-kind object) :prop)
       (property-type object 'dynamic nil)
       t))
