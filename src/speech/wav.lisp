;;;; wav.lisp -- sounds in memory and RIFF WAV files (PCM, 8 or 16 bits, any
;;;; channels, read as mono 16-bit), and resampling between rates.  Speech,
;;;; sound effects and the performance's mixed track are all SOUNDs.

(in-package #:player.speech)

(deftype samples () "Mono 16-bit audio samples." '(simple-array (signed-byte 16) (*)))

(defstruct (sound (:constructor make-sound (samples rate)))
  "Mono 16-bit audio: SAMPLES at RATE samples a second."
  (samples (make-array 0 :element-type '(signed-byte 16)) :type samples :read-only t)
  (rate 22050 :type (integer 1) :read-only t))

(defun sound-duration (sound)
  "How long SOUND lasts, in seconds."
  (/ (length (sound-samples sound)) (float (sound-rate sound) 1d0)))

(defun make-samples (count)
  "A zeroed sample vector of COUNT samples."
  (make-array count :element-type '(signed-byte 16) :initial-element 0))

(defun clamp-sample (x)
  "X rounded and clipped to the 16-bit range."
  (max -32768 (min 32767 (round x))))

;;;# Reading

(defun wav-fail (path control &rest arguments)
  "Signal a SPEECH-ERROR: the WAV file PATH cannot be used, for the reason CONTROL and ARGUMENTS give."
  (speech-fail "cannot read the WAV file ~A: ~?" (namestring path) control arguments))

(defparameter *wav-rates* '(8000 96000)
  "The lowest and highest sample rate, in Hz, of a WAV file Player reads: a
rate outside makes resampling allocate without bound (1 Hz to 16 kHz is 16,000 times the samples).")

(defparameter *max-wav-seconds* 600
  "The longest WAV file Player reads, in seconds.")

(defparameter *max-wav-bytes* (* 128 1024 1024)
  "The largest WAV file Player reads, in bytes.")

(defun read-file-octets (path)
  "The bytes of the file PATH; a SPEECH-ERROR when it is missing, unreadable,
not a regular file or larger than *MAX-WAV-BYTES*."
  (handler-case (file-octets path :limit *max-wav-bytes*)
    (io-error (e) (wav-fail path "~A" (if (file-kind path) (io-error-reason e) "there is no such file")))))

(defun u16 (octets at) "The little-endian unsigned 16-bit integer at AT." (logior (aref octets at) (ash (aref octets (1+ at)) 8)))
(defun u32 (octets at) "The little-endian unsigned 32-bit integer at AT." (logior (u16 octets at) (ash (u16 octets (+ at 2)) 16)))

(defun riff-chunks (octets path)
  "The chunks of the RIFF WAVE file in OCTETS, as (ID START SIZE) with START the
offset of the chunk's data; a SPEECH-ERROR about PATH when it is not one."
  (unless (and (>= (length octets) 12)
               (string= "RIFF" (map 'string #'code-char (subseq octets 0 4)))
               (string= "WAVE" (map 'string #'code-char (subseq octets 8 12))))
    (wav-fail path "it is not a RIFF WAVE file"))
  (loop with at = 12
        while (<= (+ at 8) (length octets))
        collect (let ((size (u32 octets (+ at 4))))
                  (list (map 'string #'code-char (subseq octets at (+ at 4)))
                        (+ at 8) (min size (- (length octets) at 8))))
        do (incf at (+ 8 (u32 octets (+ at 4)) (if (oddp (u32 octets (+ at 4))) 1 0)))))

(defun read-wav (path)
  "The sound in the WAV file PATH, its channels averaged to mono.  Reads PCM
\(format 1, or WAVE_FORMAT_EXTENSIBLE holding PCM) of 8 or 16 bits.  Signals a
SPEECH-ERROR naming PATH when the file is missing, unreadable, not a WAV file,
or of another encoding."
  (check-argument 'read-wav 'path path #'pathname-designator-p *path-phrase*)
  (let* ((octets (read-file-octets path))
         (chunks (riff-chunks octets path))
         (format-chunk (or (assoc "fmt " chunks :test #'string=) (wav-fail path "it has no fmt chunk")))
         (data (or (assoc "data" chunks :test #'string=) (wav-fail path "it has no data chunk"))))
    (destructuring-bind (start size) (rest format-chunk)
      (when (< size 16) (wav-fail path "its fmt chunk is too short"))
      (let ((tag (u16 octets start)) (channels (u16 octets (+ start 2)))
            (rate (u32 octets (+ start 4))) (bits (u16 octets (+ start 14))))
        (when (and (= tag #xFFFE) (>= size 26))
          (setf tag (u16 octets (+ start 24)))) ; the sub-format GUID's first two bytes
        (unless (= tag 1) (wav-fail path "it is not PCM (format tag ~D); convert it, e.g. sox IN -b 16 OUT.wav" tag))
        (unless (member bits '(8 16)) (wav-fail path "it has ~D-bit samples; 8 and 16 are read" bits))
        (unless (and (<= 1 channels 2) (<= (first *wav-rates*) rate (second *wav-rates*)))
          (wav-fail path "it declares ~D channel~:P at ~:D Hz; 1 or 2 channels at ~:D to ~:D Hz are read"
                    channels rate (first *wav-rates*) (second *wav-rates*)))
        (when (> (/ (third data) (* channels (/ bits 8)) rate) *max-wav-seconds*)
          (wav-fail path "it lasts more than ~D s" *max-wav-seconds*))
        (make-sound (decode-pcm octets (second data) (third data) channels bits) rate)))))

(defun decode-pcm (octets start size channels bits)
  "The mono samples of SIZE bytes of interleaved PCM at START of OCTETS."
  (let* ((width (floor bits 8))
         (frames (floor size (* width channels)))
         (samples (make-samples frames)))
    (dotimes (frame frames samples)
      (let ((sum 0))
        (dotimes (channel channels)
          (let ((at (+ start (* width (+ channel (* frame channels))))))
            (incf sum (if (= bits 8)
                          (* 256 (- (aref octets at) 128))
                          (let ((u (u16 octets at))) (if (>= u 32768) (- u 65536) u))))))
        (setf (aref samples frame) (clamp-sample (/ sum channels)))))))

;;;# Writing

(defun write-wav (path sound)
  "Write SOUND to PATH as a mono 16-bit PCM WAV file; returns PATH's truename.
Signals a SPEECH-ERROR naming PATH when it cannot be written."
  (check-argument 'write-wav 'path path #'pathname-designator-p *path-phrase*)
  (check-argument 'write-wav 'sound sound #'sound-p "a sound (from read-wav or synthesize-speech)")
  (let* ((samples (sound-samples sound))
         (bytes (* 2 (length samples))))
    (flet ((put32 (out n) (dotimes (i 4) (write-byte (ldb (byte 8 (* 8 i)) n) out)))
           (put16 (out n) (dotimes (i 2) (write-byte (ldb (byte 8 (* 8 i)) n) out)))
           (tag (out text) (loop for c across text do (write-byte (char-code c) out))))
      (handler-case
          (with-atomic-output-file (out path :element-type '(unsigned-byte 8) :make-directories t)
            (tag out "RIFF") (put32 out (+ 36 bytes)) (tag out "WAVE")
            (tag out "fmt ") (put32 out 16) (put16 out 1) (put16 out 1)
            (put32 out (sound-rate sound)) (put32 out (* 2 (sound-rate sound))) (put16 out 2) (put16 out 16)
            (tag out "data") (put32 out bytes)
            (let ((buffer (make-array bytes :element-type '(unsigned-byte 8))))
              (loop for sample across samples
                    for i from 0 by 2
                    do (setf (aref buffer i) (ldb (byte 8 0) sample)
                             (aref buffer (1+ i)) (ldb (byte 8 8) sample)))
              (write-sequence buffer out)))
        ((or io-error file-error stream-error) (condition)
          (speech-fail "cannot write the WAV file ~A: ~A" (namestring path) (condition-reason condition)))))
    (truename path)))

;;;# Resampling

(defun resample-sound (sound rate)
  "SOUND at RATE samples a second.  Going down, a windowed-sinc low-pass first
removes what the new rate cannot hold (aliases confuse a recogniser); then
linear interpolation."
  (let ((from (sound-rate sound)))
    (if (= from rate)
        sound
        (let* ((source (if (< rate from) (low-pass (sound-samples sound) (/ (* 0.45d0 rate) from)) 
                           (map '(simple-array double-float (*)) (lambda (x) (float x 1d0)) (sound-samples sound))))
               (count (floor (* (length source) rate) from))
               (out (make-samples count))
               (step (/ (float from 1d0) rate)))
          (dotimes (i count (make-sound out rate))
            (let* ((x (* i step)) (k (floor x)) (f (- x k))
                   (a (aref source (min k (1- (length source)))))
                   (b (aref source (min (1+ k) (1- (length source))))))
              (setf (aref out i) (clamp-sample (+ a (* f (- b a)))))))))))

(defun low-pass (samples cutoff &key (half-width 16))
  "SAMPLES filtered by a Hann-windowed sinc of 2*HALF-WIDTH+1 taps passing
frequencies below CUTOFF (a fraction of the sample rate), as double-floats."
  ;; The animation math's policy (*ANIM-OPTIMIZE*, defined later in the pipeline).
  (declare (type samples samples) (optimize (speed 2) (safety 1) (debug 1)))
  (let* ((n (length samples))
         (taps (make-array (1+ (* 2 half-width)) :element-type 'double-float))
         (out (make-array n :element-type 'double-float :initial-element 0d0)))
    (loop for k from (- half-width) to half-width
          for x = (* 2 pi cutoff k)
          do (setf (aref taps (+ k half-width))
                   (* (if (zerop k) (* 2 cutoff) (/ (sin x) (* pi k)))
                      (+ 0.5d0 (* 0.5d0 (cos (/ (* pi k) (1+ half-width))))))))
    (let ((sum (reduce #'+ taps)))
      (map-into taps (lambda (tap) (/ tap sum)) taps))
    (dotimes (i n out)
      (let ((acc 0d0))
        (declare (type double-float acc))
        (loop for k from (max 0 (- i half-width)) to (min (1- n) (+ i half-width))
              do (incf acc (* (aref taps (+ half-width (- k i))) (aref samples k))))
        (setf (aref out i) acc)))))
