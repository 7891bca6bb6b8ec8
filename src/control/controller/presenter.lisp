;;;; presenter.lisp -- the presenter protocol: how a controller's decisions reach
;;;; the screen. A controller never draws; it tells its presenter which op to
;;;; play when, and the presenter answers how long it took. The null presenter
;;;; reports declared durations and records nothing (for benchmarks and
;;;; embedding); the trace presenter records the trace lines the CLI prints.

(in-package #:player.control)

(defclass presenter () ()
  (:documentation "Base class of presenters. Every protocol function has a
method here, so a presenter overrides only what it needs."))

(defgeneric present-op (presenter op start)
  (:documentation "Play OP (an op or a macro's sub-op) starting at time START
(seconds); return its duration in seconds. The default returns OP's declared
:duration, or what RUN-DIRECTOR returns for a :director op."))

(defgeneric run-director (presenter director op start)
  (:documentation "Run DIRECTOR (a symbol) for OP at time START; return the duration."))

(defgeneric present-macro-start (presenter op start)
  (:documentation "Macro-op OP begins at START; its sub-ops follow."))

(defgeneric present-macro-end (presenter op start end)
  (:documentation "Macro-op OP, begun at START, ended at END."))

(defgeneric start-autoscript (presenter proc variable value time)
  (:documentation "Start autoscript procedure PROC because VARIABLE took VALUE at TIME."))

(defgeneric stop-autoscript (presenter proc variable value time)
  (:documentation "Stop autoscript procedure PROC because VARIABLE left VALUE at TIME."))

(defgeneric present-event (presenter event time)
  (:documentation "Event EVENT (a symbol) is processed from TIME on."))

(defgeneric present-failure (presenter event goal time)
  (:documentation "EVENT could not achieve GOAL (the goal as written) at TIME; the rest of it is skipped."))

(defgeneric present-state (presenter controller)
  (:documentation "An event has finished; CONTROLLER holds the resulting state."))

(defgeneric present-state-change (presenter controller time)
  (:documentation "CONTROLLER's plannable state has just changed, at TIME: an
op's effects, a cut's, a :state directive's.  A body presenter settles its
character toward the pose of the new state.  The default does nothing."))

(defgeneric present-initial-state (presenter controller)
  (:documentation "CONTROLLER, just made, holds its initial state; nothing has
played yet (its initial autoscripts start next).  A body presenter puts its
character in the starting pose that state calls for."))

(defgeneric play-script (presenter script op start)
  (:documentation "Play SCRIPT (a symbol: OP's :script, or its name) for OP from
START; return the duration.  The default returns OP's declared :duration."))

;;; What only a timed controller asks (see src/control/timeline/)

(defgeneric planned-op-duration (presenter op start)
  (:documentation "How long OP will take when PRESENT-OP plays it from START,
asked before it plays, without playing it.  The default is OP's declared
:duration; a presenter whose PRESENT-OP answers otherwise overrides this."))

(defgeneric critical-time (presenter op name)
  (:documentation "The seconds into OP of the critical time NAME of its script,
for :interrupt (:at NAME).  The default signals a SPEC-ERROR: only a presenter
with a script library knows critical times."))

(defgeneric present-cut (presenter op start time by)
  (:documentation "OP, begun at START, is cut at TIME by event BY (OP is NIL
when the interrupted event had no op running)."))

(defgeneric present-dropped (presenter event time busy-with clash)
  (:documentation "EVENT, arriving at TIME while BUSY-WITH ran, is dropped
(:override).  CLASH is what the two met on: FOOTPRINT-CLASH's list of
channels (or :ALL) and variables."))

(defgeneric present-queued (presenter event time behind)
  (:documentation "EVENT, arriving at TIME while events it meets play, waits
in the queue (:queue) behind the event BEHIND: the last one waiting, or the
running one it met."))

(defgeneric present-resume (presenter event time)
  (:documentation "The interrupted EVENT resumes at TIME (:interleave)."))

(defgeneric present-timer (presenter timer time)
  (:documentation "Timer TIMER (a name) goes off at TIME and sends its event."))

(defgeneric present-trigger (presenter trigger time)
  (:documentation "Trigger TRIGGER (a name) fires at TIME: its condition became true."))

(defgeneric op-channel-set (presenter op)
  (:documentation "The body channels OP drives, as a list of lower-case strings,
or :ALL when nothing says (then it conflicts with every op).  The default is
OP's declared :channels; a presenter with a script library infers the rest."))

(defmethod op-channel-set ((presenter presenter) op)
  (or (op-channels op) :all))

(defmethod planned-op-duration ((presenter presenter) op start)
  (declare (ignore start))
  (op-duration op))

(defmethod critical-time ((presenter presenter) op name)
  (error 'spec-error :form (op-form op) :spec nil
                     :message (format nil "op ~A: :interrupt (:at ~A) names a critical time, which only a script library gives (run it with its scripts, or give seconds into the op)"
                                      (lisp-text (op-name op)) (lisp-text name))))

(defmethod present-cut ((presenter presenter) op start time by)
  (declare (ignore op start time by)))

(defmethod present-dropped ((presenter presenter) event time busy-with clash)
  (declare (ignore event time busy-with clash)))

(defmethod present-queued ((presenter presenter) event time behind)
  (declare (ignore event time behind)))

(defmethod present-resume ((presenter presenter) event time)
  (declare (ignore event time)))

(defmethod present-timer ((presenter presenter) timer time)
  (declare (ignore timer time)))

(defmethod present-trigger ((presenter presenter) trigger time)
  (declare (ignore trigger time)))

(defmethod present-op ((presenter presenter) op start)
  (case (op-kind op)
    (:director (run-director presenter (op-director op) op start))
    (:script (play-script presenter (or (op-script op) (op-name op)) op start))
    (t (op-duration op))))

(defmethod play-script ((presenter presenter) script op start)
  (declare (ignore script start))
  (op-duration op))

(defmethod run-director ((presenter presenter) director op start)
  (declare (ignore director start))
  (op-duration op))

(defmethod present-macro-start ((presenter presenter) op start)
  (declare (ignore op start)))

(defmethod present-macro-end ((presenter presenter) op start end)
  (declare (ignore op start end)))

(defmethod start-autoscript ((presenter presenter) proc variable value time)
  (declare (ignore proc variable value time)))

(defmethod stop-autoscript ((presenter presenter) proc variable value time)
  (declare (ignore proc variable value time)))

(defmethod present-event ((presenter presenter) event time)
  (declare (ignore event time)))

(defmethod present-failure ((presenter presenter) event goal time)
  (declare (ignore event goal time)))

(defmethod present-state ((presenter presenter) controller)
  (declare (ignore controller)))

(defmethod present-initial-state ((presenter presenter) controller)
  (declare (ignore controller)))

(defmethod present-state-change ((presenter presenter) controller time)
  (declare (ignore controller time)))

;;; The null presenter

(defclass null-presenter (presenter) ()
  (:documentation "Plays nothing and records nothing; ops take their declared durations."))

(defmethod present-op ((presenter null-presenter) op start)
  ;; What the base method answers, without asking PLAY-SCRIPT or RUN-DIRECTOR
  ;; (a null presenter plays nothing): the benchmarks' hot path.
  (declare (ignore start))
  (op-duration op))

(defun make-null-presenter ()
  "A presenter that does nothing, for benchmarks and headless embedding."
  (make-instance 'null-presenter))

;;; The trace presenter

(defclass trace-presenter (presenter)
  ((lines :initform (make-array 16 :adjustable t :fill-pointer 0) :reader trace-line-vector)
   (flushed :initform 0 :accessor trace-flushed
            :documentation "Lines already written to STREAM.")
   (open-macros :initform '() :accessor trace-open-macros
                :documentation "Lines of the macros still running, innermost first; their :end is filled in when they finish.")
   (stream :initarg :stream :initform nil :reader trace-stream
           :documentation "Where finished lines are written as they happen, or NIL.")
   (limit :initarg :limit :initform nil :reader trace-limit
          :documentation "Keep at most about this many recent lines (NIL: all).")
   (dropped :initform 0 :accessor trace-dropped
            :documentation "How many of the oldest lines were forgotten to stay within LIMIT."))
  (:documentation "Records every decision as a trace line (a list such as
(:op bow :script bow :start 0 :end 1)); with a STREAM, also writes them there.
With a LIMIT it keeps only the most recent lines, so a long-running agent's
trace stays bounded."))

(defparameter *default-trace-limit* 10000
  "How many recent trace lines MAKE-CONTROLLER's default presenter keeps.")

(defun make-trace-presenter (&key stream limit)
  "A presenter recording trace lines; with STREAM (T for *STANDARD-OUTPUT*),
writing them too.  With LIMIT (a positive integer), it keeps only the most
recent LIMIT lines (TRACE-LINES returns those); without, every line."
  (check-argument 'make-trace-presenter :stream stream #'output-stream-designator-p
                  "an output stream, T (standard output) or NIL")
  (check-argument 'make-trace-presenter :limit limit (lambda (x) (or (null x) (typep x '(integer 1))))
                  "a positive integer or NIL")
  (make-instance 'trace-presenter :stream (if (eq stream t) *standard-output* stream) :limit limit))

(defun trace-presenter-p (x)
  "Is X a trace presenter?"
  (typep x 'trace-presenter))

(defun trace-line-p (x)
  "Is X shaped as a trace line: a proper list starting with a keyword (a
:state line's pairs must be conses)?"
  (and (consp x) (keywordp (first x)) (proper-form-list-p x)
       (or (not (eq (first x) :state)) (every #'consp (rest x)))))

(defun trace-lines (presenter)
  "The trace lines PRESENTER has recorded, oldest first."
  (check-argument 'trace-lines 'presenter presenter #'trace-presenter-p "a trace presenter (from make-trace-presenter)")
  (coerce (trace-line-vector presenter) 'list))

(defun clear-trace (presenter)
  "Forget PRESENTER's recorded lines."
  (check-argument 'clear-trace 'presenter presenter #'trace-presenter-p "a trace presenter (from make-trace-presenter)")
  (incf (trace-dropped presenter) (length (trace-line-vector presenter)))
  (setf (fill-pointer (trace-line-vector presenter)) 0
        (trace-flushed presenter) 0))

(defun trace-line-string (line)
  "LINE as the text the CLI prints (lower case, no package prefixes). The pairs
of a :state line always print dotted, so a false boolean reads (var . nil)."
  (check-argument 'trace-line-string 'line line #'trace-line-p "a trace line, a proper list such as (:event ev :time 0)")
  (%trace-line-string line))

(defun %trace-line-string (line)
  "TRACE-LINE-STRING of LINE, known to be a trace line."
  (if (eq (first line) :state)
      (format nil "(:state~{ (~A . ~A)~})"
              (loop for (name . value) in (rest line)
                    collect (lisp-text name) collect (lisp-text value)))
      (lisp-text line)))

(defun write-trace-line (line &optional (stream *standard-output*))
  "Write LINE and a newline to STREAM (T for *STANDARD-OUTPUT*)."
  (check-argument 'write-trace-line 'line line #'trace-line-p "a trace line, a proper list such as (:event ev :time 0)")
  (check-argument 'write-trace-line 'stream stream
                  (lambda (x) (and x (output-stream-designator-p x))) "an output stream or T")
  (%write-trace-line line (if (eq stream t) *standard-output* stream)))

(defun %write-trace-line (line stream)
  "WRITE-TRACE-LINE of LINE, a trace line, to the output stream STREAM."
  (write-string (%trace-line-string line) stream)
  (terpri stream))

(defun record-line (presenter line)
  "Append LINE to PRESENTER's trace, write what is finished, and forget the
oldest lines when the trace holds twice its limit (so trimming costs O(1) a line)."
  (vector-push-extend line (trace-line-vector presenter))
  (flush-trace presenter)
  (trim-trace presenter)
  line)

(defun trim-trace (presenter)
  "Keep PRESENTER's newest LIMIT lines once it holds twice that many, unless
lines are still waiting to be written (an open macro)."
  (let ((limit (trace-limit presenter))
        (lines (trace-line-vector presenter)))
    (when (and limit (>= (length lines) (* 2 limit)) (null (trace-open-macros presenter))
               (or (null (trace-stream presenter)) (= (trace-flushed presenter) (length lines))))
      (let ((drop (- (length lines) limit)))
        (replace lines lines :start2 drop)
        (setf (fill-pointer lines) limit)
        (incf (trace-dropped presenter) drop)
        (setf (trace-flushed presenter) (max 0 (- (trace-flushed presenter) drop)))))))

(defun flush-trace (presenter)
  "Write recorded lines to the stream, stopping at a macro line still open."
  (when (and (trace-stream presenter) (null (trace-open-macros presenter)))
    (let ((lines (trace-line-vector presenter)))
      (loop while (< (trace-flushed presenter) (length lines))
            do (%write-trace-line (aref lines (trace-flushed presenter)) (trace-stream presenter))
               (incf (trace-flushed presenter)))
      (force-output (trace-stream presenter)))))

(defun finish-trace (presenter)
  "Write every line PRESENTER (a trace presenter) still holds back, once the
clock has stopped (`run --at T` inside a macro-op): the ops started so far
appear, an open macro's line with its end at its start, as the C++ backend
prints it."
  (when (and (trace-stream presenter) (trace-open-macros presenter))
    (setf (trace-open-macros presenter) '())
    (flush-trace presenter)))

(defun op-line (op start end)
  "The trace line of OP played from START to END."
  (list* :op (op-name op)
         (append (ecase (op-kind op)
                   ((:script :macro) (list :script (op-script op)))
                   (:director (list :director (op-director op)))
                   (:code (list :code t)))
                 (list :start start :end end))))

(defmethod present-op ((presenter trace-presenter) op start)
  ;; START is exact seconds (whole microseconds): so is the end, its
  ;; duration converted as the controller converts it.
  (let ((duration (call-next-method)))
    (record-line presenter (op-line op start (if (micros-ratio-p start)
                                                 (micros->seconds (+ (seconds->micros start)
                                                                     (seconds->micros duration)))
                                                 (+ start duration))))
    duration))

(defmethod present-macro-start ((presenter trace-presenter) op start)
  (let ((line (op-line op start start)))
    (push line (trace-open-macros presenter))
    (record-line presenter line)))

(defmethod present-macro-end ((presenter trace-presenter) op start end)
  ;; The line of this macro (OP from START): the innermost open one, unless a
  ;; timed controller plays macros of two events side by side.
  (let ((line (find-if (lambda (line) (and (eq (second line) (op-name op))
                                           (eql (getf (cddr line) :start) start)))
                       (trace-open-macros presenter))))
    (when line
      (setf (trace-open-macros presenter) (remove line (trace-open-macros presenter) :count 1)
            (getf (cddr line) :end) end)))
  (flush-trace presenter))

(defmethod start-autoscript ((presenter trace-presenter) proc variable value time)
  (record-line presenter (list :autoscript-start proc :var variable :value value :time time)))

(defmethod stop-autoscript ((presenter trace-presenter) proc variable value time)
  (record-line presenter (list :autoscript-stop proc :var variable :value value :time time)))

(defmethod present-event ((presenter trace-presenter) event time)
  (record-line presenter (list :event event :time time)))

(defmethod present-failure ((presenter trace-presenter) event goal time)
  (record-line presenter (list :fail event :goal goal :time time)))

(defmethod present-state ((presenter trace-presenter) controller)
  (record-line presenter (cons :state (controller-state controller))))

(defmethod present-cut ((presenter trace-presenter) op start time by)
  ;; The op's :op line, written when it began, gave the end it was planned
  ;; to have; this line's :end is where it stopped, so no op seems to play
  ;; past its cut.
  (declare (ignore start))
  (record-line presenter (if op
                             (list :cut (op-name op) :time time :by by :end time)
                             (list :cut nil :time time :by by))))

(defmethod present-dropped ((presenter trace-presenter) event time busy-with clash)
  (record-line presenter (list :dropped event :time time :busy-with busy-with :clash clash)))

(defmethod present-queued ((presenter trace-presenter) event time behind)
  (record-line presenter (list :queued event :time time :behind behind)))

(defmethod present-resume ((presenter trace-presenter) event time)
  (record-line presenter (list :resume event :time time)))

(defmethod present-timer ((presenter trace-presenter) timer time)
  (record-line presenter (list :timer timer :time time)))

(defmethod present-trigger ((presenter trace-presenter) trigger time)
  (record-line presenter (list :trigger trigger :time time)))
