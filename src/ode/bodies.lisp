;;;; bodies.lisp -- rigid bodies: a mass with a place, a rotation and a velocity.
;;;; A dynamic body moves under gravity and contacts; a kinematic one is moved
;;;; by its owner (a prop in a hand, a script's keys) and pushes dynamic ones
;;;; without being pushed.

(in-package #:player.ode)

(defstruct (ode-body (:constructor %make-ode-body))
  "A rigid body of WORLD: its POINTER, its MASS (kg), whether it is
KINEMATIC, and DATA, whatever its owner hangs on it."
  (pointer (cffi:null-pointer) :type sb-sys:system-area-pointer)
  (world nil :type ode-world)
  (mass 1d0 :type double-float)
  (kinematic nil)
  (data nil))

(defun check-quaternion (function argument q)
  "Q, a list (W X Y Z) of finite reals not all zero; else an ARGUMENT-ERROR of FUNCTION."
  (check-argument function argument q
                  (lambda (x) (and (alexandria:proper-list-p x) (= (length x) 4) (every #'finite-real-p x)
                                   (some (lambda (c) (/= c 0)) x)))
                  "a list (W X Y Z) of finite numbers, not all zero"))

(defmacro with-quaternion ((pointer q) &body body)
  "Run BODY with POINTER to a dQuaternion holding Q, a list (W X Y Z), normalised."
  (alexandria:with-gensyms (norm i c)
    `(cffi:with-foreign-object (,pointer 'd-real 4)
       (let ((,norm (sqrt (reduce #'+ (mapcar (lambda (,c) (* ,c ,c)) ,q)))))
         (loop for ,c in ,q for ,i from 0
               do (setf (cffi:mem-aref ,pointer 'd-real ,i) (/ (float ,c 1d0) ,norm))))
       ,@body)))

(defun read-reals (pointer count)
  "COUNT dReals at POINTER, as values."
  (values-list (loop for i below count collect (cffi:mem-aref pointer 'd-real i))))

(defun live-body (function body)
  "BODY when it is a body of a live world; else an ARGUMENT-ERROR or ODE-ERROR of FUNCTION."
  (check-argument function 'body body #'ode-body-p "an ODE body (from make-ode-body)")
  (live-world function (ode-body-world body))
  body)

(defun make-ode-body (world shape &key (mass 1) (position '(0 0 0)) (rotation '(1 0 0 0)) kinematic data)
  "A body of WORLD whose MASS (kg) is spread over SHAPE (a sphere, box or capsule),
at POSITION (x y z) turned by ROTATION (w x y z), KINEMATIC or dynamic; DATA
is kept for its owner."
  (live-world 'make-ode-body world)
  (check-argument 'make-ode-body 'shape shape (lambda (x) (and (ode-shape-p x) (not (eq (first x) :plane))))
                  "a solid shape: (:sphere R), (:box X Y Z) or (:capsule R LENGTH), sizes positive")
  (check-real 'make-ode-body :mass mass :above 0 :maximum 1d6)
  (check-argument 'make-ode-body :position position #'finite-triple-p "a list of three finite numbers (metres)")
  (check-quaternion 'make-ode-body :rotation rotation)
  (let* ((pointer (with-ode-traps-masked (%d-body-create (ode-world-pointer world))))
         (body (%make-ode-body :pointer pointer :world world :mass (float mass 1d0) :data data)))
    (cffi:with-foreign-object (m 'd-real +d-mass-doubles+)
      (set-mass-of-shape m shape mass)
      (with-ode-traps-masked (%d-body-set-mass pointer m)))
    (set-ode-body-placement body position rotation)
    (setf (ode-body-kinematic-p body) kinematic)
    (push body (ode-world-bodies world))
    body))

(defun set-ode-body-placement (body position &optional rotation)
  "Put BODY at POSITION (x y z), turned by ROTATION (w x y z) when given; it wakes."
  (live-body 'set-ode-body-placement body)
  (check-argument 'set-ode-body-placement 'position position #'finite-triple-p "a list of three finite numbers (metres)")
  (when rotation (check-quaternion 'set-ode-body-placement 'rotation rotation))
  (let ((pointer (ode-body-pointer body)))
    (with-ode-traps-masked
      (apply #'%d-body-set-position pointer (mapcar (lambda (x) (float x 1d0)) position))
      (when rotation
        (with-quaternion (q rotation) (%d-body-set-quaternion pointer q)))
      (%d-body-enable pointer)))
  body)

(defun ode-body-position (body)
  "Where BODY's centre is: (values X Y Z)."
  (live-body 'ode-body-position body)
  (with-ode-traps-masked (read-reals (%d-body-get-position (ode-body-pointer body)) 3)))

(defun ode-body-rotation (body)
  "BODY's rotation: (values W X Y Z)."
  (live-body 'ode-body-rotation body)
  (with-ode-traps-masked (read-reals (%d-body-get-quaternion (ode-body-pointer body)) 4)))

(defun ode-body-velocity (body)
  "BODY's linear velocity, m/s: (values X Y Z)."
  (live-body 'ode-body-velocity body)
  (with-ode-traps-masked (read-reals (%d-body-get-linear-vel (ode-body-pointer body)) 3)))

(defun (setf ode-body-velocity) (velocity body)
  "Set BODY's linear velocity to VELOCITY (x y z, m/s); it wakes."
  (live-body '(setf ode-body-velocity) body)
  (check-argument '(setf ode-body-velocity) 'velocity velocity #'finite-triple-p "a list of three finite numbers (m/s)")
  (with-ode-traps-masked
    (apply #'%d-body-set-linear-vel (ode-body-pointer body) (mapcar (lambda (x) (float x 1d0)) velocity))
    (%d-body-enable (ode-body-pointer body)))
  velocity)

(defun ode-body-angular-velocity (body)
  "BODY's angular velocity, rad/s about x y z: (values X Y Z)."
  (live-body 'ode-body-angular-velocity body)
  (with-ode-traps-masked (read-reals (%d-body-get-angular-vel (ode-body-pointer body)) 3)))

(defun (setf ode-body-angular-velocity) (velocity body)
  "Set BODY's angular velocity to VELOCITY (x y z, rad/s)."
  (live-body '(setf ode-body-angular-velocity) body)
  (check-argument '(setf ode-body-angular-velocity) 'velocity velocity #'finite-triple-p
                  "a list of three finite numbers (rad/s)")
  (with-ode-traps-masked
    (apply #'%d-body-set-angular-vel (ode-body-pointer body) (mapcar (lambda (x) (float x 1d0)) velocity)))
  velocity)

(defun ode-body-kinematic-p (body)
  "Is BODY kinematic: moved by its owner, not by forces?"
  (check-argument 'ode-body-kinematic-p 'body body #'ode-body-p "an ODE body (from make-ode-body)")
  (ode-body-kinematic body))

(defun (setf ode-body-kinematic-p) (kinematic body)
  "Make BODY kinematic (true) or dynamic (NIL)."
  (live-body '(setf ode-body-kinematic-p) body)
  (let ((pointer (ode-body-pointer body)))
    (with-ode-traps-masked
      (if kinematic (%d-body-set-kinematic pointer) (%d-body-set-dynamic pointer))
      (%d-body-enable pointer)))
  (setf (ode-body-kinematic body) (and kinematic t)))

(defun ode-body-enabled-p (body)
  "Is BODY awake?  A body that has rested a while sleeps until something touches or moves it."
  (live-body 'ode-body-enabled-p body)
  (/= 0 (with-ode-traps-masked (%d-body-is-enabled (ode-body-pointer body)))))
