;;;; lips.lisp -- Pantomime's LipDriver: move the jaw (a parrot's lower beak)
;;;; through a timed list of visemes, the mouth shapes of speech, easing from
;;;; each to the next as speech coarticulates.  A face without a jaw joint but
;;;; with viseme or mouth morph targets (face-morphs.lisp) moves those instead.

(in-package #:player.body)

(defparameter *visemes*
  '((:rest 0    "silence: the mouth at rest")
    (:mm   0    "m b p: lips pressed shut")
    (:ff   0.1  "f v: the lower lip against the upper teeth")
    (:ss   0.15 "s z: teeth nearly together")
    (:th   0.2  "th: the tongue between the teeth")
    (:ch   0.25 "ch j sh: lips pushed out, teeth close")
    (:dd   0.3  "t d n: the tongue behind the teeth")
    (:rr   0.3  "r: lips a little rounded")
    (:oo   0.3  "oo (food), w: lips rounded, little opening")
    (:ee   0.35 "ee (see): lips spread, jaw nearly closed")
    (:kk   0.4  "k g ng: the back of the tongue raised")
    (:ll   0.4  "l: the tongue tip up, the jaw open a little")
    (:ih   0.5  "i (sit), e (bed): jaw half open")
    (:oh   0.7  "o (go), aw (saw): rounded and open")
    (:aa   1    "a (father), ah: the jaw wide open"))
  "Every viseme the :lips function knows: (NAME OPENING DOCUMENTATION).  OPENING
is the fraction of the jaw's opening range (its open DOF from closed to its
limit) the viseme takes.  The set follows the usual fifteen-viseme tables
\(MPEG-4 facial animation, Oculus Lipsync); only the jaw is modelled, so lip
rounding and spreading show as their openings.")

(defun viseme-opening (viseme)
  "The opening fraction of VISEME, or NIL when it is not in *VISEMES*."
  (second (assoc viseme *visemes*)))

