;;;; scenario.lisp -- playing a recording's scenario again: the trace exactly
;;;; as `player run` prints it, and the body frames exactly as `player
;;;; simulate --frames` writes them, both turned into the data a recording
;;;; file holds, so a replay and a recording compare like with like.

(in-package #:player.traces)

(defmacro with-recording-syntax (() &body body)
  "Run BODY with the printer and reader set as recording files are written
and read: standard syntax without #S, no *READ-EVAL*, doubles by default,
symbols in PLAYER-USER, lower case (as `simulate --frames` writes frames)."
  `(with-standard-io-syntax
     (let ((*readtable* *data-readtable*)
           (*read-eval* nil)
           (*package* (find-package '#:player-user))
           (*read-default-float-format* 'double-float)
           (*print-case* :downcase)
           (*print-readably* nil))
       ,@body)))

(defun frame-text (form)
  "FORM, a frame, as the one line `player simulate --frames` writes for it."
  (with-recording-syntax () (prin1-to-string form)))

(defun read-frame-text (text)
  "The frame form TEXT (written by FRAME-TEXT) reads as."
  (with-recording-syntax () (values (read-from-string text))))

(defun canonical-trace-line (form)
  "The trace line FORM as `player run` prints it, or NIL when FORM is no trace line."
  (and (trace-line-p form) (trace-line-string form)))

(defun read-trace-text (text)
  "The lines of TEXT, trace lines as `player run` prints them, each read and
printed again (CANONICAL-TRACE-LINE), so a replay compares with a recording read from its file."
  (with-input-from-string (in text)
    (loop for line = (read-line in nil) while line
          unless (string= "" (string-trim " " line))
            collect (or (canonical-trace-line (with-recording-syntax () (read-from-string line)))
                        line))))

(defun scenario-controller (spec recording stream)
  "A controller of SPEC set up to play RECORDING's scenario as `player run`
does, printing trace lines to STREAM."
  (let ((events (recording-events recording)) (at (recording-at recording)))
    (make-controller (compile-spec spec)
                     :initial-state (recording-initial recording)
                     :timed (or (timed-scenario-p events at) (recording-when-busy recording))
                     :presenter (make-trace-presenter :stream stream))))

(defun replay-trace (spec recording)
  "The trace lines (texts) that `player run` prints for RECORDING's scenario
played on SPEC: its events from its initial state, stopping at its AT; the
initial state alone when it has neither events nor AT."
  (let* ((events (recording-events recording)) (at (recording-at recording))
         (text (with-output-to-string (out)
                 (let ((controller (scenario-controller spec recording out)))
                   (dolist (entry events)
                     (find-compiled-event controller (event-entry-name entry)))
                   (if (or events at)
                       (play-events controller events :until at :when-busy (recording-when-busy recording))
                       (present-state (controller-presenter controller) controller))))))
    (read-trace-text text)))

(defun recording-relative-path (path recording)
  "PATH (a string or NIL) as recorded in RECORDING: relative to the directory
of the file RECORDING was read from, when it has one."
  (and path (if (recording-file recording)
                (merge-pathnames path (recording-file recording))
                path)))

(defun replay-frames (spec recording)
  "The body frames `player simulate --frames` writes for RECORDING's scenario
played on SPEC with its frame rate, seed, script library and body, as forms
read back from their text."
  (let ((simulation (simulate spec :initial (recording-initial recording)
                                   :events (recording-events recording)
                                   :until (recording-at recording)
                                   :when-busy (recording-when-busy recording)
                                   :fps (recording-fps recording) :seed (recording-seed recording)
                                   :scripts (recording-relative-path (recording-scripts recording) recording)
                                   :body (recording-body recording)))
        (frames '()))
    (map-simulation-frames (lambda (index time scene)
                             (push (read-frame-text (frame-text (frame-form index time scene))) frames))
                           simulation)
    (nreverse frames)))
