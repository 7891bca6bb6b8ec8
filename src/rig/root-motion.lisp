;;;; root-motion.lisp -- a clip played with :root :move carries its character:
;;;; the body's position follows the horizontal travel of the clip's root
;;;; from where the body stood when the clip started, turned by the body's
;;;; rotation; a looping clip carries it steadily, at its cycle's average
;;;; velocity (CLIP-TRAVEL says why).  (:in-place, the default, drops the
;;;; travel: the clip driver only writes joint angles.)
;;;;
;;;; A driver writes a pose, not the body's place, so the travel is a CONTROL
;;;; of the body's POSITION property, which the performance binds for the
;;;; item's span, as it binds an :animate item's keys: bindings already set
;;;; properties before each body is evaluated, end with their item, and
;;;; leave the property where they last put it, so a walk ends where it went.

(in-package #:player.rig)

(defun horizontal (v)
  "V with its height dropped: its x and z, y = 0."
  (make-vec3 (vec3-x v) 0d0 (vec3-z v)))

(defun clip-travel (clip local loop)
  "How far CLIP has carried its root, horizontally, LOCAL seconds into it
\(from its root at the clip's start, a vec3 in the skeleton's frame): the
root's own keys, held after the clip's end; or, when LOOP, steadily: each
cycle's travel (the root's end less its start) spread evenly over the cycle.
A clip cut from capture seldom starts moving as it ends (CMU's 01_01 crouches
back before each jump), so following the keys of a loop would take the body
back at every seam and change its speed there; its average velocity carries
it on.  The wobble within a cycle is dropped, as :in-place drops it all."
  (let* ((duration (clip-duration clip))
         (start (clip-root-offset clip 0d0)))
    (flet ((travel (at) (horizontal (v- (clip-root-offset clip at) start))))
      (if (and loop (> duration 0d0))
          (v* (travel duration) (/ (float local 1d0) duration))
          (travel (max 0d0 (min local duration)))))))

(defstruct (root-motion-control (:include control (kind :vec3))
                                (:constructor %make-root-motion-control (driver origin turn))
                                (:copier nil))
  "The position of a body its clip DRIVER carries: ORIGIN, where it stood
when the clip started, plus the clip's travel turned by TURN, its rotation
then.  Its time is seconds since the driver started."
  (driver nil :read-only t)
  (origin (vec3) :type vec3 :read-only t)
  (turn (quat) :type quat :read-only t))

(defun moves-root-p (driver)
  "Does DRIVER play a clip with :root :move?"
  (and (typep driver 'clip-driver) (eq (driver-arg driver :root) :move)))

(defun make-root-motion-control (driver origin turn)
  "A control of the position of the body DRIVER (a CLIP-DRIVER with :root
:move) plays on: ORIGIN (a vec3, where it stands now) plus the horizontal
travel of the clip's root, turned by the quat TURN (its rotation now)."
  (check-argument 'make-root-motion-control 'driver driver #'moves-root-p "a clip driver playing with :root :move")
  (%make-root-motion-control driver (v+ origin (vec3)) turn))

(defmethod control-value ((control root-motion-control) time)
  (let* ((driver (root-motion-control-driver control))
         (local (* time (driver-real driver :speed))))
    (v+ (root-motion-control-origin control)
        (qrotate (root-motion-control-turn control)
                 (clip-travel (clip-driver-clip driver) local (driver-arg driver :loop))))))
