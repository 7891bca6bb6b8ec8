;;;; ensemble.lisp -- a scene played: one controller per member, members of
;;;; one spec sharing its compiled machine.  Events reach only the members
;;;; they address; the trace is each member's lines in turn, in the scene's
;;;; order, each line prefixed with the member's name and ": ".

(in-package #:player.cast)

(defstruct (performer (:constructor make-performer (name member controller)))
  "One member of a scene at play: its NAME, its CAST-MEMBER and its CONTROLLER."
  name member controller)

(defstruct (ensemble (:constructor %make-ensemble
                        (cast performers machines
                         &aux (index (let ((table (make-hash-table :test 'equal)))
                                       (dolist (p performers table)
                                         (setf (gethash (symbol-name (performer-name p)) table) p)))))))
  "A scene at play: its CAST, a PERFORMER per member, MACHINES, an alist
from each spec's name to the compiled machine its members share, and INDEX,
the performers by name, so sending to every member costs linear time."
  cast performers machines index)

(defmethod print-object ((ensemble ensemble) stream)
  ;; One line: the scene and each member's controller's clock.
  (print-unreadable-object (ensemble stream :type t)
    (format stream "~A:~{ ~A~}" (lisp-text (cast-name (ensemble-cast ensemble)))
            (mapcar (lambda (performer)
                      (format nil "~A t=~A" (lisp-text (performer-name performer))
                              (format-number (controller-clock (performer-controller performer)))))
                    (ensemble-performers ensemble)))))

(defun cast-designator-p (x)
  "Is X a cast or the name of a defined one?"
  (or (cast-p x) (and (name-designator-p x) (find-cast x nil))))

(defun designated-cast (cast function)
  "The CAST a cast or a scene's name designates; an ARGUMENT-ERROR of FUNCTION otherwise."
  (check-argument function 'cast cast #'cast-designator-p "a scene (from defscene) or a defined scene's name")
  (if (cast-p cast) cast (find-cast cast)))

(defun cast-machines (cast)
  "An alist from each spec CAST's members play to its compiled machine, each compiled once."
  (let ((machines '()))
    (dolist (member (cast-members cast) (nreverse machines))
      (unless (assoc (cast-member-spec member) machines)
        (push (cons (cast-member-spec member) (compile-spec (cast-member-spec member))) machines)))))

(defun make-ensemble (cast &key initial timed presenter)
  "Controllers for every member of CAST (a cast or a scene's name), members of
one spec sharing one compiled machine.  Each starts from INITIAL (an alist,
as for MAKE-CONTROLLER), then its member's :initial.  TIMED is T, NIL or a
list of member names whose controllers are timed.  PRESENTER, a function of
the CAST-MEMBER, makes each member's presenter (default: a trace presenter)."
  (let ((cast (designated-cast cast 'make-ensemble)))
    (check-argument 'make-ensemble :initial initial #'initial-state-p *initial-state-phrase*)
    (check-argument 'make-ensemble :presenter presenter (lambda (x) (or (null x) (functionp x)))
                    "NIL or a function of a cast member returning a presenter")
    (check-argument 'make-ensemble :timed timed
                    (lambda (x) (or (eq x t) (and (alexandria:proper-list-p x) (every #'symbolp x))))
                    "T, NIL or a list of member names")
    (let ((machines (cast-machines cast)))
      (%make-ensemble
       cast
       (loop for member in (cast-members cast)
             for name = (cast-member-name member)
             collect (make-performer
                      name member
                      (make-controller (cdr (assoc (cast-member-spec member) machines))
                                       :initial-state (merge-initial initial (cast-member-initial member))
                                       :timed (if (listp timed) (and (member name timed) t) timed)
                                       :presenter (if presenter
                                                      (funcall presenter member)
                                                      (make-trace-presenter)))))
       machines))))

(defun merge-initial (initial override)
  "INITIAL with OVERRIDE's variables replaced by OVERRIDE's values."
  (append override (remove-if (lambda (entry) (assoc (car entry) override :test #'string-equal)) initial)))

(defun check-ensemble (function ensemble)
  "ENSEMBLE when it is one; else an ARGUMENT-ERROR of FUNCTION."
  (check-argument function 'ensemble ensemble #'ensemble-p "an ensemble (from make-ensemble)"))

(defun check-scene-timing (function at when-busy)
  "An ARGUMENT-ERROR of FUNCTION unless AT is NIL or seconds and WHEN-BUSY NIL or a policy,
checked before any member is sent anything."
  (when at (check-seconds function :at at))
  (check-argument function :when-busy when-busy
                  (lambda (x) (or (null x) (and (symbolp x) (when-busy-policy x))))
                  (format nil "NIL or one of ~{~A~^, ~}" (mapcar #'lisp-text *when-busy-policies*))))

(defun ensemble-controller (ensemble member)
  "The controller of ENSEMBLE's MEMBER (a member's name); an UNKNOWN-MEMBER-ERROR when there is none."
  (check-ensemble 'ensemble-controller ensemble)
  (check-argument 'ensemble-controller 'member member #'string-designator-p "a member's name (a symbol or string)")
  (let ((performer (or (and (symbolp member) (gethash (symbol-name member) (ensemble-index ensemble)))
                       (find (string member) (ensemble-performers ensemble)
                             :key (lambda (p) (symbol-name (performer-name p))) :test #'string-equal))))
    (unless performer
      (scene-fail 'unknown-member-error member "scene ~A has no member ~A (members: ~{~A~^, ~})"
                  (lisp-text (cast-name (ensemble-cast ensemble))) (lisp-text member)
                  (mapcar (lambda (p) (lisp-text (performer-name p))) (ensemble-performers ensemble))))
    (performer-controller performer)))

(defun send-scene-event (ensemble address &key at when-busy)
  "Send the event ADDRESS names (MEMBER/EVENT, MEMBER+.../EVENT, all/EVENT or
one of the scene's events) to each member it addresses, in the order it names
them, as SEND-EVENT would (AT and WHEN-BUSY for timed controllers; a scene
event's (ADDRESS :after OFFSET) at AT plus OFFSET, so it needs AT).  Returns T
when every member's event succeeded, else NIL.  Signals an
UNKNOWN-MEMBER-ERROR for an address naming no member, and UNKNOWN-EVENT for
an event a member's spec lacks (before any member is sent anything)."
  (check-ensemble 'send-scene-event ensemble)
  (check-scene-timing 'send-scene-event at when-busy)
  (let ((targets (resolve-scene-entry (ensemble-cast ensemble) (if at (cons address at) address))))
    (loop for (member . entry) in targets
          do (find-compiled-event (ensemble-controller ensemble member) (event-entry-name entry)
                                  'send-scene-event))
    (let ((ok t))
      (loop for (member . entry) in targets
            do (unless (apply #'send-event (ensemble-controller ensemble member) (event-entry-name entry)
                              (append (and (consp entry) (list :at (cdr entry)))
                                      (and when-busy (list :when-busy when-busy))))
                 (setf ok nil)))
      ok)))

(defun play-scene-events (ensemble events &key until when-busy)
  "Play the scenario EVENTS (entries ADDRESS or (ADDRESS . SECONDS), see
SEND-SCENE-EVENT) on ENSEMBLE: each member plays, with PLAY-EVENTS, the
events addressed to it in order, exactly as a lone controller given that list
would.  Checks every address and event before anything plays."
  (check-ensemble 'play-scene-events ensemble)
  (check-argument 'play-scene-events 'events events
                  (lambda (x) (and (alexandria:proper-list-p x) (every #'event-entry-p x)))
                  "a proper list of event addresses (symbols or strings) or (ADDRESS . SECONDS) pairs")
  (when until (check-seconds 'play-scene-events :until until :minimum 0))
  (check-scene-timing 'play-scene-events nil when-busy)
  (let ((split (split-scene-events (ensemble-cast ensemble) events)))
    (loop for (member . entries) in split
          do (dolist (entry entries)
               (find-compiled-event (ensemble-controller ensemble member) (event-entry-name entry)
                                    'play-scene-events)))
    (loop for (member . entries) in split
          do (play-events (ensemble-controller ensemble member) entries :until until :when-busy when-busy))
    ensemble))

(defun scene-timed-members (cast events until &optional when-busy)
  "The names of CAST's members whose controllers must be timed to play EVENTS
until UNTIL: those whose own scenario needs it (TIMED-SCENARIO-P), or all
with WHEN-BUSY -- what a lone run of each member's scenario would choose."
  (loop for (member . entries) in (split-scene-events cast events)
        when (or when-busy (timed-scenario-p entries until))
          collect member))

;;;# Traces

(defun ensemble-trace-lines (ensemble)
  "Every member's trace lines, member by member in the scene's order, as (MEMBER . LINE)."
  (check-ensemble 'ensemble-trace-lines ensemble)
  (loop for performer in (ensemble-performers ensemble)
        for presenter = (controller-presenter (performer-controller performer))
        when (trace-presenter-p presenter)
          append (mapcar (lambda (line) (cons (performer-name performer) line)) (trace-lines presenter))))

(defun write-scene-trace-line (member line &optional (stream *standard-output*))
  "Write LINE of MEMBER's trace as \"MEMBER: LINE\" and a newline to STREAM."
  (format stream "~A: " (lisp-text member))
  (write-trace-line line stream))

(defun write-ensemble-trace (ensemble &optional (stream *standard-output*))
  "Write ENSEMBLE's trace (ENSEMBLE-TRACE-LINES) to STREAM, one prefixed line each."
  (loop for (member . line) in (ensemble-trace-lines ensemble)
        do (write-scene-trace-line member line stream)))

(defun write-ensemble-states (ensemble &optional (stream *standard-output*))
  "Write each member's current state as its (:state ...) trace line, prefixed."
  (dolist (performer (ensemble-performers ensemble))
    (let ((presenter (make-trace-presenter)))
      (present-state presenter (performer-controller performer))
      (dolist (line (trace-lines presenter))
        (write-scene-trace-line (performer-name performer) line stream)))))
