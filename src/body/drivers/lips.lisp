;;;; lips.lisp -- Pantomime's LipDriver: move the jaw (a parrot's lower beak)
;;;; through a timed list of visemes, the mouth shapes of speech, easing from
;;;; each to the next as speech coarticulates.

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
           :documentation "The jaw angle of each viseme.")
   (from :initform 0d0 :accessor lips-from
         :documentation "The jaw angle at the start."))
  (:documentation "Drives the jaw's open DOF through timed visemes; each viseme's
opening is reached at its time after a :ramp-second ease that starts before it."))

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

(defun jaw-open-dof (driver)
  "The jaw joint and its open DOF for DRIVER's skeleton, as two values; a MOTOR-ERROR if missing."
  (let* ((jaw (role-joint driver :jaw))
         (dof (body-joint-dof jaw 'open)))
    (unless dof
      (driver-frame-fail driver "the jaw ~A has no DOF called open" (lisp-text (body-joint-name jaw))))
    (values jaw dof)))

(defun viseme-angle (dof opening scale)
  "The angle of the jaw's open DOF for an OPENING fraction scaled by SCALE."
  (let* ((low (float (body-dof-min dof) 1d0))
         (high (float (body-dof-max dof) 1d0))
         (closed (max low (min high 0d0))))
    (min high (+ closed (* (float (* opening scale) 1d0) (- high closed))))))

(defmethod driver-setup ((driver lips-driver))
  (let ((visemes (driver-arg driver :visemes)))
    (unless (and (alexandria:proper-list-p visemes) visemes
                 (every (lambda (entry) (and (alexandria:proper-list-p entry) (= (length entry) 2)))
                        visemes))
      (driver-frame-fail driver ":visemes must be a nonempty list of (SECONDS VISEME) pairs"))
    (check-increasing-times driver (mapcar #'first visemes) "viseme times")
    (multiple-value-bind (jaw dof) (jaw-open-dof driver)
      (setf (lips-times driver) (map 'simple-vector (lambda (entry) (float (first entry) 1d0)) visemes)
            (lips-angles driver)
            (map 'simple-vector (lambda (entry)
                      (let ((opening (viseme-opening (second entry))))
                        (unless opening
                          (driver-frame-fail driver "unknown viseme ~A (known: ~{~A~^ ~})"
                                             (lisp-text (second entry))
                                             (mapcar (lambda (v) (lisp-text (first v))) *visemes*)))
                        (viseme-angle dof opening (driver-arg driver :scale))))
                    visemes))
      (list (+ (body-joint-dof-start jaw) (position dof (body-joint-dofs jaw)))))))

(defmethod driver-begin ((driver lips-driver) pose time)
  (declare (ignore time))
  (setf (lips-from driver) (aref pose (first (driver-channels driver)))))

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
         (angles (lips-angles driver))
         (next (first-time-after times local))
         (previous (if (plusp next) (svref angles (1- next)) (lips-from driver)))
         (angle previous))
    (loop for i from next below (length times)
          for at = (svref times i)
          while (< (viseme-ramp-start at ramp) local)
          do (incf angle (* (eased-fraction local (viseme-ramp-start at ramp) ramp)
                            (- (svref angles i) previous)))
             (setf previous (svref angles i)))
    (setf (aref pose (first (driver-channels driver))) angle)))

(defmethod driver-end-time ((driver lips-driver))
  (let ((ramp (float (driver-arg driver :ramp) 1d0)))
    (+ (driver-start driver)
       (+ (viseme-ramp-start (svref (lips-times driver) (1- (length (lips-times driver)))) ramp) ramp))))

(defmethod driver-default-blend ((driver lips-driver))
  ;; Visemes are short: a long crossfade would swallow the first ones.
  0.05d0)
