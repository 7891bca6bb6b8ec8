;;;; scene.lisp -- ReActor's scene: a hierarchy of named objects (bodies, props,
;;;; cameras, lights) with typed properties and local transforms.  World
;;;; transforms follow the hierarchy; an object may hang from another object or
;;;; from a joint of a body, and may be reparented (the note goes from the table
;;;; into the wing) keeping where it is in the world.

(in-package #:player.body)

;;;# Property types

(defparameter *property-types*
  '((:number finite-number-p "a finite number")
    (:vector finite-vec3-p "a vector (vec3) of finite numbers")
    (:rotation finite-quat-p "a rotation (a unit quaternion)")
    (:colour finite-vec3-p "a colour (vec3 of red, green, blue in [0, 1])")
    (:boolean boolean-value-p "T or NIL"))
  "The types a scene property may have: (TYPE PREDICATE DESCRIPTION).")

(defun boolean-value-p (x) "Is X T or NIL?" (member x '(t nil)))

(defun property-type-p (type)
  "Is TYPE one of *PROPERTY-TYPES*?"
  (assoc type *property-types*))

(defun coerce-property-value (value type form)
  "VALUE as a stored property of TYPE (numbers as double-floats, vectors and
rotations copied, rotations normalized); an ANIM-ERROR naming FORM when VALUE
does not have TYPE."
  (let ((entry (or (assoc type *property-types*)
                   (anim-fail 'anim-error form "unknown property type ~A (known: ~{~A~^ ~})"
                              (lisp-text type) (mapcar #'car *property-types*)))))
    (unless (funcall (second entry) value)
      (anim-fail 'anim-error form "~A must be ~A, not ~A" (bounded-anim-text form) (third entry)
                 (bounded-anim-text value)))
    (case type
      (:number (float value 1d0))
      (:rotation (if (zerop (qnorm value))
                     (anim-fail 'anim-error form "a rotation must be a nonzero quaternion")
                     (qnormalize value)))
      (:boolean value)
      (t (copy-vec3 value)))))

;;;# Objects

(defparameter *scene-object-kinds* '(:body :prop :camera :light :group)
  "The kinds of scene object.")

(defclass scene-object ()
  ((name :initarg :name :reader object-name)
   (kind :initarg :kind :reader object-kind)
   (parent :initarg :parent :initform nil :accessor object-parent
           :documentation "NIL (the scene root), a SCENE-OBJECT, or (OBJECT . JOINT-NAME).")
   (types :initform (make-hash-table :test #'equal) :reader object-property-types)
   (values :initform (make-hash-table :test #'equal) :reader object-property-values))
  (:documentation "A named object of a scene.  Every object has the properties
POSITION (vector, metres, relative to its parent), ROTATION (rotation) and
VISIBLE (boolean); others are declared with DEFINE-PROPERTY."))

(defmethod print-object ((object scene-object) stream)
  (print-unreadable-object (object stream :type t)
    (format stream "~A ~A" (lisp-text (object-kind object)) (lisp-text (object-name object)))))

(defparameter *builtin-properties* '((position :vector) (rotation :rotation) (visible :boolean))
  "The properties every scene object has, with their types; script libraries check against it.")

(defmethod initialize-instance :after ((object scene-object) &key (position (vec3)) (rotation (quat)))
  (unless (member (object-kind object) *scene-object-kinds*)
    (anim-fail 'anim-error (object-kind object) "object ~A: the kind must be one of ~{~A~^ ~}"
               (lisp-text (object-name object)) *scene-object-kinds*))
  (loop for (name type) in *builtin-properties*
        do (define-property object name type (ecase type
                                               (:vector position)
                                               (:rotation rotation)
                                               (:boolean t)))))

(defun scene-object-p (x)
  "Is X a scene object?"
  (typep x 'scene-object))

(defun property-types-phrase ()
  "The property types, for messages."
  (format nil "a property type (~{~(~S~)~^, ~})" (mapcar #'car *property-types*)))

(defun define-property (object name type value)
  "Give OBJECT the property NAME (a symbol, compared by name) of TYPE, set to VALUE."
  (check-argument 'define-property 'object object #'scene-object-p "a scene object" 'anim-argument-error)
  (check-argument 'define-property 'name name #'string-designator-p "a property name (a symbol or string)"
                  'anim-argument-error)
  (check-argument 'define-property 'type type #'property-type-p (property-types-phrase)
                  'anim-argument-error)
  (let ((key (string name)))
    (setf (gethash key (object-property-types object)) type)
    (setf (gethash key (object-property-values object))
          (coerce-property-value value type (list (object-name object) name)))))

(defun property-type (object name &optional (errorp t))
  "The type of OBJECT's property NAME; an ANIM-ERROR (or NIL without ERRORP) when it has none."
  (or (gethash (string name) (object-property-types object))
      (and errorp
           (anim-fail 'anim-error (list (object-name object) name)
                      "object ~A has no property ~A (it has ~{~A~^ ~})"
                      (lisp-text (object-name object)) (lisp-text name)
                      (sort (mapcar #'string-downcase
                                    (hash-table-keys (object-property-types object)))
                            #'string<)))))

(defun property-value (object name)
  "The current value of OBJECT's property NAME (do not modify it)."
  (check-argument 'property-value 'object object #'scene-object-p "a scene object" 'anim-argument-error)
  (check-argument 'property-value 'name name #'string-designator-p "a property name (a symbol or string)"
                  'anim-argument-error)
  (multiple-value-bind (value found) (gethash (string name) (object-property-values object))
    ;; Every declared property has a value: one lookup on the good path.
    (if found value (progn (property-type object name) nil))))

(defun (setf property-value) (value object name)
  "Set OBJECT's property NAME to VALUE, checked against its type."
  (check-argument '(setf property-value) 'object object #'scene-object-p "a scene object"
                  'anim-argument-error)
  (check-argument '(setf property-value) 'name name #'string-designator-p "a property name (a symbol or string)"
                  'anim-argument-error)
  (let ((type (property-type object name)))
    (setf (gethash (string name) (object-property-values object))
          (coerce-property-value value type (list (object-name object) name)))))

(defun object-local-transform (object)
  "OBJECT's transform relative to its parent, from its POSITION and ROTATION."
  (make-transform :rotation (property-value object 'rotation)
                  :translation (property-value object 'position)))

(defgeneric object-joint-transform (object joint-name)
  (:documentation "The world transform of OBJECT's joint JOINT-NAME, for objects
hanging from a joint; only bodies have joints.")
  (:method ((object scene-object) joint-name)
    (anim-fail 'anim-error joint-name "object ~A has no joints (it is a ~A), so nothing can hang from ~A"
               (lisp-text (object-name object)) (lisp-text (object-kind object))
               (lisp-text joint-name))))

(defun parent-world-transform (object)
  "The world transform OBJECT's local transform is relative to."
  (let ((parent (object-parent object)))
    (etypecase parent
      (null (identity-transform))
      (scene-object (object-world-transform parent))
      (cons (object-joint-transform (car parent) (cdr parent))))))

(defvar *world-transform-memo* nil
  "While WITH-WORLD-TRANSFORMS-MEMOISED runs: a table from each object to its
world transform, so N objects hanging in a chain cost N compositions, not
N^2/2 (20,000 library objects made check take minutes).")

(defmacro with-world-transforms-memoised (() &body body)
  "Run BODY with every object's world transform computed once: BODY must not
move, reparent or change any object meanwhile."
  `(let ((*world-transform-memo* (or *world-transform-memo* (make-hash-table :test #'eq))))
     ,@body))

(defun object-world-transform (object)
  "OBJECT's transform in the world: its parent's world transform times its
local one.  A fresh matrix, the caller's to change."
  (check-argument 'object-world-transform 'object object #'scene-object-p "a scene object"
                  'anim-argument-error)
  (let ((memo *world-transform-memo*))
    (if memo
        (copy-seq-mat4 (or (gethash object memo)
                           (setf (gethash object memo) (computed-world-transform object))))
        (computed-world-transform object))))

(defun copy-seq-mat4 (matrix)
  "A copy of the mat4 MATRIX."
  (let ((copy (make-array '(4 4) :element-type 'double-float)))
    (dotimes (i 16 copy)
      (setf (row-major-aref copy i) (row-major-aref matrix i)))))

(defun computed-world-transform (object)
  "OBJECT's world transform, computed from its parent's (OBJECT-WORLD-TRANSFORM)."
  (let ((local (object-local-transform object)))
    (declare (type mat4 local))
    (if (null (object-parent object))
        ;; The identity times LOCAL, without making either: the same numbers
        ;; (the product's sums turn a -0d0 entry into 0d0, so this does too).
        (dotimes (i 3 local)
          (dotimes (j 4)
            (setf (aref local i j) (+ (aref local i j) 0d0))))
        (transform-compose (parent-world-transform object) local local))))

(defun object-world-position (object)
  "Where OBJECT is in the world, as a new vec3."
  (check-argument 'object-world-position 'object object #'scene-object-p "a scene object"
                  'anim-argument-error)
  (transform-translation (object-world-transform object)))

;;;# Scenes

(defclass scene ()
  ((objects :initform '() :accessor scene-objects
            :documentation "Every object, in the order they were added.")
   (index :initform (make-hash-table :test #'equalp) :reader scene-index
          :documentation "The objects by name, so finding one does not grow with the scene.")
   (caption :initform nil :accessor scene-caption
            :documentation "A line of text drawn over the frame (an op's name while a
placeholder plays it), or NIL."))
  (:documentation "A set of named scene objects forming a hierarchy."))

(defun find-object (scene name &optional (errorp t))
  "SCENE's object called NAME (compared by name); an ANIM-ERROR listing the
objects, or NIL without ERRORP, when there is none."
  (check-argument 'find-object 'scene scene (lambda (x) (typep x 'scene)) "a scene" 'anim-argument-error)
  (check-argument 'find-object 'name name #'string-designator-p "an object's name (a symbol or string)"
                  'anim-argument-error)
  (or (gethash (string name) (scene-index scene))
      (and errorp
           (anim-fail 'anim-error name "the scene has no object ~A (objects: ~{~A~^ ~})"
                      (lisp-text name)
                      (mapcar (lambda (o) (lisp-text (object-name o))) (scene-objects scene))))))

(defun add-object (scene object)
  "Add OBJECT to SCENE; an ANIM-ERROR when the name is taken.  Returns OBJECT."
  (check-argument 'add-object 'scene scene (lambda (x) (typep x 'scene)) "a scene" 'anim-argument-error)
  (check-argument 'add-object 'object object #'scene-object-p "a scene object" 'anim-argument-error)
  (when (find-object scene (object-name object) nil)
    (anim-fail 'anim-error (object-name object) "the scene already has an object ~A"
               (lisp-text (object-name object))))
  (setf (scene-objects scene) (append (scene-objects scene) (list object))
        (gethash (string (object-name object)) (scene-index scene)) object)
  object)

(defun object-ancestor-p (ancestor object)
  "Does OBJECT hang, directly or not, from ANCESTOR (or is it ANCESTOR)?"
  (loop for o = object then (let ((parent (object-parent o)))
                              (if (consp parent) (car parent) parent))
        while o
        thereis (eq o ancestor)))

(defun reparent-object (object new-parent &key (keep-world t))
  "Hang OBJECT from NEW-PARENT: NIL, a scene object, or (OBJECT . JOINT-NAME).
With KEEP-WORLD, OBJECT's local transform changes so that it stays where it is
in the world.  An ANIM-ERROR, with nothing changed, for a cycle."
  (check-argument 'reparent-object 'object object #'scene-object-p "a scene object" 'anim-argument-error)
  (check-argument 'reparent-object 'new-parent new-parent
                  (lambda (x) (or (null x) (scene-object-p x)
                                  (and (consp x) (scene-object-p (car x)) (string-designator-p (cdr x)))))
                  "NIL, a scene object or (object . joint-name)" 'anim-argument-error)
  (let ((parent-object (if (consp new-parent) (car new-parent) new-parent)))
    (when (and parent-object (object-ancestor-p object parent-object))
      (anim-fail 'anim-error (object-name object) "cannot hang ~A from ~A: that would make a cycle"
                 (lisp-text (object-name object)) (lisp-text (object-name parent-object))))
    (let ((world (and keep-world (object-world-transform object))))
      (when (consp new-parent)
        ;; Resolve the joint now, so a bad name fails before anything moves.
        (object-joint-transform parent-object (cdr new-parent)))
      (setf (object-parent object) new-parent)
      (when keep-world
        (let ((local (transform-compose (transform-invert (parent-world-transform object)) world)))
          (setf (property-value object 'position) (transform-translation local)
                (property-value object 'rotation) (transform-rotation local))))
      object)))
