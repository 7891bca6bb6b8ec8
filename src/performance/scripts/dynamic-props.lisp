;;;; dynamic-props.lisp -- (defobject NAME :kind :prop ... :dynamic t): a prop
;;;; the physics moves (src/physics/).  It falls under gravity, collides with
;;;; the set and the other props and comes to rest; a hand or a script that
;;;; places it moves it, and when they let go it flies on.  Such a prop gets
;;;; two properties a script may set: DYNAMIC (NIL freezes it where it is)
;;;; and VELOCITY (m/s; setting it tosses the prop).

(in-package #:player.performance)

(defun dynamic-prop-properties (properties dynamic kind form)
  "PROPERTIES, the parsed (NAME TYPE VALUE) list of the defobject FORM of KIND,
with DYNAMIC and VELOCITY added when DYNAMIC is true."
  (unless (member dynamic '(t nil))
    (script-fail form ":dynamic must be T or NIL, not ~A" (lisp-text dynamic)))
  (cond ((not dynamic) properties)
        ((not (eq kind :prop))
         (script-fail form ":dynamic makes a prop move by physics; a ~A does not" (lisp-text kind)))
        (t (flet ((declared-p (name) (find name properties :key #'first :test #'string-equal)))
             (when (declared-p "DYNAMIC")
               (script-fail form "a dynamic prop has the property DYNAMIC already"))
             (append properties
                     (list (list 'dynamic :boolean t))
                     (unless (declared-p "VELOCITY")
                       (list (list 'velocity :vector (make-vec3 0d0 0d0 0d0)))))))))
