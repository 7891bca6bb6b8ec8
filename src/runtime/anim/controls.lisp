;;;; controls.lisp -- controls: functions of time that drive a property's value.
;;;; A control (after ReActor) answers CONTROL-VALUE at any time, as a pure
;;;; function of the time: constants, keyframes with step, linear, ease-in-out
;;;; and Catmull-Rom interpolation, seeded Perlin noise for idle life, and sums
;;;; and products of controls. Values are numbers (double-floats), VEC3s or
;;;; unit QUATs; a control's KIND says which. PARSE-CONTROL reads the same
;;;; controls from s-expressions.

(in-package #:player)

;;;# Errors

;;; Named ANIM-CONTROL-ERROR because CL:CONTROL-ERROR (bad THROW targets) is
;;; taken, and the PLAYER package uses CL.
(define-condition anim-control-error (anim-error)
  ()
  (:documentation "A control is malformed: bad keys, an unknown interpolation mode,
values of mismatched kinds, or a bad argument. FORM is the offending form or value."))

(defun control-fail (form control &rest arguments)
  "Signal a ANIM-CONTROL-ERROR about FORM, with a message from CONTROL and ARGUMENTS."
  (apply #'anim-fail 'anim-control-error form control arguments))

;;;# Values

(deftype value-kind ()
  "The kinds of value a control produces."
  '(member :number :vec3 :quat))

(defun value-kind-of (value)
  "The VALUE-KIND of VALUE (a real, VEC3 or QUAT); signals a ANIM-CONTROL-ERROR for anything else."
  (typecase value
    (real :number)
    (vec3 :vec3)
    (quat :quat)
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
    (quat (qslerp a b u))))

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
  (unless (realp time)
    (control-fail time "the time of a control must be a real number of seconds"))
  (call-next-method control (float time 1d0)))

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

;;;# Keyframes

(deftype interpolation ()
  "The interpolation modes of a keys control."
  '(member :step :linear :ease-in-out :catmull-rom))

(defstruct (keys-control (:include control)
                         (:constructor %make-keys-control)
                         (:copier nil))
  "Keyframes: VALUES at increasing TIMES, interpolated by INTERPOLATION. TANGENTS
holds per-key slopes (Catmull-Rom numbers and vectors) or SQUAD control points
(Catmull-Rom rotations). When LOOP, time wraps with period PERIOD."
  (times (make-array 0 :element-type 'double-float)
   :type (simple-array double-float (*)) :read-only t)
  (values #() :type simple-vector :read-only t)
  (tangents nil :type (or null simple-vector) :read-only t)
  (interpolation :linear :type interpolation :read-only t)
  (loop nil :type boolean :read-only t)
  (period 0d0 :type double-float :read-only t))

(defun check-key (key)
  "Signal a ANIM-CONTROL-ERROR unless KEY is a (TIME . VALUE) cons with a real TIME."
  (unless (and (consp key) (realp (car key)))
    (control-fail key "a key must be a (time . value) pair with a real time")))

(defun check-keys (keys)
  "Check the key list KEYS: a nonempty proper list of (TIME . VALUE) keys with
strictly increasing times and values of one kind. Return that kind."
  (unless (and (listp keys) (null (cdr (last keys))))
    (control-fail keys "keys must be a list of (time . value) pairs"))
  (when (null keys)
    (error 'anim-control-error :message "a keys control needs at least one key"))
  (mapc #'check-key keys)
  (loop for (previous key) on keys
        while key
        unless (< (car previous) (car key))
          do (control-fail keys "keys are not sorted by strictly increasing time: ~A comes after ~A"
                           (anim-text key) (anim-text previous)))
  (let ((kind (value-kind-of (cdr (first keys)))))
    (dolist (key (rest keys) kind)
      (let ((other (value-kind-of (cdr key))))
        (unless (eq other kind)
          (control-fail key "key value is a ~(~A~) but the first key's value is a ~(~A~)"
                        other kind))))))

(defun check-interpolation (interpolation)
  "Signal a ANIM-CONTROL-ERROR unless INTERPOLATION is a known mode."
  (unless (typep interpolation 'interpolation)
    (control-fail interpolation
                  "unknown interpolation mode (expected :step, :linear, :ease-in-out or :catmull-rom)")))

(defun align-quats (quats)
  "Negate, in place, each quaternion of the simple-vector QUATS that lies in the
other hemisphere from its predecessor, so neighbours interpolate the short way."
  (loop for i from 1 below (length quats)
        when (minusp (qdot (svref quats (1- i)) (svref quats i)))
          do (setf (svref quats i) (qnegate (svref quats i))))
  quats)

(defun neighbour-keys (times key-values i looping period)
  "The keys before and after key I of TIMES and KEY-VALUES as four values:
previous time, previous value, next time, next value. At the ends, a LOOPING
control wraps around with PERIOD (key N-1 stands for key 0); a non-looping one
repeats key I."
  (let* ((n (length times))
         (last (1- n)))
    (flet ((key (j shift) (values (+ (aref times j) shift) (svref key-values j))))
      (multiple-value-bind (previous-time previous)
          (cond ((plusp i) (key (1- i) 0d0))
                ((and looping (> n 1)) (key (1- last) (- period)))
                (t (key i 0d0)))
        (multiple-value-bind (next-time next)
            (cond ((< i last) (key (1+ i) 0d0))
                  ((and looping (> n 1)) (key (min 1 last) period))
                  (t (key i 0d0)))
          (values previous-time previous next-time next))))))

(defun key-tangents (times key-values kind looping period)
  "For Catmull-Rom keys TIMES and KEY-VALUES of KIND (LOOPING with PERIOD or
not): for numbers and vectors the slope at each key, (next - previous) / (next
time - previous time), one-sided at the ends of a non-looping control; for
quaternions the SQUAD control points."
  (let ((tangents (make-array (length times))))
    (dotimes (i (length times) tangents)
      (multiple-value-bind (previous-time previous next-time next)
          (neighbour-keys times key-values i looping period)
        (let ((value (svref key-values i)))
          (setf (svref tangents i)
                (cond ((eq kind :quat)
                       (flet ((aligned (q) (if (minusp (qdot value q)) (qnegate q) q)))
                         (squad-control-point (aligned previous) value (aligned next))))
                      ((= previous-time next-time) (slope-value value value 1d0))
                      (t (slope-value previous next (- next-time previous-time))))))))))

(defun make-keys-control (keys &key (interpolation :linear) loop)
  "A control interpolating KEYS, a list of (TIME . VALUE) pairs sorted by strictly
increasing real TIME, whose VALUEs are all reals, all VEC3s or all QUATs.
INTERPOLATION is :step (hold each key until the next), :linear, :ease-in-out
(smoothstep between each pair of keys: zero slope at every key) or :catmull-rom
(a C1 cubic through the keys; slopes from the neighbouring keys). Rotations
interpolate by QSLERP for :linear and :ease-in-out and by QSQUAD for
:catmull-rom. Before the first key and after the last the end values hold;
when LOOP is true, time wraps instead with period (last time - first time), so
the last key should repeat the first. Signals a ANIM-CONTROL-ERROR for an empty,
unsorted or malformed key list, values of mixed kinds, or an unknown mode."
  (check-interpolation interpolation)
  (let* ((kind (check-keys keys))
         (times (map '(simple-array double-float (*)) (lambda (key) (float (car key) 1d0)) keys))
         (key-values (map 'simple-vector (lambda (key) (canonical-value (cdr key))) keys))
         (period (- (aref times (1- (length times))) (aref times 0)))
         (looping (and loop t)))
    (when (eq kind :quat)
      (align-quats key-values))
    (%make-keys-control :kind kind :times times :values key-values
                        :interpolation interpolation :loop looping :period period
                        :tangents (and (eq interpolation :catmull-rom)
                                       (key-tangents times key-values kind looping period)))))

(defun key-segment (times time)
  "The index I of the last key of the sorted TIMES with TIMES[I] <= TIME, for a
TIME within [TIMES[0], TIMES[N-1]), by binary search."
  (declare (type (simple-array double-float (*)) times) (type double-float time))
  (let ((low 0) (high (1- (length times))))
    (declare (type fixnum low high))
    ;; Invariant: times[low] <= time < times[high].
    (loop while (> (- high low) 1)
          do (let ((middle (ash (+ low high) -1)))
               (if (<= (aref times middle) time)
                   (setf low middle)
                   (setf high middle))))
    low))

(defun wrap-time (control time)
  "TIME mapped into CONTROL's key range when it loops, else TIME."
  (let ((period (keys-control-period control)))
    (if (and (keys-control-loop control) (plusp period))
        (let ((start (aref (keys-control-times control) 0)))
          (+ start (mod (- time start) period)))
        time)))

(defun segment-value (control i u)
  "The value of keys CONTROL at fraction U in [0, 1) of the segment from key I to key I+1."
  (let ((key-values (keys-control-values control))
        (times (keys-control-times control)))
    (ecase (keys-control-interpolation control)
      (:step (fresh-value (svref key-values i)))
      (:linear (lerp-value (svref key-values i) (svref key-values (1+ i)) u))
      (:ease-in-out (lerp-value (svref key-values i) (svref key-values (1+ i)) (smoothstep u)))
      (:catmull-rom
       (let ((tangents (keys-control-tangents control)))
         (if (eq (control-kind control) :quat)
             (qsquad (svref key-values i) (svref key-values (1+ i))
                     (svref tangents i) (svref tangents (1+ i)) u)
             (hermite-value (svref key-values i) (svref tangents i)
                            (svref key-values (1+ i)) (svref tangents (1+ i))
                            (- (aref times (1+ i)) (aref times i)) u)))))))

(defmethod control-value ((control keys-control) time)
  (let* ((times (keys-control-times control))
         (key-values (keys-control-values control))
         (last (1- (length times)))
         (time (wrap-time control time)))
    (cond ((<= time (aref times 0)) (fresh-value (svref key-values 0)))
          ((>= time (aref times last)) (fresh-value (svref key-values last)))
          (t (let ((i (key-segment times time)))
               (segment-value control i (/ (- time (aref times i))
                                           (- (aref times (1+ i)) (aref times i)))))))))

;;;# Perlin noise

(declaim (inline hash32))
(defun hash32 (n)
  "A well-mixed 32-bit hash of the integer N (its low 32 bits), for noise lattices."
  (let ((x (ldb (byte 32 0) n)))
    (declare (type (unsigned-byte 32) x))
    (setf x (ldb (byte 32 0) (* (logxor x (ash x -16)) #x7feb352d)))
    (setf x (ldb (byte 32 0) (* (logxor x (ash x -15)) #x846ca68b)))
    (logxor x (ash x -16))))

(defun lattice-gradient (key i)
  "The gradient in [-1, 1) at lattice point I (an integer) of the noise stream KEY."
  (let ((h (hash32 (logxor (hash32 key) (hash32 (ldb (byte 32 0) i)) (ash (ldb (byte 32 32) i) 1)))))
    (- (/ (float h 1d0) 2147483648d0) 1d0)))

(defun perlin-1d (key x)
  "Seeded 1-D gradient noise of the stream KEY (an integer) at the real X: C2
continuous, 0 at integers, within [-1, 1] (twice classic Perlin noise, whose
1-D range is [-1/2, 1/2])."
  (declare (type double-float x))
  (multiple-value-bind (i f) (floor x)
    (declare (type double-float f))
    (let ((a (* (lattice-gradient key i) f))
          (b (* (lattice-gradient key (1+ i)) (- f 1d0)))
          (s (* f f f (+ 10d0 (* f (- (* 6d0 f) 15d0))))))
      (* 2d0 (+ a (* s (- b a)))))))

(defstruct (noise-control (:include control)
                          (:constructor %make-noise-control)
                          (:copier nil))
  "Perlin noise of AMPLITUDE at FREQUENCY (lattice points per second), from SEED."
  (seed 0 :type (unsigned-byte 32) :read-only t)
  (amplitude 1d0 :type (double-float 0d0) :read-only t)
  (frequency 1d0 :type (double-float (0d0)) :read-only t))

(defun make-noise-control (&key (seed 0) (amplitude 1d0) (frequency 1d0) (kind :number))
  "A control of seeded Perlin noise for idle life: continuous, deterministic
for a SEED (an integer), changing about FREQUENCY times a second (a positive
real), never larger than AMPLITUDE (a nonnegative real). KIND :number gives a
real in [-AMPLITUDE, AMPLITUDE]; :vec3 a vector of three independent such
channels; :quat the rotation by Euler angles (QUAT-FROM-EULER) of three such
channels, in radians. Signals a ANIM-CONTROL-ERROR for a bad argument."
  (unless (integerp seed)
    (control-fail seed "the seed of a noise control must be an integer"))
  (unless (and (realp amplitude) (>= amplitude 0))
    (control-fail amplitude "the amplitude of a noise control must be a nonnegative real"))
  (unless (and (realp frequency) (> frequency 0))
    (control-fail frequency "the frequency of a noise control must be a positive real"))
  (unless (typep kind 'value-kind)
    (control-fail kind "unknown noise kind (expected :number, :vec3 or :quat)"))
  (%make-noise-control :kind kind :seed (ldb (byte 32 0) seed)
                       :amplitude (float amplitude 1d0) :frequency (float frequency 1d0)))

(defun noise-channel (control channel time)
  "Channel CHANNEL (0, 1 or 2) of noise CONTROL at TIME: a double-float within the amplitude."
  (let* ((key (hash32 (+ (noise-control-seed control) (* channel #x9e3779b9))))
         ;; A per-channel phase, so the channels do not all cross zero together.
         (phase (/ (float (hash32 (1+ key)) 1d0) 4294967296d0)))
    (* (noise-control-amplitude control)
       (perlin-1d key (+ phase (* time (noise-control-frequency control)))))))

(defmethod control-value ((control noise-control) time)
  (flet ((channel (c) (noise-channel control c time)))
    (ecase (control-kind control)
      (:number (channel 0))
      (:vec3 (vec3 (channel 0) (channel 1) (channel 2)))
      (:quat (quat-from-euler (channel 0) (channel 1) (channel 2))))))

;;;# Sums and products

(defstruct (combined-control (:include control)
                             (:constructor nil)
                             (:copier nil))
  "A control computed from the values of its CONTROLS at the same time."
  (controls #() :type simple-vector :read-only t))

(defstruct (sum-control (:include combined-control)
                        (:constructor %make-sum-control (kind controls))
                        (:copier nil))
  "The sum of its controls: numbers add, vectors add.")

(defstruct (product-control (:include combined-control)
                            (:constructor %make-product-control (kind controls))
                            (:copier nil))
  "The product of its controls: numbers multiply, rotations compose, numbers scale a vector.")

(defun check-controls (controls what)
  "Signal a ANIM-CONTROL-ERROR unless CONTROLS is a nonempty list of controls; WHAT names the combination."
  (when (null controls)
    (error 'anim-control-error :message (format nil "a ~A needs at least one control" what)))
  (dolist (control controls)
    (unless (control-p control)
      (control-fail control "a ~A combines controls, and this is not one" what))))

(defun make-sum-control (&rest controls)
  "A control whose value is the sum of the values of CONTROLS, all :number or
all :vec3. Signals a ANIM-CONTROL-ERROR when CONTROLS is empty, holds a non-control,
mixes kinds or holds rotations (rotations compose: use MAKE-PRODUCT-CONTROL)."
  (check-controls controls "sum")
  (let ((kind (control-kind (first controls))))
    (when (eq kind :quat)
      (control-fail (first controls) "rotations do not add; compose them with a product"))
    (dolist (control (rest controls))
      (unless (eq (control-kind control) kind)
        (control-fail control "cannot add a ~(~A~) control to a ~(~A~) control"
                      (control-kind control) kind)))
    (%make-sum-control kind (coerce controls 'simple-vector))))

(defun make-product-control (&rest controls)
  "A control whose value is the product of the values of CONTROLS, in order:
all :number multiply; all :quat compose (the product of A and B rotates by B,
then by A, so B acts in A's frame); one :vec3 among :numbers is scaled by them.
Signals a ANIM-CONTROL-ERROR when CONTROLS is empty, holds a non-control, or mixes
kinds otherwise."
  (check-controls controls "product")
  (let* ((kinds (mapcar #'control-kind controls))
         (kind (cond ((every (lambda (k) (eq k :number)) kinds) :number)
                     ((every (lambda (k) (eq k :quat)) kinds) :quat)
                     ((and (= 1 (count :vec3 kinds)) (null (remove :vec3 (remove :number kinds))))
                      :vec3)
                     (t (control-fail kinds "a product takes numbers, rotations, or one vector scaled by numbers; cannot multiply controls of these kinds")))))
    (%make-product-control kind (coerce controls 'simple-vector))))

(defmethod control-value ((control sum-control) time)
  (let ((controls (combined-control-controls control)))
    (if (eq (control-kind control) :number)
        (loop for c across controls sum (the double-float (control-value c time)) of-type double-float)
        (let ((sum (control-value (svref controls 0) time)))
          (loop for i from 1 below (length controls)
                do (nv+ sum (control-value (svref controls i) time)))
          sum))))

(defmethod control-value ((control product-control) time)
  (let ((controls (combined-control-controls control)))
    (ecase (control-kind control)
      (:number (let ((product 1d0))
                 (declare (type double-float product))
                 (loop for c across controls do (setf product (* product (control-value c time))))
                 product))
      (:quat (let ((product (control-value (svref controls 0) time)))
               (loop for i from 1 below (length controls)
                     do (nq* product (control-value (svref controls i) time)))
               (nqnormalize product)))
      (:vec3 (let ((scale 1d0) (vector nil))
               (declare (type double-float scale))
               (loop for c across controls
                     for value = (control-value c time)
                     do (if (vec3-p value) (setf vector value) (setf scale (* scale value))))
               (nv* vector scale))))))

;;;# Controls as s-expressions

(defun parse-value (form)
  "The control value FORM denotes: a real; a VEC3 or QUAT object; (:vec3 X Y Z);
(:quat W X Y Z) (normalized); (:axis-angle (X Y Z) ANGLE); (:euler X Y Z)
(radians, see QUAT-FROM-EULER). Signals a ANIM-CONTROL-ERROR naming FORM otherwise."
  (flet ((reals (list count)
           (unless (and (listp list) (null (cdr (last list))) (= (length list) count)
                        (every #'realp list))
             (control-fail form "~(~A~) takes ~D real numbers" (first form) count))
           list))
    (cond ((or (realp form) (vec3-p form) (quat-p form)) (canonical-value form))
          ((not (consp form))
           (control-fail form "a control value must be a number, (:vec3 x y z), (:quat w x y z), (:axis-angle (x y z) angle) or (:euler x y z)"))
          (t (case (first form)
               (:vec3 (apply #'make-vec3 (reals (rest form) 3)))
               (:quat (canonical-value (apply #'make-quat (reals (rest form) 4))))
               (:euler (apply #'quat-from-euler (reals (rest form) 3)))
               (:axis-angle
                (unless (and (= (length form) 3) (realp (third form)))
                  (control-fail form "(:axis-angle (x y z) angle) takes an axis and a real angle"))
                (quat-from-axis-angle (apply #'make-vec3 (reals (second form) 3)) (third form)))
               (t (control-fail form "unknown value form (expected :vec3, :quat, :axis-angle or :euler)")))))))

(defun parse-plist (form plist allowed)
  "Check that PLIST (from FORM) is a property list of keywords among ALLOWED; return it."
  (unless (and (listp plist) (null (cdr (last plist))) (evenp (length plist)))
    (control-fail form "options must come as :keyword value pairs"))
  (loop for (key) on plist by #'cddr
        unless (member key allowed)
          do (control-fail form "unknown option ~A (expected ~{~(~S~)~^, ~})" (anim-text key) allowed))
  plist)

(defun parse-control (form)
  "The control the s-expression FORM describes:
  VALUE                          a constant (see PARSE-VALUE)
  (:constant VALUE)
  (:keys ((TIME . VALUE)...) [:interpolation MODE] [:loop BOOLEAN])
  (:noise [:seed N] [:amplitude A] [:frequency F] [:kind KIND])
  (:sum CONTROL...)  (:product CONTROL...)
A CONTROL object stands for itself. Signals a ANIM-CONTROL-ERROR naming the offending form."
  (cond ((control-p form) form)
        ((not (and (consp form) (member (first form) '(:constant :keys :noise :sum :product))))
         (make-constant-control (parse-value form)))
        (t (destructuring-bind (head &rest arguments) form
             (unless (listp (cdr (last arguments)))
               (control-fail form "a control form must be a proper list"))
             (ecase head
               (:constant
                (unless (= (length arguments) 1)
                  (control-fail form "(:constant VALUE) takes exactly one value"))
                (make-constant-control (parse-value (first arguments))))
               (:keys
                (when (null arguments)
                  (control-fail form "(:keys KEYS ...) needs a list of keys"))
                (let ((keys (first arguments))
                      (options (parse-plist form (rest arguments) '(:interpolation :loop))))
                  (unless (and (listp keys) (null (cdr (last keys))))
                    (control-fail keys "keys must be a list of (time . value) pairs"))
                  (apply #'make-keys-control
                         (mapcar (lambda (key)
                                   (check-key key)
                                   (cons (car key) (parse-value (cdr key))))
                                 keys)
                         options)))
               (:noise
                (apply #'make-noise-control
                       (parse-plist form arguments '(:seed :amplitude :frequency :kind))))
               ((:sum :product)
                (when (null arguments)
                  (control-fail form "a ~(~A~) needs at least one control" head))
                (apply (if (eq head :sum) #'make-sum-control #'make-product-control)
                       (mapcar #'parse-control arguments))))))))
