;;;; tapes.lisp -- plans taped and replayed.  Planning an event ahead runs its
;;;; compiled closures, which test plan conditions and call each other to
;;;; find the ops to play.  For most events what they find depends only on
;;;; the plannable state the event starts from: the same state, the same ops,
;;;; changes and macro spans, in the same order.  So the first time a timed
;;;; controller plans such an event from a state, it tapes what the closures
;;;; hand the recorder; the next time, it replays the tape.  A replay calls
;;;; the same recording functions with the same arguments and moves the clock
;;;; with the same arithmetic as the closures (an op's start plus its
;;;; duration, a macro's span as the largest end inside it), so the items and
;;;; their times are the very ones the closures would have made, to the last
;;;; bit.
;;;;
;;;; An event is taped only when nothing but the plannable state can steer
;;;; it (TAPEABLE-EVENT-P): its directives and every macro's are goals, ops,
;;;; plain assignments and C++ text -- no :if, :time, :label, arithmetic on
;;;; numbers or :code, and no :code op anywhere -- the machine plans every
;;;; state (not the reachable regime, which may search at run time), and the
;;;; presenter answers each op's declared duration.  A plan that sets a
;;;; runtime value anyway spoils its tape (RECORD-VALUE-CHANGE).

(in-package #:player.control)

(declaim #.*timeline-optimize*)                 ; the engine's policy (agenda.lisp)

(defparameter *plan-tapes-per-event* 1024
  "How many start states a timed controller keeps an event's plan taped for;
from others, once that many are kept, the event is planned by its closures.")

(defstruct (plan-tape (:constructor make-plan-tape (entries result step)))
  "What an event's closures did from one state: ENTRIES, five slots for each
call they made to the recorder (see REPLAY-TAPE), what they returned (T or a
FAILURE), and the top-level directive they ended in."
  (entries #() :type simple-vector)
  (result t)
  (step 0 :type fixnum))

(defun directives-tapeable-p (directives)
  "Are parsed DIRECTIVES only goals, ops, plain assignments and C++ text,
whose outcome the plannable state alone decides?"
  (every (lambda (directive) (member (first directive) '(:achieve :op :assign :c++)))
         directives))

(defun spec-tapeable-p (spec)
  "Can any plan of SPEC be taped: no :code op, and no macro-op whose :seq
holds a directive other than TAPEABLE ones?"
  (every (lambda (op)
           (case (op-kind op)
             (:code nil)
             (:macro (directives-tapeable-p (op-seq op)))
             (t t)))
         (spec-ops spec)))

;; Inline: a timed controller asks for every event it plans.
(declaim (inline event-tapeable-p))
(defun event-tapeable-p (compiled machine)
  "Is the plan of COMPILED, an event of MACHINE, decided by the plannable state
alone, so that it may be taped (see above)?  Worked out once per event."
  (let ((known (compiled-event-tapeable compiled)))
    (if (eq known :unknown)
        (setf (compiled-event-tapeable compiled)
              (and (null (layout-reachable (machine-layout machine)))
                   (spec-tapeable-p (machine-spec machine))
                   (directives-tapeable-p (event-directives (compiled-event-event compiled)))))
        known)))

;;;# The tapes of an event, by start state
;;;
;;; An event's tapes belong to its compiled event, so every controller of the
;;; machine replays what any of them taped (a tape depends on the machine
;;; alone).  Controllers on several threads may share a machine, so a table is
;;; never changed once published: adding a tape makes a new table (copy on
;;; write; a tape two threads add at once may be lost, and is taped again).

(defstruct (tape-table (:constructor make-tape-table (slots count)))
  "Open addressing: a start state at 2i, its PLAN-TAPE at 2i+1, NIL at 2i when
empty; at most half the pairs full, so every probe ends."
  (slots (make-array 16 :initial-element nil) :type simple-vector)
  (count 0 :type fixnum))

(declaim (inline tape-key-hash))
(defun tape-key-hash (key)
  "A hash of plannable state KEY (an integer) for a tape table."
  (if (typep key 'fixnum)
      (logand (logxor key (ash key -11) (ash key -23)) most-positive-fixnum)
      (sxhash key)))

;; Inline: a timed controller looks for every event it plans.
(declaim (inline find-plan-tape))
(defun find-plan-tape (table key)
  "The PLAN-TAPE in TABLE (a TAPE-TABLE or NIL) for start state KEY, or NIL."
  (when table
    (let* ((slots (tape-table-slots table))
           (mask (1- (ash (length slots) -1))))
      (declare (fixnum mask))
      (loop for i of-type fixnum = (logand (tape-key-hash key) mask) then (logand (1+ i) mask)
            for stored = (svref slots (* 2 i))
            do (cond ((null stored) (return nil))
                     ;; A fixnum state (the usual one) compares without a call.
                     ((if (typep key 'fixnum) (eq stored key) (eql stored key))
                      (return (svref slots (1+ (* 2 i))))))))))

(defun table-with-tape (table key tape)
  "A new tape table: TABLE's pairs (none when TABLE is NIL) and KEY -> TAPE."
  (let* ((count (1+ (if table (tape-table-count table) 0)))
         (pairs (loop for pairs = 8 then (* 2 pairs) when (>= pairs (* 2 count)) return pairs))
         (slots (make-array (* 2 pairs) :initial-element nil))
         (mask (1- pairs)))
    (flet ((put (key tape)
             (loop for i = (logand (tape-key-hash key) mask) then (logand (1+ i) mask)
                   when (null (svref slots (* 2 i)))
                     return (setf (svref slots (* 2 i)) key
                                  (svref slots (1+ (* 2 i))) tape))))
      (when table
        (let ((old (tape-table-slots table)))
          (loop for i from 0 below (length old) by 2
                when (svref old i) do (put (svref old i) (svref old (1+ i))))))
      (put key tape))
    (make-tape-table slots count)))

;;;# Taping and replaying

(defun replay-macro-start (recorder controller op)
  "What COMPILE-MACRO-EXECUTOR does as macro-op OP begins, in the same order:
its span, and the outer one, are kept in RECORDER's MACRO-SPANS (unboxed
doubles, three a macro open: START, OUTER-START, OUTER-END)."
  (let* ((spans (recorder-macro-spans recorder))
         (at (* 3 (recorder-macro-depth recorder)))
         (start (controller-schedule controller)))
    (declare (simple-vector spans) (fixnum at))
    (when (> (+ at 3) (length spans))
      (setf spans (replace (make-array (* 2 (length spans)) :initial-element 0) spans)
            (recorder-macro-spans recorder) spans))
    (setf (aref spans at) start
          (aref spans (+ at 1)) (controller-span-start controller)
          (aref spans (+ at 2)) (controller-span-end controller))
    (incf (recorder-macro-depth recorder))
    (record-macro-start recorder op start)
    (setf (controller-span-start controller) start
          (controller-span-end controller) start)))

(defun replay-macro-end (recorder controller op)
  "What COMPILE-MACRO-EXECUTOR does as the innermost macro-op open, OP, ends:
its span closes, the clock moves to its end."
  (let* ((spans (recorder-macro-spans recorder))
         (at (* 3 (decf (recorder-macro-depth recorder))))
         (start (aref spans at))
         (outer-end (aref spans (+ at 2)))
         (end (controller-span-end controller)))
    (declare (simple-vector spans) (fixnum at))
    (setf (controller-span-start controller) (aref spans (+ at 1))
          (controller-span-end controller) (if (micros< outer-end end) end outer-end)
          (controller-schedule controller) end)
    (record-macro-end recorder op start end)))

(defun replay-tape (recorder controller tape)
  "Do to RECORDER what the closures did when TAPE was made, with CONTROLLER's
clock where they found theirs; return what they returned.  Each entry is a
code, an op, a mask, bits and the step it was made in; the codes
(RECORDER.LISP) say:
  +TAPED-OP+            the op played (RECORD-OP-PLAYED, its end's change MASK BITS)
  +TAPED-MACRO-START+   a macro-op began: its span opens at the clock
  +TAPED-MACRO-END+     the macro-op ended: its span closes, the clock moves to its end
  +TAPED-STATE-CHANGE+  the fields of MASK became BITS at the clock, at the end of the op or NIL."
  (let* ((entries (plan-tape-entries tape))
         (count (length entries)))
    (declare (simple-vector entries) (fixnum count))
    (setf (recorder-macro-depth recorder) 0)
    (do ((i 0 (+ i 5)))
        ((>= i count))
      (declare (fixnum i))
      (let ((op (svref entries (+ i 1))))
        (setf (controller-step controller) (the fixnum (svref entries (+ i 4))))
        (let ((code (svref entries i)))
          (cond ((eql code +taped-op+)
                 (record-op-played recorder controller op (svref entries (+ i 2)) (svref entries (+ i 3))))
                ((eql code +taped-macro-start+) (replay-macro-start recorder controller op))
                ((eql code +taped-macro-end+) (replay-macro-end recorder controller op))
                ((eql code +taped-state-change+)
                 (record-change recorder :delta controller (controller-schedule controller)
                                (svref entries (+ i 2)) (svref entries (+ i 3)) op))))))
    (setf (controller-step controller) (plan-tape-step tape))
    (plan-tape-result tape)))

(defun tape-plan (recorder controller compiled closure)
  "Run CLOSURE, COMPILED's plan from its first directive, on CONTROLLER,
taping what it hands RECORDER; keep the tape under the start state unless it
is spoiled (or the event has *PLAN-TAPES-PER-EVENT* already).  Return what
CLOSURE returns."
  (let ((key (controller-bits controller)))
    (setf (recorder-taping recorder) t
          (recorder-tape recorder) '())
    (let ((result (let ((*controller* controller))
                    (funcall (the function closure) controller)))
          (tape (recorder-tape recorder))
          (table (compiled-event-tapes compiled)))
      (setf (recorder-taping recorder) nil
            (recorder-tape recorder) '())
      (unless (or (eq tape :spoiled)
                  (and table (>= (tape-table-count table) *plan-tapes-per-event*)))
        (setf (compiled-event-tapes compiled)
              (table-with-tape table key (make-plan-tape (coerce (reverse tape) 'simple-vector)
                                                         result (controller-step controller)))))
      result)))

(defun run-event-plan (timeline run controller)
  "Plan RUN on CONTROLLER (its recorder recording, the clocks set): replay
the tape of RUN's event from the current plannable state if there is one,
else run the event's closures (taping them when the event may be taped),
with *CONTROLLER* bound for their :code and presenters (a replay runs
neither).  Return the plan's result, T or a FAILURE."
  (let* ((compiled (run-compiled run))
         (machine (controller-machine controller))
         (recorder (timeline-recorder timeline)))
    (flet ((closure ()
             (svref (event-suffixes compiled machine) (run-first-step run))))
      (declare (inline closure))
      (if (and (zerop (run-first-step run)) (timeline-replay-tapes timeline)
               (recorder-declared-durations recorder) (event-tapeable-p compiled machine))
          (let ((tape (find-plan-tape (compiled-event-tapes compiled) (controller-bits controller))))
            (if tape
                (replay-tape recorder controller tape)
                (tape-plan recorder controller compiled (closure))))
          (let ((*controller* controller))
            (funcall (the function (closure)) controller))))))
