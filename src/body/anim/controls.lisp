;;;; controls.lisp -- controls: functions of time that drive a property's value.
;;;; A control (after ReActor) answers CONTROL-VALUE at any time, as a pure
;;;; function of the time: constants, keyframes with step, linear, ease-in-out
;;;; and Catmull-Rom interpolation, seeded Perlin noise for idle life, and sums
;;;; and products of controls. Values are numbers (double-floats), VEC3s or
;;;; unit QUATs; a control's KIND says which. PARSE-CONTROL reads the same
;;;; controls from s-expressions.

(in-package #:player.body)

;;;# Errors

;;; Named ANIM-CONTROL-ERROR because CL:CONTROL-ERROR (bad THROW targets) is
;;; taken, and the PLAYER package uses CL.
(define-condition anim-control-error (anim-error)
  ()
  (:documentation "A control is malformed: bad keys, an unknown interpolation mode,
values of mismatched kinds, or a bad argument. FORM is the offending form or value."))

(define-condition control-argument-error (argument-error anim-control-error)
  ()
  (:documentation "A control function was called with a bad argument: both an
ARGUMENT-ERROR (naming the function and argument) and an ANIM-CONTROL-ERROR."))

(defun control-fail (form control &rest arguments)
  "Signal a ANIM-CONTROL-ERROR about FORM, with a message from CONTROL and ARGUMENTS."
  (apply #'anim-fail 'anim-control-error form control arguments))

;;;# Values

(deftype value-kind ()
  "The kinds of value a control produces."
  '(member :number :vec3 :quat))

(defun value-kind-of (value)
  "The VALUE-KIND of VALUE (a finite real, VEC3 or QUAT); signals a
ANIM-CONTROL-ERROR for anything else, or for a NaN or infinity in it."
  (typecase value
    (real (if (finite-number-p value)
              :number
              (control-fail value "a control value must be a finite number")))
    (vec3 (if (finite-vec3-p value)
              :vec3
              (control-fail value "a control value's coordinates must be finite numbers")))
    (quat (if (finite-quat-p value)
              :quat
              (control-fail value "a control value's components must be finite numbers")))
    (t (control-fail value "a control value must be a number, a vec3 or a quat"))))

(defun canonical-value (value)
  "VALUE as a control stores it: a real as a double-float, a VEC3 copied, a QUAT
copied and normalized. Signals a ANIM-CONTROL-ERROR for a zero quaternion or a value
of no known kind."
  (ecase (value-kind-of value)
    (:number (float value 1d0))
    (:vec3 (copy-vec3 value))
    (:quat (if (zerop (qnorm value))
               (control-fail value "a rotation must be a nonzero quaternion")
               (qnormalize value)))))

(defun fresh-value (value)
  "A copy of the stored control value VALUE that a caller may modify."
  (etypecase value
    (double-float value)
    (vec3 (copy-vec3 value))
    (quat (copy-quat value))))

(declaim (inline smoothstep))
(defun smoothstep (u)
  "The cubic ease 3U^2 - 2U^3 of U in [0, 1]: 0 and 1 at the ends, with zero slope there."
  (declare (type double-float u))
  (* u u (- 3d0 (* 2d0 u))))

(defun lerp-value (a b u)
  "The value (1-U)A + UB between values A and B of one kind; quaternions by QSLERP."
  (declare (type double-float u))
  (etypecase a
    (double-float (+ a (* u (- (the double-float b) a))))
    (vec3 (vlerp a b u))
    (quat (%qslerp a b u))))

(defun hermite-value (p0 m0 p1 m1 h u)
  "The cubic Hermite curve at U in [0, 1] from value P0 (slope M0 per second) to
P1 (slope M1) over a segment H seconds long; values are double-floats or VEC3s."
  (declare (type double-float h u))
  (let* ((u2 (* u u)) (u3 (* u2 u))
         (h00 (+ (* 2d0 u3) (* -3d0 u2) 1d0))
         (h10 (* h (+ u3 (* -2d0 u2) u)))
         (h01 (+ (* -2d0 u3) (* 3d0 u2)))
         (h11 (* h (- u3 u2))))
    (etypecase p0
      (double-float (+ (* h00 p0) (* h10 (the double-float m0))
                       (* h01 (the double-float p1)) (* h11 (the double-float m1))))
      (vec3 (nv+ (nv+ (nv+ (v* p0 h00) (v* m0 h10)) (v* p1 h01)) (v* m1 h11))))))

(defun slope-value (a b dt)
  "The slope (B - A) / DT between values A and B (double-floats or VEC3s) DT seconds apart."
  (declare (type double-float dt))
  (etypecase a
    (double-float (/ (- (the double-float b) a) dt))
    (vec3 (nv* (v- b a) (/ dt)))))

;;;# The protocol

(defstruct (control (:constructor nil) (:copier nil))
  "A function of time producing values of one KIND (:number, :vec3 or :quat)."
  (kind :number :type value-kind :read-only t))

(defmethod print-object ((control control) stream)
  "Print CONTROL as #<TYPE KIND>, short enough for error messages."
  (print-unreadable-object (control stream :type t)
    (prin1 (control-kind control) stream)))

(defgeneric control-value (control time)
  (:documentation "The value of CONTROL at TIME (a real, in seconds): a double-float,
a fresh VEC3 or a fresh unit QUAT, depending only on CONTROL and TIME.
Signals a ANIM-CONTROL-ERROR when TIME is not a real."))

(defmethod control-value :around ((control control) time)
  "Check TIME and pass it on as a double-float."
  (unless (seconds-p time)
    (argument-fail 'control-value 'time time (seconds-phrase) 'control-argument-error))
  (call-next-method control (float time 1d0)))

(defmethod control-value (control time)
  "Anything but a control is an argument error."
  (declare (ignore time))
  (argument-fail 'control-value 'control control "a control (from parse-control, say)"
                 'control-argument-error))

;;;# Constants

(defstruct (constant-control (:include control)
                             (:constructor %make-constant-control (kind value))
                             (:copier nil))
  "A control whose value never changes."
  (value 0d0 :type (or double-float vec3 quat) :read-only t))

(defun make-constant-control (value)
  "A control that is always VALUE (a real, VEC3 or QUAT, copied).
Signals a ANIM-CONTROL-ERROR when VALUE is none of those."
  (%make-constant-control (value-kind-of value) (canonical-value value)))

(defmethod control-value ((control constant-control) time)
  (declare (ignore time))
  (fresh-value (constant-control-value control)))
