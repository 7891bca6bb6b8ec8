;;;; capture.lisp -- sound from a microphone: ALSA's `arecord` (Debian
;;;; alsa-utils) records 16 kHz mono 16-bit samples from an ALSA PCM device
;;;; onto a pipe, read here a piece at a time.  Any ALSA device serves,
;;;; a file-backed one too (a `file` PCM's infile), which is how the tests
;;;; and CI listen without a microphone.  A device that cannot be opened is
;;;; one SPEECH-ERROR quoting arecord.

(in-package #:player.speech)

(defparameter *capture-device* "default"
  "The ALSA PCM device a microphone is read from unless told otherwise.")

(defstruct (capture (:constructor %make-capture (device process stream messages)))
  "A running recording: the ALSA DEVICE, arecord's PROCESS and the STREAM of
its raw samples, with the odd byte left over from the last read (CARRY), and
the file its MESSAGES go to (a pipe nobody read would fill and stop it)."
  device process stream messages (carry nil))

(defun find-arecord ()
  "The arecord program; SPEECH-UNAVAILABLE naming alsa-utils when it is missing."
  ;; The path itself, not its truename: arecord is a link to aplay, which plays when called so.
  (or (find-if #'probe-file (mapcar (lambda (dir) (merge-pathnames "arecord" dir)) '(#p"/usr/bin/" #p"/bin/" #p"/usr/local/bin/")))
      (error 'speech-unavailable :package "alsa-utils"
                                 :message "listening to a microphone needs arecord: install the Debian package alsa-utils")))

(defun capture-failure (device messages)
  "Signal the SPEECH-ERROR saying the microphone DEVICE could not be opened,
quoting the first line arecord wrote in the file MESSAGES."
  (let ((said (ignore-errors (with-open-file (in messages) (read-line in nil nil)))))
    (speech-fail "cannot open the microphone ~A~@[: arecord says ~A~]"
                 device (and said (string-trim '(#\Space #\Return) said)))))

(defun open-capture (&key (device *capture-device*) (rate *recognition-rate*))
  "Start recording from the ALSA DEVICE (a string) at RATE samples a second,
mono 16-bit: a CAPTURE to READ-CAPTURE from and CLOSE-CAPTURE.  A
SPEECH-ERROR when the device cannot be opened; SPEECH-UNAVAILABLE without arecord."
  (check-argument 'open-capture :device device (lambda (x) (and (stringp x) (plusp (length x)) (not (find #\Nul x))))
                  "an ALSA device name")
  (let* ((messages (temporary-file (format nil "player-arecord-~D.txt" (sb-posix:getpid))))
         (process (sb-ext:run-program (namestring (find-arecord))
                                      (list "-q" "-D" device "-f" "S16_LE" "-r" (princ-to-string rate) "-c" "1" "-t" "raw")
                                      :wait nil :input nil :output :stream
                                      :error messages :if-error-exists :supersede))
         ;; Read as bytes: run-program's stream is of characters, which raw samples are not.
         (capture (%make-capture device process
                                 (sb-sys:make-fd-stream (sb-sys:fd-stream-fd (sb-ext:process-output process))
                                                        :input t :element-type '(unsigned-byte 8)
                                                        :buffering :full :auto-close nil)
                                 messages)))
    ;; arecord fails at once when the device cannot be opened: the pipe ends
    ;; with no sound.  The first byte, read to know, is kept for READ-CAPTURE.
    (let ((first (read-byte (capture-stream capture) nil nil)))
      (unless first
        (sb-ext:process-wait process)
        (unwind-protect (capture-failure device messages) (close-capture capture)))
      (setf (capture-carry capture) first))
    capture))

(defun read-capture (capture samples)
  "Fill SAMPLES (a SAMPLES vector) from CAPTURE; the number of samples read,
fewer than asked only at the end of the recording (0: it has ended)."
  (let* ((octets (make-array (* 2 (length samples)) :element-type '(unsigned-byte 8)))
         (start (if (capture-carry capture) 1 0)))
    (when (capture-carry capture)
      (setf (aref octets 0) (capture-carry capture) (capture-carry capture) nil))
    (let* ((end (read-sequence octets (capture-stream capture) :start start))
           (count (floor end 2)))
      (when (oddp end) (setf (capture-carry capture) (aref octets (1- end))))
      (dotimes (i count count)
        (let ((value (logior (aref octets (* 2 i)) (ash (aref octets (1+ (* 2 i))) 8))))
          (setf (aref samples i) (if (>= value 32768) (- value 65536) value)))))))

(defun close-capture (capture)
  "Stop CAPTURE's recording and free its process."
  (let ((process (capture-process capture)))
    ;; The pipe first: arecord blocked writing to a full one outlives a SIGTERM
    ;; (its handler returns to the write), and so would wait for us for ever.
    ;; Closing run-program's stream closes the descriptor the byte stream reads.
    (ignore-errors (close (sb-ext:process-output process)))
    (when (sb-ext:process-alive-p process) (ignore-errors (sb-ext:process-kill process 9)))
    (ignore-errors (sb-ext:process-wait process))
    (sb-ext:process-close process)
    (ignore-errors (delete-file (capture-messages capture)))
    nil))
