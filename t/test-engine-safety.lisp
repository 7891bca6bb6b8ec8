;;;; test-engine-safety.lisp -- the timed engine checked by default (issue 25,
;;;; item 5): the policy it compiles at, agenda items retired twice or applied
;;;; once retired, what a
;;;; presenter answers validated, and a SEND-EVENT from inside a controller's
;;;; own event deferred.  `make test-unchecked-engine' runs this suite against
;;;; the unchecked build too: the tests of checks only that build makes skip
;;;; there (UNCHECKED-ENGINE-P).

(in-package #:player-tests)

(def-suite* engine-safety :in player-tests)

(defun unchecked-engine-p ()
  "Was the timed engine compiled with :PLAYER-UNCHECKED-ENGINE, at (safety 0)?"
  (and (member '(safety 0) (rest player.control::*timeline-optimize*) :test #'equal) t))

;;; The policy

(test engine-policy-follows-the-feature
  "The engine compiles checked unless the build had :player-unchecked-engine."
  (if (member :player-unchecked-engine *features*)
      (is (unchecked-engine-p))
      (is (equal '(optimize (speed 1) (safety 1) (debug 1)) player.control::*timeline-optimize*))))

(test checked-engine-checks-its-structures
  "Checked, an engine function handed something that is not an agenda item
signals a type error instead of writing through it."
  (if (unchecked-engine-p)
      (skip "the unchecked engine does not check")
      (signals type-error (player.control::agenda-push (player.control::make-agenda) 42))))

(test an-item-retired-twice-is-an-error
  "Checked, retiring an agenda item already in the pool signals a
RETIRED-ITEM-ERROR (a TIMELINE-ERROR), and so does a list holding one: the
pool would hand it out twice."
  (if (unchecked-engine-p)
      (skip "the unchecked engine does not check")
      (let* ((agenda (player.control::make-agenda))
             (item (player.control::fresh-agenda-item agenda :op 0 nil))
             (other (player.control::fresh-agenda-item agenda :op 1000000 nil)))
        (player.control::retire-item agenda item)
        (is (eq :free (player.control::agenda-item-status item)))
        (signals player.control::retired-item-error (player.control::retire-item agenda item))
        (signals timeline-error (player.control::retire-item-list agenda (list other item)))
        ;; Retired once, an item goes back to the pool once.
        (is (eq item (player.control::fresh-agenda-item agenda :op 2000000 nil))))))

(test tape-codes-are-distinct
  "The tape's codes are four different numbers, so a replay tells them apart."
  (is (= 4 (length (remove-duplicates (list player.control::+taped-op+ player.control::+taped-macro-start+
                                            player.control::+taped-macro-end+
                                            player.control::+taped-state-change+))))))

(test a-retired-item-applied-is-an-error
  "Checked, an item due on the agenda that was retired (too early: something
still reached it) is a RETIRED-ITEM-ERROR when its time comes, not a state
change of whatever the pool made of it."
  (if (unchecked-engine-p)
      (skip "the unchecked engine does not check")
      (with-spec (spec retired-early
                   (state-variable walked boolean false)
                   (op walk :add walked :duration 1)
                   (event ev-go :state walked))
        (let* ((c (make-controller spec :timed t))
               (timeline (player.control::controller-timeline c)))
          (send-event c 'ev-go)
          (let* ((agenda (player.control::timeline-agenda timeline))
                 (top (svref (player.control::agenda-items agenda) 0)))
            (player.control::retire-item agenda top)
            (let ((error (handler-case (progn (finish-events c) nil)
                           (player.control::retired-item-error (e) e))))
              (is (typep error 'timeline-error))
              ;; Caught as it is applied, not later as it is retired again.
              (is (search "applied" (princ-to-string error)))))))))

;;; What a presenter answers

(defclass answering-presenter (trace-presenter)
  ((answer :initarg :answer :accessor presenter-answer))
  (:documentation "A trace presenter whose ops take ANSWER seconds, whatever that is:
PRESENT-OP and PLANNED-OP-DURATION both answer it, and CRITICAL-TIME too."))

(defmethod present-op ((presenter answering-presenter) op start)
  (call-next-method)
  (presenter-answer presenter))

(defmethod player.control::planned-op-duration ((presenter answering-presenter) op start)
  (declare (ignore op start))
  (presenter-answer presenter))

(defmethod player.control::critical-time ((presenter answering-presenter) op name)
  (declare (ignore op name))
  (presenter-answer presenter))

(defun bad-durations ()
  "Answers a presenter may not give for a duration: NaN, the infinities, a
negative number, something not a number."
  ;; The NaN made from its bits: arithmetic making one would trap.
  (list (sb-kernel:make-double-float -524288 0)
        sb-ext:double-float-positive-infinity sb-ext:double-float-negative-infinity
        -1d0 -1/2 "2 seconds" nil))

(defmacro with-walk-spec ((var) &body body)
  "BODY with VAR a spec of two ops in a row, WALK then TURN, sent by EV-GO."
  `(with-spec (,var answer-walk
                (state-variable walked boolean false)
                (state-variable turned boolean false)
                (op walk :add walked :duration 1)
                (op turn :precond walked :add turned :duration 1)
                (event ev-go :state turned))
     ,@body))

