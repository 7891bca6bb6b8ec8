;;;; cradle-ode-scripts.lisp -- Newton's cradle swung by the physics (ODE,
;;;; src/physics/pendulums.lisp) instead of keyed: the scene of
;;;; cradle-scripts.lisp with each ball a dynamic prop hanging from its pivot,
;;;; perfectly elastic and frictionless, and one script, RELEASE, in which a
;;;; hand lifts the leftmost balls to the swing angle and lets go.  From then
;;;; on nothing is keyed: each ball is a pendulum, so it swings with the
;;;; pendulum's timing (a quarter period (pi/2)·sqrt(L/g), a little more at
;;;; 35 degrees) and the collisions pass the momentum along the row.

(in-package #:player.compose)

(defparameter *cradle-ode-gap* 0.001d0
  "Metres between resting balls (each is this much smaller than the spacing),
so a collision runs along the row one pair at a time, as in a real cradle.")

(defun cradle-ode-ball-form (form)
  "FORM, a ball's DEFOBJECT from CRADLE-SPHERE-FORMS, as a dynamic, hanging,
elastic ball; any other form unchanged."
  (destructuring-bind (head name &rest options) form
    (if (and (search "BALL" (string name)) (eq (getf options :kind) :prop))
        (let* ((properties (getf options :properties))
               (size (- (cradle-geometry :ball) *cradle-ode-gap*)))
          `(,head ,name ,@(alexandria:remove-from-plist options :properties)
                  :dynamic t
                  :properties (,@(remove "SIZE" properties :key (lambda (p) (string (first p))) :test #'string=)
                               (,(spec-symbol "size") :vector (,size ,size ,size))
                               (,(spec-symbol "hangs") :boolean t)
                               (,(spec-symbol "bounce") :number 1)
                               (,(spec-symbol "friction") :number 0))))
        form)))

(defun cradle-ode-script-forms (&key (n 5) (lifted 1))
  "The forms of a script library of the cradle of N balls swung by the physics:
the stand, the balls as pendulums, and RELEASE lifting the LIFTED leftmost
balls to the swing angle over *CRADLE-LIFT-SECONDS* and letting go."
  (check-argument 'cradle-ode-script-forms :n n (lambda (x) (typep x '(integer 2 9))) "an integer from 2 to 9")
  (check-argument 'cradle-ode-script-forms :lifted lifted (lambda (x) (and (typep x '(integer 1)) (< x n)))
                  "an integer from 1 to N - 1")
  (double-floats
   (append (cradle-frame-forms n)
           (mapcar #'cradle-ode-ball-form (cradle-sphere-forms n))
           (list `(,(spec-symbol "defscript") ,(spec-symbol "release")
                   (:duration ,*cradle-lift-seconds*
                    :documentation ,(format nil "A hand lifts the ~R leftmost ball~:P and lets go: the physics swings them." lifted lifted))
                   ,@(loop for k below lifted
                           collect `(:at 0 :animate (,(cradle-object-name "pivot-~D" (1+ k)) ,(spec-symbol "rotation"))
                                         (:keys ((0 :euler 0 0 0)
                                                 (,*cradle-lift-seconds* :euler 0 0 ,(rounded (cradle-angle -1))))
                                          :interpolation :ease))))))))
