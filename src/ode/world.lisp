;;;; world.lisp -- an ODE world: the dynamics world, its collision space and its
;;;; group of contact joints, made and destroyed together.  A world is used by
;;;; one thread at a time; it is freed when destroyed or when the garbage
;;;; collector finds it unreachable, whichever comes first.

(in-package #:player.ode)

(defparameter *max-contacts* 8
  "The most contact points one pair of geoms gives in a step.")

(defstruct (ode-world (:constructor %make-ode-world))
  "A dynamics world with its collision space and contact joints.  GEOMS and
BODIES are the Lisp sides of what was made in it, in order of making."
  (pointer (cffi:null-pointer) :type sb-sys:system-area-pointer)
  (space (cffi:null-pointer) :type sb-sys:system-area-pointer)
  (contact-group (cffi:null-pointer) :type sb-sys:system-area-pointer)
  (contacts (cffi:null-pointer) :type sb-sys:system-area-pointer)
  (geoms (make-array 8 :adjustable t :fill-pointer 0) :type vector)
  (bodies '() :type list)
  (gravity '(0d0 -9.81d0 0d0) :type list)
  (step-size (/ 1d0 240) :type double-float)
  ;; NIL, or a function of two geoms: false when they must not touch (a
  ;; pendulum's sphere and its own string).
  (contact-filter nil)
  (live t))

(defmethod print-object ((world ode-world) stream)
  (print-unreadable-object (world stream :type t :identity t)
    (format stream "~D geoms~:[, destroyed~;~]" (fill-pointer (ode-world-geoms world)) (ode-world-live world))))

(defun finite-triple-p (x)
  "Is X a list of three finite reals?"
  (and (alexandria:proper-list-p x) (= (length x) 3) (every #'finite-real-p x)))

(defun make-ode-world (&key (gravity '(0 -9.81 0)) (step-size (/ 1d0 240)))
  "A fresh world pulling with GRAVITY (x y z, m/s²), stepped STEP-SIZE seconds
at a time, with an empty collision space.  Signals ODE-UNAVAILABLE (naming
libode8) when ODE is not installed."
  (check-argument 'make-ode-world :gravity gravity #'finite-triple-p "a list of three finite numbers (m/s²)")
  (check-real 'make-ode-world :step-size step-size :above 0 :maximum 1)
  (ensure-ode-thread)
  (let* ((gravity (mapcar (lambda (g) (float g 1d0)) gravity))
         (world (with-ode-traps-masked (%d-world-create)))
         (space (with-ode-traps-masked (%d-simple-space-create (cffi:null-pointer))))
         (group (with-ode-traps-masked (%d-joint-group-create 0)))
         (contacts (cffi:foreign-alloc '(:struct d-contact) :count *max-contacts*)))
    (with-ode-traps-masked
      (apply #'%d-world-set-gravity world gravity)
      ;; Stiff, slightly soft contacts that rest without jitter; a body at rest sleeps;
      ;; a little angular damping settles a card that rocks (no linear damping: free fall is exact).
      (%d-world-set-erp world 0.2d0)
      (%d-world-set-cfm world 1d-5)
      (%d-world-set-contact-surface-layer world 0.00002d0)
      (%d-world-set-contact-max-correcting-vel world 1d0)
      (%d-world-set-auto-disable-flag world 1)
      (%d-world-set-auto-disable-steps world 20)
      (%d-world-set-angular-damping world 0.002d0)
      ;; Destroying the space destroys its geoms.
      (%d-space-set-cleanup space 1))
    (let ((lisp-world (%make-ode-world :pointer world :space space :contact-group group :contacts contacts
                                       :gravity gravity :step-size (float step-size 1d0))))
      (sb-ext:finalize lisp-world (lambda () (free-world-pointers world space group contacts))
                       :dont-save t)
      lisp-world)))

(defun free-world-pointers (world space group contacts)
  "Free what MAKE-ODE-WORLD allocated: the contact joints, the space and its
geoms, the world and its bodies and joints, the contact buffer."
  (with-ode-traps-masked
    (%d-joint-group-destroy group)
    (%d-space-destroy space)
    (%d-world-destroy world))
  (cffi:foreign-free contacts))

(defun destroy-ode-world (world)
  "Free WORLD and everything in it now; using it afterwards is an ODE-ERROR."
  (check-argument 'destroy-ode-world 'world world #'ode-world-p "an ODE world (from make-ode-world)")
  (when (ode-world-live world)
    (sb-ext:cancel-finalization world)
    (setf (ode-world-live world) nil)
    (free-world-pointers (ode-world-pointer world) (ode-world-space world)
                         (ode-world-contact-group world) (ode-world-contacts world)))
  nil)

(defun live-world (function world)
  "WORLD when it is a live ODE world; else an ARGUMENT-ERROR or ODE-ERROR of FUNCTION."
  (check-argument function 'world world #'ode-world-p "an ODE world (from make-ode-world)")
  (unless (ode-world-live world)
    (ode-fail "~(~A~): the ODE world was destroyed" function))
  world)

(defun ode-world-step (world &optional (steps 1))
  "Advance WORLD by STEPS steps of its step size: collide (contact joints for
every touching pair with something free to move), step the dynamics, forget
the contacts."
  (live-world 'ode-world-step world)
  (check-argument 'ode-world-step 'steps steps (lambda (x) (typep x '(integer 0 1000000))) "a count of steps")
  ;; A world made in one thread may be stepped in another (the viewer's).
  (ensure-ode-thread)
  (let ((step (ode-world-step-size world)))
    (dotimes (i steps)
      (collide-world world #'add-contact-joints)
      (with-ode-traps-masked
        (when (zerop (%d-world-step (ode-world-pointer world) step))
          (ode-fail "the ODE world failed to step (out of memory)"))
        (%d-joint-group-empty (ode-world-contact-group world)))))
  world)