(test presenter-durations-are-checked-whole-event
  "A whole-event controller takes only finite durations of 0 or more from
PRESENT-OP: any other answer is a PRESENTER-RESULT-ERROR naming the
presenter, the op and the value, before the op changes anything, and the
controller plays on once the presenter answers again."
  (with-walk-spec (spec)
    (dolist (bad (bad-durations))
      (let* ((presenter (make-instance 'answering-presenter :answer bad))
             (c (make-controller spec :presenter presenter)))
        (let ((error (handler-case (progn (send-event c 'ev-go) nil)
                       (player.control::presenter-result-error (e) e))))
          (is (typep error 'player-error))
          (when error
            (is (eq presenter (player.control::presenter-result-error-presenter error)))
            (is (eq 'walk (op-name (player.control::presenter-result-error-op error))))
            (is (eql bad (player.control::presenter-result-error-value error)))
            (is (search "walk" (princ-to-string error)))))
        (is (null (state-value c 'walked)) "WALK's effect was not applied")
        (is (= 0 (controller-clock c)))
        (setf (presenter-answer presenter) 2)
        (is (eq t (send-event c 'ev-go)))
        (is (eq t (state-value c 'turned)))
        (is (= 4 (controller-clock c)))))))

(test presenter-durations-are-checked-timed
  "A timed controller takes only finite durations of 0 or more from
PLANNED-OP-DURATION: any other answer is a PRESENTER-RESULT-ERROR before the
event is installed, and the controller plays on."
  (with-walk-spec (spec)
    (dolist (bad (bad-durations))
      (let* ((presenter (make-instance 'answering-presenter :answer bad))
             (c (make-controller spec :presenter presenter :timed t)))
        (signals player.control::presenter-result-error (send-event c 'ev-go))
        (is (not (controller-busy-p c)) "nothing of the event was installed")
        (setf (presenter-answer presenter) 1/2)
        (is (eq t (send-event c 'ev-go)))
        (is (= 1 (finish-events c)))
        (is (eq t (state-value c 'turned)))))))

(test presenter-critical-times-are-checked
  "An interruption point a presenter answers must be finite seconds, 0 or more."
  (with-spec (spec answer-crit
               (state-variable walked boolean false)
               (op walk :add walked :duration 1 :interrupt (:at half))
               (event ev-go :state walked))
    (dolist (bad (bad-durations))
      (signals player.control::presenter-result-error
        (make-controller spec :timed t :presenter (make-instance 'answering-presenter :answer bad))))
    (is (player.control::controller-p (make-controller spec :timed t :presenter (make-instance 'answering-presenter :answer 0.5d0))))))

;;; A send from inside the controller's own event

(defmacro with-reentry-spec ((var) &body body)
  "BODY with VAR the spec of issue 25: EV-B's :code sends EV-C to its own controller."
  `(with-spec (,var reentry
                (state-variable pos string a (a b c))
                (op go-b :precond pos.a :add pos.b :duration 1)
                (op go-c :precond pos.b :add pos.c :duration 1)
                (event ev-b :state pos.b :code (send-event *controller* 'ev-c))
                (event ev-c :state pos.c))
     ,@body))

(defparameter *reentry-trace*
  '("(:event ev-b :time 0)"
    "(:op go-b :script go-b :start 0 :end 1)"
    "(:state (pos . b))"
    "(:event ev-c :time 1)"
    "(:op go-c :script go-c :start 1 :end 2)"
    "(:state (pos . c))")
  "The trace of ev-b, whose :code sends ev-c to its own controller, on either
controller: ev-b's op whole, then ev-c's from the state ev-b left.")

(test code-sending-to-its-own-controller-is-deferred
  "A whole-event controller's :code sending an event to it: the outer event
plays whole, then the one sent, from the state the outer left."
  (with-reentry-spec (spec)
    (let ((c (make-controller spec)))
      (is (eq t (send-event c 'ev-b)))
      (is (equal *reentry-trace* (trace-of c)))
      (is (eq 'c (state-value c 'pos)))
      (is (= 2 (controller-clock c))))))

(test code-sending-to-its-own-timed-controller-is-deferred
  "A timed controller's :code sending an event to it while it plans: the
outer event plays whole, the one sent arrives when it is planned and waits
for it (its policy, :queue)."
  (with-reentry-spec (spec)
    (let ((c (make-controller spec :timed t)))
      (is (eq t (send-event c 'ev-b)))
      (is (= 2 (finish-events c)))
      ;; The timed controller says when ev-c arrived and whom it waits behind.
      (is (equal (append (subseq *reentry-trace* 0 2)
                         '("(:queued ev-c :time 0 :behind ev-b)")
                         (subseq *reentry-trace* 2))
                 (trace-of c)))
      (is (eq 'c (state-value c 'pos))))))

(test deferred-sends-are-checked-where-they-are-sent
  "A deferred send of an unknown event is an error in the :code that sends it;
a timed one may not ask for a later time."
  (with-spec (spec reentry-bad
               (state-variable pos string a (a b))
               (op go-b :precond pos.a :add pos.b :duration 1)
               (event ev-b :state pos.b :code (send-event *controller* 'ev-nowhere))
               (event ev-later :code (send-event *controller* 'ev-b :at 5)))
    (signals unknown-event (send-event (make-controller spec) 'ev-b))
    (signals unknown-event (send-event (make-controller spec :timed t) 'ev-b))
    (let ((c (make-controller spec :timed t)))
      (signals argument-error (send-event c 'ev-later))
      (is (not (controller-busy-p c))))))

(test events-sending-themselves-for-ever-are-an-error
  "An event whose :code sends itself again and again: a DEFERRED-SENDS-ERROR
once too many were sent, not a stack overflow or a hang."
  (with-spec (spec reentry-loop
               (state-variable n integer 0)
               (event ev-again :add (n 1) :code (send-event *controller* 'ev-again)))
    (let ((player.control::*max-deferred-sends* 50)
          (c (make-controller spec :presenter (make-null-presenter))))
      (signals player.control::deferred-sends-error (send-event c 'ev-again))
      (is (= 51 (state-value c 'n)))
      (is (null (player.control::controller-deferred-sends c))))))
