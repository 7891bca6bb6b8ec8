;;;; contacts.lisp -- collision: ODE's dSpaceCollide calls back into Lisp for
;;;; each pair of geoms whose boxes overlap.  Stepping turns the touching
;;;; points into contact joints; a query lists who touches whom instead.

(in-package #:player.ode)

(defvar *colliding-world* nil
  "The ODE-WORLD whose space dSpaceCollide is walking (bound per thread).")

(defvar *near-function* nil
  "The Lisp function the near callback calls with the world and the two ODE-GEOMs.")

(cffi:defcallback near-callback :void ((data :pointer) (a :pointer) (b :pointer))
  (declare (ignore data))
  (let ((world *colliding-world*))
    (funcall *near-function* world (pointer-geom world a) (pointer-geom world b))))

(defun collide-world (world function)
  "Call FUNCTION with WORLD and each pair of enabled geoms of WORLD whose bounding boxes overlap."
  (let ((*colliding-world* world)
        (*near-function* function))
    (with-ode-traps-masked
      (%d-space-collide (ode-world-space world) (cffi:null-pointer) (cffi:callback near-callback)))))

(defmacro contact-size ()
  "The bytes of one dContact, found once at load time (CFFI parses a type spec
at run time otherwise, and collisions are queried many times a frame)."
  '(load-time-value (cffi:foreign-type-size '(:struct d-contact)) t))

(defun contact-pointer (world index)
  "The INDEXth dContact of WORLD's contact buffer."
  (cffi:inc-pointer (ode-world-contacts world) (* index (contact-size))))

(defun collide-geoms (world a b)
  "How many points (at most *MAX-CONTACTS*) geoms A and B touch at, written to WORLD's contact buffer."
  (with-ode-traps-masked
    (%d-collide (ode-geom-pointer a) (ode-geom-pointer b) *max-contacts*
                (cffi:foreign-slot-pointer (contact-pointer world 0) '(:struct d-contact) 'geom)
                (contact-size))))

(defun free-body-p (geom)
  "Does GEOM ride on a dynamic body (one forces move)?"
  (let ((body (ode-geom-body geom)))
    (and body (not (ode-body-kinematic body)))))

(defun add-contact-joints (world a b)
  "Join A and B where they touch, when one of them is free to move and they
are not on one body or already joined."
  (let ((body-a (ode-geom-body a)) (body-b (ode-geom-body b)))
    (when (and (or (free-body-p a) (free-body-p b))
               (not (eq body-a body-b))
               (let ((filter (ode-world-contact-filter world)))
                 (or (null filter) (funcall filter a b)))
               (not (and body-a body-b
                         (/= 0 (with-ode-traps-masked
                                 (%d-are-connected-excluding (ode-body-pointer body-a) (ode-body-pointer body-b)
                                                             +d-joint-type-contact+))))))
      (let ((count (collide-geoms world a b))
            (friction (sqrt (* (ode-geom-friction a) (ode-geom-friction b))))
            (bounce (max (ode-geom-bounce a) (ode-geom-bounce b))))
        (dotimes (i count)
          (let* ((contact (contact-pointer world i))
                 (surface (cffi:foreign-slot-pointer contact '(:struct d-contact) 'surface)))
            (cffi:with-foreign-slots ((mode mu bounce-vel soft-cfm) surface (:struct d-surface-parameters))
              (setf mode (logior +d-contact-bounce+ +d-contact-soft-cfm+ +d-contact-approx1+)
                    mu friction
                    bounce-vel 0.1d0
                    soft-cfm 1d-5))
            (setf (cffi:foreign-slot-value surface '(:struct d-surface-parameters) 'bounce) bounce)
            (with-ode-traps-masked
              (%d-joint-attach (%d-joint-create-contact (ode-world-pointer world) (ode-world-contact-group world)
                                                        contact)
                               (if body-a (ode-body-pointer body-a) (cffi:null-pointer))
                               (if body-b (ode-body-pointer body-b) (cffi:null-pointer))))))))))

;;;# Queries

(defun ode-geom-depth (a b)
  "How deep geoms A and B (of one live world) are inside each other, metres:
the deepest of their contact points, 0 when they do not touch.  Conses nothing;
the caller checks A and B, and has called ENSURE-ODE-THREAD in this thread."
  (let ((world (ode-geom-world a))
        (deepest 0d0))
    (declare (type double-float deepest))
    (dotimes (i (collide-geoms world a b) deepest)
      (let ((depth (cffi:foreign-slot-value (cffi:foreign-slot-pointer (contact-pointer world i) '(:struct d-contact) 'geom)
                                            '(:struct d-contact-geom) 'depth)))
        (declare (type double-float depth))
        (when (> depth deepest) (setf deepest depth))))))

(defstruct (ode-contact (:constructor make-ode-contact (position normal depth)))
  "Where two geoms touch: a POSITION and a NORMAL (lists x y z) and how DEEP
one is inside the other (metres)."
  (position nil :type list :read-only t)
  (normal nil :type list :read-only t)
  (depth 0d0 :type double-float :read-only t))

(defun read-contacts (world count)
  "The first COUNT contacts of WORLD's buffer, as ODE-CONTACTs."
  (loop for i below count
        collect (let ((geom (cffi:foreign-slot-pointer (contact-pointer world i) '(:struct d-contact) 'geom)))
                  (flet ((triple (slot)
                           (let ((p (cffi:foreign-slot-pointer geom '(:struct d-contact-geom) slot)))
                             (list (cffi:mem-aref p 'd-real 0) (cffi:mem-aref p 'd-real 1) (cffi:mem-aref p 'd-real 2)))))
                    (make-ode-contact (triple 'pos) (triple 'normal)
                                      (cffi:foreign-slot-value geom '(:struct d-contact-geom) 'depth))))))

(defun ode-geom-contacts (a b)
  "Where geoms A and B (of one world) touch: a list of ODE-CONTACTs, empty when they do not."
  (live-geom 'ode-geom-contacts a)
  (live-geom 'ode-geom-contacts b)
  (unless (eq (ode-geom-world a) (ode-geom-world b))
    (argument-fail 'ode-geom-contacts 'b b "a geom of the same world as A"))
  (ensure-ode-thread)
  (read-contacts (ode-geom-world a) (collide-geoms (ode-geom-world a) a b)))

(defun ode-world-touching-pairs (world &key (test (constantly t)) (min-depth 0))
  "Every pair of enabled geoms of WORLD that touch deeper than MIN-DEPTH metres
and pass TEST (a function of the two geoms), as (GEOM-A GEOM-B DEPTH), the
deepest contact's depth."
  (live-world 'ode-world-touching-pairs world)
  (ensure-ode-thread)
  (check-argument 'ode-world-touching-pairs :test test #'functionp "a function of two geoms")
  (check-real 'ode-world-touching-pairs :min-depth min-depth :minimum 0)
  (let ((pairs '()))
    (collide-world world
                   (lambda (world a b)
                     (when (funcall test a b)
                       (let ((count (collide-geoms world a b)))
                         (when (plusp count)
                           (let ((depth (reduce #'max (read-contacts world count) :key #'ode-contact-depth)))
                             (when (> depth min-depth)
                               (push (list a b depth) pairs))))))))
    (nreverse pairs)))
