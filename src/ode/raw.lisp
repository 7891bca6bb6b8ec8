;;;; raw.lisp -- ODE's C API as CFFI declares it: the %d functions, one per C
;;;; function Player calls, and the structs they fill.  Nothing here checks
;;;; anything; the files after this one do.  Debian builds ODE in double
;;;; precision (dDOUBLE in <ode/precision.h>), so dReal is a C double.

(in-package #:player.ode)

(cffi:defctype d-real :double "ODE's dReal: double precision in Debian's build.")

(cffi:defcstruct (d-surface-parameters :class d-surface-parameters)
  "dSurfaceParameters: how two touching surfaces behave."
  (mode :int) (mu d-real) (mu2 d-real) (rho d-real) (rho2 d-real) (rho-n d-real)
  (bounce d-real) (bounce-vel d-real) (soft-erp d-real) (soft-cfm d-real)
  (motion1 d-real) (motion2 d-real) (motion-n d-real) (slip1 d-real) (slip2 d-real))

(cffi:defcstruct (d-contact-geom :class d-contact-geom)
  "dContactGeom: one point where two geoms touch."
  (pos d-real :count 4) (normal d-real :count 4) (depth d-real)
  (g1 :pointer) (g2 :pointer) (side1 :int) (side2 :int))

(cffi:defcstruct (d-contact :class d-contact)
  "dContact: a contact point and the surface a contact joint gives it."
  (surface (:struct d-surface-parameters))
  (geom (:struct d-contact-geom))
  (fdir1 d-real :count 4))

(defconstant +d-contact-bounce+ #x004 "dContactBounce.")
(defconstant +d-contact-soft-cfm+ #x010 "dContactSoftCFM.")
(defconstant +d-contact-approx1+ #x7000 "dContactApprox1: friction pyramids on both directions and the normal.")
(defconstant +d-joint-type-contact+ 4 "dJointTypeContact in enum dJointType.")
(defconstant +d-mass-doubles+ 17 "A dMass is a dReal mass, a dVector3 centre and a dMatrix3 inertia: 17 dReals.")

(defmacro define-ode-functions (&body entries)
  "Declare each (LISP-NAME C-NAME RESULT-TYPE (ARG TYPE)...) as a foreign function."
  `(progn ,@(loop for (lisp-name c-name result . arguments) in entries
                  collect `(cffi:defcfun (,c-name ,lisp-name) ,result ,@arguments))))

(define-ode-functions
  ;; the library
  (%d-init-ode2 "dInitODE2" :int (flags :unsigned-int))
  (%d-close-ode "dCloseODE" :void)
  (%d-allocate-ode-data-for-thread "dAllocateODEDataForThread" :int (mask :unsigned-int))
  (%d-set-message-handler "dSetMessageHandler" :void (handler :pointer))
  ;; worlds
  (%d-world-create "dWorldCreate" :pointer)
  (%d-world-destroy "dWorldDestroy" :void (world :pointer))
  (%d-world-set-gravity "dWorldSetGravity" :void (world :pointer) (x d-real) (y d-real) (z d-real))
  (%d-world-set-erp "dWorldSetERP" :void (world :pointer) (erp d-real))
  (%d-world-set-cfm "dWorldSetCFM" :void (world :pointer) (cfm d-real))
  (%d-world-set-contact-surface-layer "dWorldSetContactSurfaceLayer" :void (world :pointer) (depth d-real))
  (%d-world-set-contact-max-correcting-vel "dWorldSetContactMaxCorrectingVel" :void (world :pointer) (vel d-real))
  (%d-world-set-auto-disable-flag "dWorldSetAutoDisableFlag" :void (world :pointer) (flag :int))
  (%d-world-set-auto-disable-steps "dWorldSetAutoDisableSteps" :void (world :pointer) (steps :int))
  (%d-world-set-linear-damping "dWorldSetLinearDamping" :void (world :pointer) (scale d-real))
  (%d-world-set-angular-damping "dWorldSetAngularDamping" :void (world :pointer) (scale d-real))
  (%d-world-step "dWorldStep" :int (world :pointer) (step d-real))
  ;; spaces
  (%d-simple-space-create "dSimpleSpaceCreate" :pointer (parent :pointer))
  (%d-space-destroy "dSpaceDestroy" :void (space :pointer))
  (%d-space-set-cleanup "dSpaceSetCleanup" :void (space :pointer) (mode :int))
  (%d-space-collide "dSpaceCollide" :void (space :pointer) (data :pointer) (callback :pointer))
  ;; bodies
  (%d-body-create "dBodyCreate" :pointer (world :pointer))
  (%d-body-set-position "dBodySetPosition" :void (body :pointer) (x d-real) (y d-real) (z d-real))
  (%d-body-set-quaternion "dBodySetQuaternion" :void (body :pointer) (q :pointer))
  (%d-body-get-position "dBodyGetPosition" :pointer (body :pointer))
  (%d-body-get-quaternion "dBodyGetQuaternion" :pointer (body :pointer))
  (%d-body-set-linear-vel "dBodySetLinearVel" :void (body :pointer) (x d-real) (y d-real) (z d-real))
  (%d-body-set-angular-vel "dBodySetAngularVel" :void (body :pointer) (x d-real) (y d-real) (z d-real))
  (%d-body-get-linear-vel "dBodyGetLinearVel" :pointer (body :pointer))
  (%d-body-get-angular-vel "dBodyGetAngularVel" :pointer (body :pointer))
  (%d-body-set-mass "dBodySetMass" :void (body :pointer) (mass :pointer))
  (%d-body-set-kinematic "dBodySetKinematic" :void (body :pointer))
  (%d-body-set-dynamic "dBodySetDynamic" :void (body :pointer))
  (%d-body-enable "dBodyEnable" :void (body :pointer))
  (%d-body-is-enabled "dBodyIsEnabled" :int (body :pointer))
  (%d-are-connected-excluding "dAreConnectedExcluding" :int (a :pointer) (b :pointer) (joint-type :int))
  ;; masses
  (%d-mass-set-zero "dMassSetZero" :void (mass :pointer))
  (%d-mass-set-sphere-total "dMassSetSphereTotal" :void (mass :pointer) (total d-real) (radius d-real))
  (%d-mass-set-box-total "dMassSetBoxTotal" :void (mass :pointer) (total d-real) (lx d-real) (ly d-real) (lz d-real))
  (%d-mass-set-capsule-total "dMassSetCapsuleTotal" :void (mass :pointer) (total d-real) (direction :int)
   (radius d-real) (length d-real))
  ;; geoms
  (%d-create-sphere "dCreateSphere" :pointer (space :pointer) (radius d-real))
  (%d-create-box "dCreateBox" :pointer (space :pointer) (lx d-real) (ly d-real) (lz d-real))
  (%d-create-capsule "dCreateCapsule" :pointer (space :pointer) (radius d-real) (length d-real))
  (%d-geom-capsule-set-params "dGeomCapsuleSetParams" :void (geom :pointer) (radius d-real) (length d-real))
  (%d-create-plane "dCreatePlane" :pointer (space :pointer) (a d-real) (b d-real) (c d-real) (d d-real))
  (%d-geom-set-body "dGeomSetBody" :void (geom :pointer) (body :pointer))
  (%d-geom-set-data "dGeomSetData" :void (geom :pointer) (data :pointer))
  (%d-geom-get-data "dGeomGetData" :pointer (geom :pointer))
  (%d-geom-set-position "dGeomSetPosition" :void (geom :pointer) (x d-real) (y d-real) (z d-real))
  (%d-geom-set-quaternion "dGeomSetQuaternion" :void (geom :pointer) (q :pointer))
  (%d-geom-set-offset-position "dGeomSetOffsetPosition" :void (geom :pointer) (x d-real) (y d-real) (z d-real))
  (%d-geom-enable "dGeomEnable" :void (geom :pointer))
  (%d-geom-disable "dGeomDisable" :void (geom :pointer))
  (%d-collide "dCollide" :int (a :pointer) (b :pointer) (flags :int) (contacts :pointer) (skip :int))
  ;; joints
  (%d-joint-group-create "dJointGroupCreate" :pointer (max-size :int))
  (%d-joint-group-destroy "dJointGroupDestroy" :void (group :pointer))
  (%d-joint-group-empty "dJointGroupEmpty" :void (group :pointer))
  (%d-joint-create-contact "dJointCreateContact" :pointer (world :pointer) (group :pointer) (contact :pointer))
  (%d-joint-create-ball "dJointCreateBall" :pointer (world :pointer) (group :pointer))
  (%d-joint-set-ball-anchor "dJointSetBallAnchor" :void (joint :pointer) (x d-real) (y d-real) (z d-real))
  (%d-joint-attach "dJointAttach" :void (joint :pointer) (a :pointer) (b :pointer)))
