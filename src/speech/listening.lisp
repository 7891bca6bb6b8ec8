;;;; listening.lisp -- requests heard from a microphone as they are said:
;;;; pocketsphinx's voice-activity detection finds where each utterance
;;;; starts and ends in the stream, the grammar's decoder and the phone
;;;; loop's hear it side by side, a piece at a time, so when the speaker
;;;; stops only the ends of two searches are left to do; each utterance is
;;;; then judged as RECOGNIZE-SOUND judges a whole sound (recognition.lisp).

(in-package #:player.speech)

(defparameter *capture-piece* 1024
  "Samples read and decoded at a time (64 ms at 16 kHz): the latency the
voice-activity detection adds to the half second of silence that ends an utterance.")

(defun listen-for-requests (capture grammar on-request &key seconds)
  "Hear requests of GRAMMAR (JSGF text) from CAPTURE (OPEN-CAPTURE) until it
ends, SECONDS of sound have been read (NIL: no limit) or ON-REQUEST returns
:STOP.  ON-REQUEST is called for each utterance with TEXT, SCORE and
SENTENCE as RECOGNIZE-SOUND returns them, and the internal real time its end
was heard.  Returns the seconds of sound read."
  (check-argument 'listen-for-requests :grammar grammar #'jsgf-text-p "a JSGF grammar's text (starting #JSGF V1.0;)")
  (check-argument 'listen-for-requests :seconds seconds (lambda (x) (or (null x) (and (realp x) (plusp x))))
                  "a positive number of seconds, or NIL")
  (let ((decoder (grammar-decoder grammar :listening t))
        (phones (cdr (listening-decoders)))
        (piece (make-samples *capture-piece*))
        (limit (and seconds (round (* seconds *recognition-rate*))))
        (read 0)
        (speaking nil))
    (sphinx-start-stream decoder)
    (sphinx-start-stream phones)
    (sphinx-start decoder)
    (sphinx-start phones)
    (loop (let ((count (read-capture capture piece)))
            (when (zerop count) (return))
            (incf read count)
            (let ((in-speech (sphinx-feed decoder piece :end count)))
              (sphinx-feed phones piece :end count)
              (cond (in-speech (setf speaking t))
                    (speaking
                     (setf speaking nil)
                     (let ((heard-at (get-internal-real-time)))
                       (multiple-value-bind (text acoustic frames speech word-phones segments) (sphinx-finish decoder)
                         (declare (ignore speech))
                         (multiple-value-bind (loop-text loop-acoustic loop-frames loop-speech loop-phones loop-segments)
                             (sphinx-finish phones)
                           (declare (ignore loop-text loop-frames loop-phones))
                           (sphinx-start decoder)
                           (sphinx-start phones)
                           (when text
                             (multiple-value-bind (text score sentence)
                                 (judge-recognition text (recognition-score acoustic loop-acoustic frames)
                                                    (recognition-stretch loop-speech word-phones)
                                                    (unexplained-speech segments loop-segments))
                               (when (eq :stop (funcall on-request text score sentence heard-at))
                                 (return))))))))))
            (when (and limit (>= read limit)) (return))))
    (ignore-errors (sphinx-finish decoder))
    (ignore-errors (sphinx-finish phones))
    (/ read (float *recognition-rate* 1d0))))
