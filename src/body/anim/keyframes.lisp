;;;; keyframes.lisp -- keyframe controls: step, linear, ease-in-out, Catmull-Rom (squad for rotations).

(in-package #:player.body)

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
  "Signal a ANIM-CONTROL-ERROR unless KEY is a (TIME . VALUE) cons with a finite
real TIME within +-*MAX-SECONDS*."
  (unless (and (consp key) (seconds-p (car key)))
    (control-fail key "a key must be a (time . value) pair with a real time, a finite number of seconds")))

(defun check-keys (keys)
  "Check the key list KEYS: a nonempty proper list of (TIME . VALUE) keys with
strictly increasing times and values of one kind. Return that kind."
  (unless (proper-form-list-p keys)
    (control-fail keys
                  "keys must be a proper list of (time . value) pairs"))
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
                  "unknown interpolation mode (expected :step, :linear, :ease-in-out (or :ease) or :catmull-rom)")))

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
(a C1 cubic through the keys; slopes from the neighbouring keys); :ease is
short for :ease-in-out. Rotations
interpolate by QSLERP for :linear and :ease-in-out and by QSQUAD for
:catmull-rom. Before the first key and after the last the end values hold;
when LOOP is true, time wraps instead with period (last time - first time), so
the last key should repeat the first. Signals a ANIM-CONTROL-ERROR for an empty,
unsorted or malformed key list, values of mixed kinds, or an unknown mode;
KEYS that are circular, or not a list, are also an ARGUMENT-ERROR."
  (check-argument 'make-keys-control 'keys keys #'proper-form-list-p
                  "a proper list of (time . value) pairs" 'control-argument-error)
  (when (eq interpolation :ease)         ; the short name authors reach for
    (setf interpolation :ease-in-out))
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
             (%qsquad (svref key-values i) (svref key-values (1+ i))
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
