;;;; geoms.lisp -- collision shapes in a world's space.  A geom on a body moves
;;;; with it; a geom without one is static (the set) unless its owner places it
;;;; again (a bone, a prop moved by a script).  FRICTION and BOUNCE say how its
;;;; surface meets another's.

(in-package #:player.ode)

(defstruct (ode-geom (:constructor %make-ode-geom))
  "A collision SHAPE of WORLD: its POINTER, the BODY it rides on (or NIL), its
surface (FRICTION, a Coulomb coefficient; BOUNCE, restitution 0 to 1), whether
it is ENABLED, and DATA for its owner."
  (pointer (cffi:null-pointer) :type sb-sys:system-area-pointer)
  (world nil :type ode-world)
  (shape nil :type list)
  (body nil :type (or null ode-body))
  (friction 0.6d0 :type double-float)
  (bounce 0.1d0 :type double-float)
  (enabled t)
  (data nil))

(defun live-geom (function geom)
  "GEOM when it is a geom of a live world; else an ARGUMENT-ERROR or ODE-ERROR of FUNCTION."
  (check-argument function 'geom geom #'ode-geom-p "an ODE geom (from make-ode-geom)")
  (live-world function (ode-geom-world geom))
  geom)

(defun make-ode-geom (world shape &key body (position '(0 0 0)) (rotation '(1 0 0 0))
                                       (friction 0.6) (bounce 0.1) data)
  "A geom of SHAPE in WORLD's space, riding on BODY (an ODE-BODY of WORLD) or
static at POSITION (x y z) turned by ROTATION (w x y z); its surface has
FRICTION (0 to 10) and BOUNCE (0 to 1); DATA is kept for its owner."
  (live-world 'make-ode-geom world)
  (check-argument 'make-ode-geom 'shape shape #'ode-shape-p *shape-phrase*)
  (check-argument 'make-ode-geom :body body (lambda (x) (or (null x) (and (ode-body-p x) (eq (ode-body-world x) world))))
                  "NIL or a body of the same world")
  (when (and body (eq (first shape) :plane))
    (argument-fail 'make-ode-geom :body body "NIL: a plane cannot move"))
  (check-real 'make-ode-geom :friction friction :minimum 0 :maximum 10)
  (check-real 'make-ode-geom :bounce bounce :minimum 0 :maximum 1)
  (let* ((pointer (create-shape-geom (ode-world-space world) shape))
         (geom (%make-ode-geom :pointer pointer :world world :shape (copy-list shape) :body body
                               :friction (float friction 1d0) :bounce (float bounce 1d0) :data data)))
    ;; The geom's index, plus one (a null pointer is no geom), finds it again from C.
    (with-ode-traps-masked
      (%d-geom-set-data pointer (cffi:make-pointer (1+ (vector-push-extend geom (ode-world-geoms world)))))
      (when body (%d-geom-set-body pointer (ode-body-pointer body))))
    (unless (or body (eq (first shape) :plane))
      (set-ode-geom-placement geom position rotation))
    geom))

(defun set-ode-geom-placement (geom position &optional rotation)
  "Put GEOM at POSITION (x y z), turned by ROTATION (w x y z) when given (a
geom on a body moves the body)."
  (live-geom 'set-ode-geom-placement geom)
  (check-argument 'set-ode-geom-placement 'position position #'finite-triple-p "a list of three finite numbers (metres)")
  (when rotation (check-quaternion 'set-ode-geom-placement 'rotation rotation))
  (when (eq (first (ode-geom-shape geom)) :plane)
    (argument-fail 'set-ode-geom-placement 'geom geom "a geom that is not a plane (a plane cannot move)"))
  (let ((pointer (ode-geom-pointer geom)))
    (with-ode-traps-masked
      (%d-geom-set-position pointer (float (first position) 1d0) (float (second position) 1d0)
                            (float (third position) 1d0))
      (when rotation
        (with-quaternion (q rotation) (%d-geom-set-quaternion pointer q)))))
  geom)

(declaim (inline finite-double-p))
(defun finite-double-p (x)
  "Is the double-float X finite (not NaN, not an infinity)?  Reads its exponent
bits, comparing nothing, so it is safe with float traps enabled."
  (declare (type double-float x))
  (/= (ldb (byte 11 20) (sb-kernel:double-float-high-bits x)) #x7ff))

(defmacro with-finite-coordinates ((function &rest names) &body body)
  "Run BODY with each of NAMES (variables holding reals) rebound to its value as
a double-float, after checking each is a finite real; else an ARGUMENT-ERROR
of FUNCTION naming it."
  `(progn
     ,@(loop for name in names
             collect `(unless (and (typep ,name 'double-float) (finite-double-p ,name))
                        (check-argument ,function ',name ,name #'finite-real-p "a finite number")))
     (let ,(loop for name in names collect `(,name (float ,name 1d0)))
       (declare (type double-float ,@names))
       ,@body)))

(defun set-ode-geom-position (geom x y z)
  "Put GEOM at (X Y Z), finite reals (metres): SET-ODE-GEOM-PLACEMENT without a
rotation, and without consing (collision queries move bones every frame)."
  (live-geom 'set-ode-geom-position geom)
  (when (eq (first (ode-geom-shape geom)) :plane)
    (argument-fail 'set-ode-geom-position 'geom geom "a geom that is not a plane (a plane cannot move)"))
  (with-finite-coordinates ('set-ode-geom-position x y z)
    (with-ode-traps-masked
      (%d-geom-set-position (ode-geom-pointer geom) x y z)))
  geom)

(defun set-ode-geom-rotation (geom w x y z)
  "Turn GEOM by the rotation (W X Y Z), finite reals not all zero (normalised
here), without consing."
  (live-geom 'set-ode-geom-rotation geom)
  (when (eq (first (ode-geom-shape geom)) :plane)
    (argument-fail 'set-ode-geom-rotation 'geom geom "a geom that is not a plane (a plane cannot move)"))
  (with-finite-coordinates ('set-ode-geom-rotation w x y z)
    (let ((norm (sqrt (+ (* w w) (* x x) (* y y) (* z z)))))
      (when (zerop norm)
        (argument-fail 'set-ode-geom-rotation 'w w "a rotation (W X Y Z) not all zero"))
      (cffi:with-foreign-object (q 'd-real 4)
        (setf (cffi:mem-aref q 'd-real 0) (/ w norm) (cffi:mem-aref q 'd-real 1) (/ x norm)
              (cffi:mem-aref q 'd-real 2) (/ y norm) (cffi:mem-aref q 'd-real 3) (/ z norm))
        (with-ode-traps-masked (%d-geom-set-quaternion (ode-geom-pointer geom) q)))))
  geom)

(defun ode-geom-enabled-p (geom)
  "Does GEOM collide?"
  (check-argument 'ode-geom-enabled-p 'geom geom #'ode-geom-p "an ODE geom (from make-ode-geom)")
  (ode-geom-enabled geom))

(defun (setf ode-geom-enabled-p) (enabled geom)
  "Make GEOM collide (true) or be ignored (NIL)."
  (live-geom '(setf ode-geom-enabled-p) geom)
  (with-ode-traps-masked
    (if enabled (%d-geom-enable (ode-geom-pointer geom)) (%d-geom-disable (ode-geom-pointer geom))))
  (setf (ode-geom-enabled geom) (and enabled t)))

(defun pointer-geom (world pointer)
  "The ODE-GEOM of WORLD whose dGeom is at POINTER."
  (aref (ode-world-geoms world)
        (1- (cffi:pointer-address (with-ode-traps-masked (%d-geom-get-data pointer))))))

(defun set-ode-capsule-size (geom radius length)
  "Make the capsule GEOM RADIUS thick and LENGTH long between its caps' centres (metres)."
  (live-geom 'set-ode-capsule-size geom)
  (unless (eq (first (ode-geom-shape geom)) :capsule)
    (argument-fail 'set-ode-capsule-size 'geom geom "a capsule geom"))
  (check-real 'set-ode-capsule-size 'radius radius :above 0 :maximum 100)
  (check-real 'set-ode-capsule-size 'length length :minimum 0 :maximum 100)
  (with-ode-traps-masked
    (%d-geom-capsule-set-params (ode-geom-pointer geom) (float radius 1d0) (float length 1d0)))
  (setf (ode-geom-shape geom) (list :capsule radius length))
  geom)