(defclass lips-driver (driver)
  ((times :initform '() :accessor lips-times
          :documentation "Viseme times, seconds from the start, increasing.")
   (angles :initform '() :accessor lips-angles
           :documentation "Per viseme, the value of each of its channels (the jaw's open
angle, or the weights of the mouth's morph targets), a vector in channel order.")
   (from :initform #() :accessor lips-from
         :documentation "Each channel's value at the start."))
  (:documentation "Drives the jaw's open DOF (or the mouth's morph targets) through
timed visemes; each viseme's shape is reached at its time after a
:ramp-second ease that starts before it."))

(define-motor-function :lips lips-driver
  "Move the jaw (a parrot's beak) through timed visemes; ends when the last is formed.
Visemes and their openings (fractions of the jaw's range): :rest :mm 0, :ff 0.1,
:ss 0.15, :th 0.2, :ch 0.25, :dd :rr :oo 0.3, :ee 0.35, :kk :ll 0.4, :ih 0.5,
:oh 0.7, :aa 1.  End the list with :rest to close the mouth."
  (:visemes :list :required
   "((SECONDS VISEME) ...), increasing seconds from the start; each viseme is formed at its time")
  (:ramp :non-negative 0.06 "seconds the jaw takes into each viseme (coarticulation)")
  (:scale :non-negative 1.0 "multiplies every opening (capped at the jaw's limit)")
  (:priority :real 25 "arbitration priority; higher wins"))

(defparameter *imported-jaw-opening* 25
  "Degrees an imported model's jaw (a joint without an open DOF) turns about x
to open the mouth wide: a 45-50 mm incisal opening on a human.")

(defun jaw-open-channel (driver jaw)
  "The pose index of JAW's opening and its closed-to-open range, three values
INDEX LOW HIGH: its DOF called open, or for an imported joint its x DOF
opening up to *IMPORTED-JAW-OPENING* degrees.  A MOTOR-ERROR when it has neither."
  (let ((open (body-joint-dof jaw 'open))
        (x (find :x (body-joint-dofs jaw) :key #'body-dof-axis)))
    (cond (open (values (+ (body-joint-dof-start jaw) (position open (body-joint-dofs jaw)))
                        (float (body-dof-min open) 1d0) (float (body-dof-max open) 1d0)))
          (x (values (+ (body-joint-dof-start jaw) (position x (body-joint-dofs jaw)))
                     (float (body-dof-min x) 1d0)
                     (min (float (body-dof-max x) 1d0) (float *imported-jaw-opening* 1d0))))
          (t (driver-frame-fail driver "the jaw ~A has no DOF called open" (lisp-text (body-joint-name jaw)))))))

(defun viseme-angle (low high opening scale)
  "The angle of a jaw opening between LOW and HIGH for an OPENING fraction scaled by SCALE."
  (let ((closed (max low (min high 0d0))))
    (min high (+ closed (* (float (* opening scale) 1d0) (- high closed))))))

(defun check-viseme (driver viseme)
  "VISEME's opening; a MOTOR-ERROR naming the known visemes when it is none."
  (or (viseme-opening viseme)
      (driver-frame-fail driver "unknown viseme ~A (known: ~{~A~^ ~})" (lisp-text viseme)
                         (mapcar (lambda (v) (lisp-text (first v))) *visemes*))))

(defun lips-shapes (driver visemes)
  "The channels DRIVER drives and each of VISEMES' values on them, two values:
the jaw's opening when the skeleton has a :jaw, else the mouth's morph
targets (VISEME-MORPH-TABLE); a MOTOR-ERROR when it has neither."
  (let* ((skeleton (driver-skeleton driver))
         (jaw (skeleton-role skeleton :jaw))
         (scale (driver-arg driver :scale))
         (table (and (not jaw) (viseme-morph-table skeleton))))
    (cond (table
           (values (mapcar #'car (cdr (first table)))
                   (map 'simple-vector
                        (lambda (viseme)
                          (check-viseme driver viseme)
                          (map '(simple-array double-float (*))
                               (lambda (entry) (min 1d0 (* (cdr entry) (float scale 1d0))))
                               (cdr (assoc viseme table))))
                        visemes)))
          (t (multiple-value-bind (index low high) (jaw-open-channel driver (role-joint driver :jaw))
               (values (list index)
                       (map 'simple-vector
                            (lambda (viseme)
                              (make-array 1 :element-type 'double-float
                                            :initial-element (viseme-angle low high (check-viseme driver viseme) scale)))
                            visemes)))))))

(defmethod driver-setup ((driver lips-driver))
  (let ((visemes (driver-arg driver :visemes)))
    (unless (and (alexandria:proper-list-p visemes) visemes
                 (every (lambda (entry) (and (alexandria:proper-list-p entry) (= (length entry) 2)))
                        visemes))
      (driver-frame-fail driver ":visemes must be a nonempty list of (SECONDS VISEME) pairs"))
    (check-increasing-times driver (mapcar #'first visemes) "viseme times")
    (multiple-value-bind (channels shapes) (lips-shapes driver (mapcar #'second visemes))
      (setf (lips-times driver) (map 'times-vector (lambda (entry) (float (first entry) 1d0)) visemes)
            (lips-angles driver) shapes)
      channels)))

(defmethod driver-begin ((driver lips-driver) pose time)
  (declare (ignore time))
  (setf (lips-from driver) (map '(simple-array double-float (*)) (lambda (index) (aref pose index))
                                (driver-channels driver))))

(defun viseme-ramp-start (time ramp)
  "When the ease into a viseme at TIME (local seconds) begins: RAMP before it, not before the start."
  (max 0d0 (- time ramp)))

;;; The jaw angle is the start angle plus, for each viseme, its step from the
;;; previous viseme times a smoothstep ramp ending at its time.  The ramps
;;; have one length and start in order, so they are nested (each is at most
;;; the one before), and the sum is a convex combination of the viseme
;;; angles: it never leaves their range, and overlapping ramps in fast speech
;;; blend rather than overshoot.
(defmethod driver-drive ((driver lips-driver) time pose)
  ;; Ramps that have finished telescope to their viseme's angle and ramps not
  ;; yet begun add nothing, so only the few in progress need summing.
  (let* ((local (driver-local-time driver time))
         (ramp (float (driver-arg driver :ramp) 1d0))
         (times (lips-times driver))
         (shapes (lips-angles driver))
         (next (first-time-after times local)))
    (loop for index in (driver-channels driver)
          for c from 0
          do (let* ((previous (if (plusp next) (aref (svref shapes (1- next)) c) (aref (lips-from driver) c)))
                    (angle previous))
               (loop for i from next below (length times)
                     for at = (aref times i)
                     for value = (aref (svref shapes i) c)
                     while (< (viseme-ramp-start at ramp) local)
                     do (incf angle (* (eased-fraction local (viseme-ramp-start at ramp) ramp)
                                       (- value previous)))
                        (setf previous value))
               (setf (aref pose index) angle)))))

(defmethod driver-end-time ((driver lips-driver))
  (let ((ramp (float (driver-arg driver :ramp) 1d0)))
    (+ (driver-start driver)
       (+ (viseme-ramp-start (aref (lips-times driver) (1- (length (lips-times driver)))) ramp) ramp))))

(defmethod driver-default-blend ((driver lips-driver))
  ;; Visemes are short: a long crossfade would swallow the first ones.
  0.05d0)
