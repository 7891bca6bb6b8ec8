;;;; blink.lisp -- the blink reflex (Pantomime's EyeBlinkReflex): the upper
;;;; lids close and open at exponentially distributed intervals, and on each
;;;; gaze shift.  Pure in time: the intervals are a function of the seed and
;;;; their index (SplitMix64), never of CL's global random state.

(in-package #:player.body)

;;;# Seeded intervals

(defun splitmix64 (seed index)
  "The INDEX-th (from 0) 64-bit output of SplitMix64 started from the integer
SEED (Steele, Lea & Flood, \"Fast splittable pseudorandom number generators\",
OOPSLA 2014): a pure function of SEED and INDEX."
  (flet ((u64 (x) (ldb (byte 64 0) x)))
    (let* ((z (u64 (+ seed (* (1+ index) #x9E3779B97F4A7C15))))
           (z (u64 (* (logxor z (ash z -30)) #xBF58476D1CE4E5B9)))
           (z (u64 (* (logxor z (ash z -27)) #x94D049BB133111EB))))
      (logxor z (ash z -31)))))

(defun blink-interval (seed index mean &optional (regularity 1))
  "The INDEX-th interval (seconds) between blinks for SEED, with mean MEAN:
exponentially distributed (by inverting the distribution at a uniform draw in
[0, 1)), or for a REGULARITY K above 1 the sum of K such draws of mean MEAN/K
\(a gamma distribution: intervals spread less, about MEAN/sqrt(K) apart)."
  (flet ((draw (n)
           (- (log (- 1d0 (* (ash (splitmix64 seed n) -11) (scale-float 1d0 -53)))))))
    (* (/ (to-double mean) regularity)
       (loop for j below regularity sum (draw (+ (* index regularity) j))))))

(defun blink-intervals (n &key (seed 1) (mean-interval 4.0))
  "The first N intervals (seconds) between the blinks of a blink driver with
SEED and MEAN-INTERVAL, as a list."
  (loop for index below n collect (blink-interval seed index mean-interval)))

;;;# The driver

(defclass blink-driver (driver)
  ((lids :accessor blink-lids :documentation "Per channel, its value when shut: each upper
lid's close DOF's limit, or 1 for a morph target that closes the eyes.")
   (open :accessor blink-open :documentation "Each lid's angle between blinks.")
   (times :initform (make-array 16 :adjustable t :fill-pointer 0) :reader blink-reflex-times
          :documentation "The reflex blinks' absolute times found so far, increasing."))
  (:documentation "Performs :blink: blinks at seeded exponential intervals from
its start, and at the start of each later gaze shift, until stopped."))

(defmethod driver-setup ((driver blink-driver))
  (unless (integerp (driver-arg driver :regularity))
    (driver-frame-fail driver ":regularity must be a whole number, not ~A" (lisp-text (driver-arg driver :regularity))))
  (unless (integerp (driver-arg driver :seed))
    (motor-fail (motor-call-frame (driver-call driver)) "blink :seed must be an integer, not ~A"
                (lisp-text (driver-arg driver :seed))))
  (let ((skeleton (driver-skeleton driver))
        (morphs (blink-morph-indices (driver-skeleton driver))))
    ;; A face of morph targets without lid joints closes its eyes with them.
    (when (and morphs (not (skeleton-role skeleton :left-upper-lid)))
      (setf (blink-lids driver) (mapcar (constantly 1d0) morphs))
      (return-from driver-setup morphs))
    (let ((lids (loop for role in '(:left-upper-lid :right-upper-lid)
                      collect (multiple-value-list (lid-close-channel driver (role-joint driver role))))))
      (setf (blink-lids driver) (mapcar #'second lids))
      (mapcar #'first lids))))

(defparameter *imported-lid-closing* 60
  "Degrees an imported model's upper lid (a joint without a close DOF) turns
about x to shut, as the humanoid's lids do.")

(defun lid-close-channel (driver lid)
  "The pose index that closes the upper LID and its value when shut, two
values: its DOF called close at its limit, or for an imported joint its x DOF
at *IMPORTED-LID-CLOSING* degrees (within its limits).  A MOTOR-ERROR when it
has neither."
  (let ((close (body-joint-dof lid 'close))
        (x (find :x (body-joint-dofs lid) :key #'body-dof-axis)))
    (cond (close (values (+ (body-joint-dof-start lid) (position close (body-joint-dofs lid)))
                         (float (body-dof-max close) 1d0)))
          (x (values (+ (body-joint-dof-start lid) (position x (body-joint-dofs lid)))
                     (min (float (body-dof-max x) 1d0) (float *imported-lid-closing* 1d0))))
          (t (motor-fail (motor-call-frame (driver-call driver))
                         "lid ~A of skeleton ~A has no DOF close"
                         (lisp-text (body-joint-name lid))
                         (lisp-text (skeleton-name (driver-skeleton driver))))))))

(defmethod driver-begin ((driver blink-driver) pose time)
  (declare (ignore time))
  (setf (blink-open driver) (loop for i in (driver-channels driver) collect (aref pose i))))

(defun reflex-blink-times (driver until)
  "DRIVER's reflex blink times (absolute, increasing), extended past UNTIL: the
cumulative sums of its intervals from its start, computed once and cached."
  (let ((times (blink-reflex-times driver)))
    ;; A forced blink (no :mean-interval): one, at the start.
    (unless (driver-arg driver :mean-interval)
      (when (zerop (fill-pointer times))
        (vector-push-extend (float (driver-start driver) 1d0) times))
      (return-from reflex-blink-times times))
    (loop while (or (zerop (fill-pointer times))
                    (<= (aref times (1- (fill-pointer times))) until))
          do (let ((index (fill-pointer times)))
               (vector-push-extend
                (+ (if (zerop index) (float (driver-start driver) 1d0) (aref times (1- index)))
                   (blink-interval (blink-seed driver) index (driver-real driver :mean-interval)
                                   (driver-arg driver :regularity)))
                times)))
    times))

(defun note-gaze-shifts (driver time)
  "The starts of the gaze drivers of DRIVER's body that started after DRIVER,
at or before TIME, increasing (from the body's record, BODY-GAZE-STARTS)."
  (when (driver-arg driver :on-gaze-shift)
    (let* ((starts (body-gaze-starts (driver-body driver)))
           (after (driver-start driver))
           ;; Binary search for the first start after DRIVER's own.
           (first (let ((lo 0) (hi (fill-pointer starts)))
                    (loop while (< lo hi)
                          do (let ((mid (floor (+ lo hi) 2)))
                               (if (<= (aref starts mid) after) (setf lo (1+ mid)) (setf hi mid))))
                    lo)))
      (loop for i from first below (fill-pointer starts)
            while (<= (aref starts i) time)
            collect (aref starts i)))))

(defun blink-times (driver until)
  "Every blink of DRIVER that starts by UNTIL, reflex and gaze shift, increasing."
  (let ((reflex (reflex-blink-times driver until)))
    (sort (append (remove-if (lambda (b) (> b until)) (coerce reflex 'list))
                  (remove-if (lambda (b) (> b until)) (note-gaze-shifts driver until)))
          #'<)))

(defun blink-closure (since duration)
  "How shut a lid is (0 open, 1 shut) SINCE seconds into a blink of DURATION:
eased shut by the middle, eased open by the end."
  (let ((u (/ since duration)))
    (cond ((or (< u 0) (> u 1)) 0d0)
          ((<= u 0.5d0) (smoothstep (* 2d0 u)))
          (t (smoothstep (- 2d0 (* 2d0 u)))))))

(defun blink-closure-at (driver time)
  "How shut DRIVER's lids are at TIME: the most of any blink under way."
  (let* ((duration (driver-real driver :duration))
         (times (reflex-blink-times driver time))
         ;; Binary search for the first reflex blink starting after TIME - DURATION.
         (low (let ((lo 0) (hi (fill-pointer times)))
                (loop while (< lo hi)
                      do (let ((mid (floor (+ lo hi) 2)))
                           (if (<= (aref times mid) (- time duration)) (setf lo (1+ mid)) (setf hi mid))))
                lo))
         (closure 0d0))
    (loop for i from low below (fill-pointer times)
          while (<= (aref times i) time)
          do (setf closure (max closure (blink-closure (- time (aref times i)) duration))))
    (dolist (start (note-gaze-shifts driver time) closure)
      (setf closure (max closure (blink-closure (- time start) duration))))))

(defmethod driver-drive ((driver blink-driver) time pose)
  (let ((closure (blink-closure-at driver time)))
    (when (driver-idle-p driver)
      ;; Idle life: shut from wherever the lids are.
      (loop for index in (driver-channels driver)
            for shut in (blink-lids driver)
            do (incf (aref pose index) (* closure (- shut (aref pose index)))))
      (return-from driver-drive pose))
    (loop for index in (driver-channels driver)
          for shut in (blink-lids driver)
          for open in (blink-open driver)
          do (setf (aref pose index) (+ open (* closure (- shut open)))))))

(define-motor-function :blink blink-driver
  "One forced blink (Pantomime's eyeblink); with :mean-interval, the blink
reflex: the upper lids close and open at seeded, exponentially distributed
intervals, and on each gaze shift, until stopped (Pantomime's blinkreflex)."
  (:mean-interval (:or :reflex-interval (:member nil)) nil "mean seconds between reflex blinks; NIL blinks once")
  (:regularity :positive 1 "1: exponential intervals (the reflex); a whole K above 1 spreads them less (a gamma of shape K)")
  (:idle :boolean nil "run as idle life: add onto the lids, yielding to any op that holds them")
  (:duration :brief 0.15 "seconds a blink takes, shut at its middle")
  (:seed :non-negative 1 "an integer choosing the sequence of intervals")
  (:on-gaze-shift :boolean t "also blink when a gaze shift starts")
  (:priority :real 50 "arbitration priority; higher wins"))

(defmethod driver-end-time ((driver blink-driver))
  (unless (driver-arg driver :mean-interval)
    (+ (driver-start driver) (driver-real driver :duration))))

(defmethod driver-additive-p ((driver blink-driver)) (driver-arg driver :idle))
(defmethod driver-idle-p ((driver blink-driver)) (driver-arg driver :idle))

(defmethod driver-default-blend ((driver blink-driver))
  ;; It eases from the angles it captured at its start: a crossfade would only slow it.
  0d0)

(defun blink-seed (driver)
  "DRIVER's :seed mixed with its body's seed, so `simulate --seed N` varies the blinks."
  (+ (driver-arg driver :seed) (* 7919 (body-seed (driver-body driver)))))
