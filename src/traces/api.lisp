;;;; api.lisp -- recorded traces as regression tests: RECORD-SCENARIO plays a
;;;; scenario and keeps what came out; VERIFY-RECORDING plays it again and
;;;; says where the replay first departs from the recording.

(in-package #:player.traces)

(defun check-scenario-arguments (function initial events at when-busy)
  "Check a scenario's INITIAL, EVENTS, AT and WHEN-BUSY: an ARGUMENT-ERROR of FUNCTION for the first that is wrong."
  (check-argument function :initial initial #'initial-state-p *initial-state-phrase*)
  (check-argument function :events events
                  (lambda (x) (and (proper-list-p x) (every #'event-entry-p x)))
                  "a proper list of event names (symbols or strings) or (NAME . SECONDS) pairs")
  (when at (check-seconds function :at at :minimum 0))
  (check-argument function :when-busy when-busy (lambda (x) (or (null x) (member x *when-busy-policies*)))
                  (format nil "NIL or one of ~{~(~S~)~^, ~}" *when-busy-policies*)))

(defun record-scenario (spec &key initial events at when-busy frames (fps 30) (seed 0) scripts body out)
  "Play a scenario on SPEC (a spec or a defined spec's name) and return it as
a RECORDING: from INITIAL (an alist, as for MAKE-CONTROLLER), the EVENTS
(names, or (NAME . SECONDS) arriving at that time) until AT (seconds, or
NIL: until every event has ended), every busy event resolved by WHEN-BUSY (a
policy keyword, or NIL for each event's own).  The recording holds the trace
lines `player run` prints; with FRAMES, also the body frames `player
simulate --frames` writes at FPS frames per second, with SEED for the random
drivers, the script library SCRIPTS (a path, or NIL for the spec's own) and
the skeleton BODY (a name, or NIL).  With OUT (a path), the recording is
also written there (see WRITE-RECORDING), the spec's file and SCRIPTS stored
relative to it.  Signals an ARGUMENT-ERROR for an argument of the wrong
kind, and what running the scenario signals (UNKNOWN-EVENT, a SPEC-ERROR)."
  (check-argument 'record-scenario 'spec spec #'spec-designator-p *spec-designator*)
  (check-scenario-arguments 'record-scenario initial events at when-busy)
  (check-fps 'record-scenario fps)
  (check-real 'record-scenario :seed seed :integer t)
  (check-argument 'record-scenario :scripts scripts (lambda (x) (or (null x) (pathname-designator-p x)))
                  (format nil "NIL or ~A" *path-phrase*))
  (check-argument 'record-scenario :body body (lambda (x) (and (symbolp x) (not (keywordp x))))
                  "NIL or a skeleton's name")
  (check-argument 'record-scenario :out out (lambda (x) (or (null x) (pathname-designator-p x)))
                  (format nil "NIL or ~A" *path-phrase*))
  (let* ((spec (if (spec-p spec) spec (find-spec spec)))
         (recording (%make-recording
                     :spec-name (recorded-name (spec-name spec))
                     :spec-file (and (spec-source-file spec) (native-namestring (spec-source-file spec)))
                     :initial (recorded-initial initial) :events (mapcar #'recorded-event events)
                     :at (and at (to-double at)) :when-busy when-busy
                     :frames-p (and frames t) :fps fps :seed seed
                     :scripts (and scripts (native-namestring (merge-pathnames scripts)))
                     :body (and body (recorded-name body)))))
    (setf (recording-lines recording) (replay-trace spec recording))
    (when frames
      (setf (recording-frames recording) (replay-frames spec recording)))
    (when out
      (setf (recording-spec-file recording) (recorded-file-name (recording-spec-file recording) out)
            (recording-scripts recording) (recorded-file-name (recording-scripts recording) out))
      (write-recording recording out)
      (setf (recording-file recording) out))
    recording))

;;;# Verifying

(defstruct (verification (:constructor make-verification (line-count frame-count tolerance difference)))
  "What VERIFY-RECORDING found: the LINE-COUNT and FRAME-COUNT of the
recording, the TOLERANCE frames were compared with, and the first
DIFFERENCE (a RECORDING-DIFFERENCE), or NIL when the replay matches."
  line-count frame-count tolerance difference)

(defun verification-ok-p (verification)
  "Did the replay match the recording?"
  (check-argument 'verification-ok-p 'verification verification #'verification-p
                  "a verification (from verify-recording)")
  (null (verification-difference verification)))

(defun verification-message (verification)
  "VERIFICATION in one line: \"ok: N lines match\" (and frames), or the first difference."
  (check-argument 'verification-message 'verification verification #'verification-p
                  "a verification (from verify-recording)")
  (let ((difference (verification-difference verification)))
    (if difference
        (recording-difference-message difference)
        (format nil "ok: ~D line~:P ~:[match~;and ~:*~D frame~:P match (tolerance ~A)~]"
                (verification-line-count verification)
                (and (plusp (verification-frame-count verification)) (verification-frame-count verification))
                (tolerance-text (verification-tolerance verification))))))

(defun recorded-spec (recording file allow-code)
  "The spec RECORDING was played on, loaded from FILE (a path, or NIL for the
recording's SPEC-FILE, relative to the recording's file); a RECORDING-ERROR
when there is no such file or it defines no spec of the recorded name."
  (let ((path (or file (recording-relative-path (recording-spec-file recording) recording)
                  (recording-fail (recording-file recording) nil
                                  "the recording names no spec file; give the spec"))))
    (or (find (name-key (recording-spec-name recording)) (load-spec path :allow-code allow-code)
              :key (lambda (spec) (name-key (spec-name spec))) :test #'string=)
        (recording-fail (recording-file recording) nil "~A defines no spec ~A, the one recorded"
                        (native-namestring path) (lisp-text (recording-spec-name recording))))))

(defun verify-recording (recording &key spec spec-file (allow-code t) (tolerance *default-frame-tolerance*))
  "Replay RECORDING (a RECORDING, or a path to read one from with
READ-RECORDING) and compare: the trace lines as text, then the frames, every
number within TOLERANCE (a real from 0).  The spec is SPEC (a spec or a
defined spec's name), else the one named as recorded in SPEC-FILE (a path),
else in the recording's own spec file; ALLOW-CODE NIL refuses a spec file
holding :code or :c++.  Returns a VERIFICATION: VERIFICATION-OK-P, and
VERIFICATION-DIFFERENCE the first difference, in plain words by
VERIFICATION-MESSAGE.  Signals a RECORDING-ERROR for a malformed recording
file or a spec that cannot be found, an ARGUMENT-ERROR for an argument of the
wrong kind, and what replaying signals (UNKNOWN-EVENT when the spec lost an event)."
  (check-argument 'verify-recording 'recording recording
                  (lambda (x) (or (recording-p x) (pathname-designator-p x)))
                  (format nil "a recording (from record-scenario) or ~A" *path-phrase*))
  (check-argument 'verify-recording :spec spec (lambda (x) (or (null x) (spec-designator-p x))) *spec-designator*)
  (check-argument 'verify-recording :spec-file spec-file (lambda (x) (or (null x) (pathname-designator-p x)))
                  (format nil "NIL or ~A" *path-phrase*))
  (check-real 'verify-recording :tolerance tolerance :minimum 0)
  (let* ((recording (if (recording-p recording) recording (read-recording recording)))
         (spec (cond ((spec-p spec) spec)
                     (spec (find-spec spec))
                     (t (recorded-spec recording spec-file allow-code))))
         (frames (and (recording-frames-p recording) (recording-frames recording))))
    (make-verification (length (recording-lines recording)) (length frames) tolerance
                       (or (trace-difference recording (replay-trace spec recording))
                           (and frames (frames-difference recording (replay-frames spec recording) tolerance))))))
