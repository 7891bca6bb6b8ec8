;;;; noise.lisp -- seeded 1-D Perlin noise controls for idle life.

(in-package #:player.body)

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
  (unless (and (finite-number-p amplitude) (>= amplitude 0))
    (control-fail amplitude "the amplitude of a noise control must be a nonnegative real"))
  (unless (and (finite-number-p frequency) (< 0 frequency 1d6))
    (control-fail frequency "the frequency of a noise control must be a positive real below 1e6"))
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
