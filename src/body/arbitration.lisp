;;;; arbitration.lisp -- who drives which DOF channel: Pantomime's Arbitrator.
;;;; Drivers request channels with a priority; the best request owns each
;;;; channel, a higher priority usurps it (the loser is told through
;;;; ON-CHANNEL-LOSS), and a release hands the channel to the best waiting
;;;; request.  Every change of owner is stamped with a time and a blend duration
;;;; so an evaluator can crossfade; slaves request on their master's behalf.

(in-package #:player.body)

;;; The rule, in one sentence: the owner of a channel is always its best active
;;; request, where a higher priority beats a lower one and, between equal
;;; priorities, the earlier request wins unless the later one usurps (else the
;;; body blends the owner with its equals: CHANNEL-SHARERS, blending.lisp).
;;; A driver has at most one request per channel; requesting again changes its
;;; priority and keeps its place in time.  A usurped driver keeps its request,
;;; waiting: it gets the channel back (and ON-CHANNEL-GRANT) when the usurper
;;; releases, unless it releases first -- from ON-CHANNEL-LOSS, say, to end.
;;;
;;; A channel is any object compared with EQUAL: a joint name, a role, or a
;;; (JOINT . DOF) pair from SKELETON-CHANNELS.  A driver is any object compared
;;; with EQ.  Handlers run after the arbitrator's state is consistent, so they
;;; may request and release freely.

(defgeneric on-channel-loss (driver channel new-owner)
  (:documentation "Called once each time DRIVER loses CHANNEL to NEW-OWNER, a
driver of higher priority (or of equal priority and earlier request, after
DRIVER lowered its own).  DRIVER's request stays waiting; DRIVER may release it
to end, or keep it to resume.  A slave's loss is then reported to its master,
and to its master's master.  The default method does nothing.")
  (:method (driver channel new-owner)
    (declare (ignore driver channel new-owner))
    nil))

(defgeneric on-channel-grant (driver channel previous-owner)
  (:documentation "Called when a waiting request of DRIVER becomes CHANNEL's owner
because PREVIOUS-OWNER (or NIL) released it or lowered its priority.  Not called
for a request that is granted at once: REQUEST-CHANNELS returns those.  The
default method does nothing.")
  (:method (driver channel previous-owner)
    (declare (ignore driver channel previous-owner))
    nil))

(defgeneric driver-priority (driver)
  (:documentation "DRIVER's own priority, used when REQUEST-CHANNELS gets none and
DRIVER has no master; NIL (the default) for none.")
  (:method (driver)
    (declare (ignore driver))
    nil))

(define-condition arbitration-error (player-error)
  ((message :initarg :message :reader arbitration-error-message))
  (:report (lambda (condition stream)
             (write-string (arbitration-error-message condition) stream)))
  (:documentation "A request the arbitrator cannot serve: no priority, a master
cycle, a non-real priority."))

(defun arbitration-fail (control &rest arguments)
  "Signal an ARBITRATION-ERROR with a message from CONTROL and ARGUMENTS."
  (error 'arbitration-error :message (apply #'format nil control arguments)))

;;; ---------------------------------------------------------------------------
;;; Data

(defstruct (channel-request (:constructor make-channel-request (driver priority serial &optional usurp)))
  "DRIVER's claim on one channel at PRIORITY; SERIAL orders requests in time; USURP beats earlier equals."
  (driver nil :read-only t)
  (priority 0 :type real)
  (serial 0 :type (integer 0) :read-only t)
  (usurp nil :read-only t))

(defstruct (channel-state (:constructor make-channel-state ()))
  "One channel: its requests, best first (the first is the owner), and its last
change of owner."
  (requests '() :type list)
  (handover-time nil :type (or null real))
  (blend-duration 0 :type (real 0)))

(defstruct (driver-record (:constructor make-driver-record ()))
  "What an arbitrator knows about one driver; dropped as soon as it is empty."
  (channels '() :type list)
  (priority nil :type (or null real))
  (master nil)
  (slaves '() :type list))

(defstruct (arbitrator (:constructor %make-arbitrator))
  "Owners and waiting requests of every channel, and the drivers' master/slave links."
  (channels (make-hash-table :test #'equal) :type hash-table)
  (drivers (make-hash-table :test #'eq) :type hash-table)
  (serial 0 :type (integer 0))
  (clock 0 :type real)
  (blend-time 0 :type (real 0)))

(defun make-arbitrator (&key (blend-time 0) (clock 0))
  "A new arbitrator with no channels held.  BLEND-TIME (seconds) is how long a
change of owner blends unless a request or release says otherwise; CLOCK is the
time used when a request or release gives no :TIME."
  (check-real 'make-arbitrator :blend-time blend-time :minimum 0 :maximum *max-seconds*)
  (check-seconds 'make-arbitrator :clock clock)
  (%make-arbitrator :blend-time blend-time :clock clock))

(defmethod print-object ((arbitrator arbitrator) stream)
  (print-unreadable-object (arbitrator stream :type t :identity t)
    (format stream "~D channels held, ~D drivers"
            (count-if #'channel-state-requests
                      (alexandria:hash-table-values (arbitrator-channels arbitrator)))
            (hash-table-count (arbitrator-drivers arbitrator)))))

;;; ---------------------------------------------------------------------------
;;; Queries

(defun check-arbitrator (function arbitrator)
  "ARBITRATOR, when it is one; else an ARGUMENT-ERROR of FUNCTION."
  (check-argument function 'arbitrator arbitrator #'arbitrator-p "an arbitrator (from make-arbitrator)"))

(defun check-channels (function channels)
  "CHANNELS, one channel or a proper list of them; else an ARGUMENT-ERROR of FUNCTION."
  (check-argument function 'channels channels
                  (lambda (x) (or (atom x) (and (alexandria:proper-list-p x) (bounded-form-p x))))
                  "a channel or a proper list of channels"))

(defun check-driver (function driver &optional (argument 'driver))
  "DRIVER, any object but NIL; else an ARGUMENT-ERROR of FUNCTION."
  (check-argument function argument driver #'identity "a driver (any object but NIL)"))

(defun check-time-and-blend (function arbitrator time blend)
  "TIME and BLEND, defaulted from ARBITRATOR and checked, as two values."
  (values (if time
              (progn (check-seconds function :time time) time)
              (arbitrator-clock arbitrator))
          (if blend
              (check-real function :blend blend :minimum 0 :maximum *max-seconds*)
              (arbitrator-blend-time arbitrator))))

(defun channel-owner (arbitrator channel)
  "The driver that owns CHANNEL in ARBITRATOR, or NIL."
  (check-arbitrator 'channel-owner arbitrator)
  (let ((state (gethash channel (arbitrator-channels arbitrator))))
    (and state (channel-state-requests state)
         (channel-request-driver (first (channel-state-requests state))))))

(defun channel-waiting (arbitrator channel)
  "The drivers waiting for CHANNEL, best first (the owner excluded)."
  (let ((state (gethash channel (arbitrator-channels arbitrator))))
    (and state (mapcar #'channel-request-driver (rest (channel-state-requests state))))))

(defun channels-of (arbitrator driver &key (owned-only nil))
  "The channels DRIVER has requested in ARBITRATOR, oldest request first; with
OWNED-ONLY, just those it owns now."
  (let ((record (gethash driver (arbitrator-drivers arbitrator))))
    (and record
         (remove-if-not (lambda (channel)
                          (or (not owned-only)
                              (eq (channel-owner arbitrator channel) driver)))
                        (reverse (driver-record-channels record))))))

(defun driver-master (arbitrator driver)
  "DRIVER's master in ARBITRATOR, or NIL."
  (let ((record (gethash driver (arbitrator-drivers arbitrator))))
    (and record (driver-record-master record))))

(defun driver-slaves (arbitrator driver)
  "DRIVER's slaves in ARBITRATOR, in the order they were added."
  (let ((record (gethash driver (arbitrator-drivers arbitrator))))
    (and record (reverse (driver-record-slaves record)))))

(defun known-drivers (arbitrator)
  "Every driver ARBITRATOR holds any record of (requests or master/slave links)."
  (alexandria:hash-table-keys (arbitrator-drivers arbitrator)))

(defun channel-handover (arbitrator channel)
  "The time and blend duration of CHANNEL's last change of owner, as two values;
NIL and 0 when its owner never changed."
  (let ((state (gethash channel (arbitrator-channels arbitrator))))
    (if state
        (values (channel-state-handover-time state) (channel-state-blend-duration state))
        (values nil 0))))

(defun channel-blend-weight (arbitrator channel time)
  "The weight, from 0 to 1, of CHANNEL's current owner at TIME in the crossfade
from the previous owner's output (or the rest pose, for a channel that was free):
0 at the handover, rising linearly to 1 after its blend duration.  1 for a
channel whose owner never changed or whose blend duration is zero.  When the
channel has become free, it is the weight of the rest pose."
  (check-arbitrator 'channel-blend-weight arbitrator)
  (check-seconds 'channel-blend-weight 'time time)
  (multiple-value-bind (handover duration) (channel-handover arbitrator channel)
    (cond ((null handover) 1)
          ((zerop duration) (if (>= time handover) 1 0))
          (t (max 0 (min 1 (/ (- time handover) duration)))))))

;;; ---------------------------------------------------------------------------
;;; Driver records

(defun driver-record (arbitrator driver)
  "DRIVER's record in ARBITRATOR, created when missing."
  (let ((table (arbitrator-drivers arbitrator)))
    (or (gethash driver table)
        (setf (gethash driver table) (make-driver-record)))))

(defun forget-driver-if-idle (arbitrator driver)
  "Drop DRIVER's record when it holds no request and no master/slave link, so
nothing in ARBITRATOR refers to DRIVER any more."
  (let ((record (gethash driver (arbitrator-drivers arbitrator))))
    (when (and record
               (null (driver-record-channels record))
               (null (driver-record-master record))
               (null (driver-record-slaves record)))
      (remhash driver (arbitrator-drivers arbitrator)))))

(defun effective-priority (arbitrator driver)
  "The priority DRIVER requests at when it gives none: its master's, for a slave;
else its last requested priority, else DRIVER-PRIORITY.  Signals
ARBITRATION-ERROR when there is none."
  (let* ((record (gethash driver (arbitrator-drivers arbitrator)))
         (master (and record (driver-record-master record))))
    (cond (master (effective-priority arbitrator master))
          ((and record (driver-record-priority record)))
          ((driver-priority driver))
          (t (arbitration-fail "driver ~A has no priority: give :priority, define ~
                                DRIVER-PRIORITY, or make it a slave" (argument-value-text driver))))))

(defun masters-of (arbitrator driver)
  "DRIVER's master, its master's master, and so on."
  (loop for master = (driver-master arbitrator driver) then (driver-master arbitrator master)
        while master
        collect master))

;;; ---------------------------------------------------------------------------
;;; Settling a channel

(defun request-better-p (a b)
  "Does request A beat request B: higher priority; or equal, and A the later
one usurping, or the earlier one when the later does not usurp?"
  (or (> (channel-request-priority a) (channel-request-priority b))
      (and (= (channel-request-priority a) (channel-request-priority b))
           (if (< (channel-request-serial a) (channel-request-serial b))
               (not (channel-request-usurp b))
               (channel-request-usurp a)))))

(defvar *requesting-driver* nil
  "The driver whose REQUEST-CHANNELS is running: it learns of its grants from the
return value, not from ON-CHANNEL-GRANT.")

(defun settle-channel (arbitrator channel state old-owner time blend &key sort)
  "Sort STATE's requests when SORT (else they are in order); if CHANNEL's owner is no
longer OLD-OWNER, stamp the handover at TIME with BLEND seconds and return the notifications
due, as a list of (:loss|:grant RECIPIENT CHANNEL OTHER SUBJECT) for NOTIFY."
  (when sort
    (setf (channel-state-requests state) (stable-sort (channel-state-requests state) #'request-better-p)))
  (let ((new-owner (and (channel-state-requests state)
                        (channel-request-driver (first (channel-state-requests state))))))
    (unless (eq new-owner old-owner)
      (setf (channel-state-handover-time state) time
            (channel-state-blend-duration state) blend)
      (let ((old-still-waiting
              (and old-owner (find old-owner (channel-state-requests state)
                                   :key #'channel-request-driver))))
        (append (and old-still-waiting
                     (loop for recipient in (cons old-owner (masters-of arbitrator old-owner))
                           collect (list :loss recipient channel new-owner old-owner)))
                (and new-owner (not (eq new-owner *requesting-driver*))
                     (list (list :grant new-owner channel old-owner new-owner))))))))

(defun notify (arbitrator notifications)
  "Call ON-CHANNEL-LOSS or ON-CHANNEL-GRANT for each of NOTIFICATIONS, in order,
each (KIND RECIPIENT CHANNEL OTHER SUBJECT).  A notification whose news an
earlier handler made stale is skipped: a loss once SUBJECT (the driver, or the
slave, that lost) has released CHANNEL, a grant once SUBJECT no longer owns it."
  (loop for (kind recipient channel other subject) in notifications
        do (ecase kind
             (:loss (when (member channel (channels-of arbitrator subject) :test #'equal)
                      (on-channel-loss recipient channel other)))
             (:grant (when (eq subject (channel-owner arbitrator channel))
                       (on-channel-grant recipient channel other))))))

;;; ---------------------------------------------------------------------------
;;; Requests and releases

(defun request-channels (arbitrator driver channels &key priority time blend usurp)
  "Request CHANNELS (a list, or one channel) for DRIVER at PRIORITY (a real;
higher wins; with USURP, an equal priority requested earlier loses too).  Without PRIORITY a slave uses its master's, other drivers their
last one or DRIVER-PRIORITY.  A channel DRIVER already requested takes the new
priority and keeps its place in time.  Usurped owners are told through
ON-CHANNEL-LOSS after all CHANNELS are settled; each change of owner is stamped
at TIME with BLEND seconds.  Returns the channels among CHANNELS that DRIVER now
owns.  Signals ARBITRATION-ERROR when no priority can be found.  TIME defaults
to the arbitrator's clock, BLEND to its blend time."
  (check-arbitrator 'request-channels arbitrator)
  (check-driver 'request-channels driver)
  (check-channels 'request-channels channels)
  (when priority (check-real 'request-channels :priority priority))
  (multiple-value-setq (time blend) (check-time-and-blend 'request-channels arbitrator time blend))
  (let ((priority (or priority (effective-priority arbitrator driver)))
        (channels (remove-duplicates (ensure-list channels) :test #'equal :from-end t))
        (notifications '()))
    (unless (finite-number-p priority)
      (arbitration-fail "the priority ~A of driver ~A is not a finite real number"
                        (argument-value-text priority) (argument-value-text driver)))
    (let ((record (driver-record arbitrator driver))
          (*requesting-driver* driver))
      (unless (driver-record-master record)
        (setf (driver-record-priority record) priority))
      (dolist (channel channels)
        (let* ((state (or (gethash channel (arbitrator-channels arbitrator))
                          (setf (gethash channel (arbitrator-channels arbitrator))
                                (make-channel-state))))
               (old-owner (channel-owner arbitrator channel))
               (request (and (member channel (driver-record-channels record) :test #'equal) ; short
                             (find driver (channel-state-requests state) :key #'channel-request-driver))))
          (if request
              (setf (channel-request-priority request) priority)
              (progn
                (setf (channel-state-requests state) ; in its place: sorting all made many quadratic
                      (merge 'list (list (make-channel-request driver priority (incf (arbitrator-serial arbitrator)) usurp))
                             (channel-state-requests state) #'request-better-p))
                (push channel (driver-record-channels record))))
          (setf notifications
                (nconc notifications
                       (settle-channel arbitrator channel state old-owner time blend :sort (and request t)))))))
    (notify arbitrator notifications)
    (remove-if-not (lambda (channel) (eq (channel-owner arbitrator channel) driver))
                   channels)))

(defun release-channels (arbitrator driver channels &key time blend)
  "Withdraw DRIVER's requests for CHANNELS (a list, or one channel).  Where DRIVER
owned a channel, the best waiting request gets it (ON-CHANNEL-GRANT), stamped
at TIME with BLEND seconds.  Channels DRIVER never requested are ignored."
  (check-arbitrator 'release-channels arbitrator)
  (check-driver 'release-channels driver)
  (check-channels 'release-channels channels)
  (multiple-value-setq (time blend) (check-time-and-blend 'release-channels arbitrator time blend))
  (let ((notifications '())
        (record (gethash driver (arbitrator-drivers arbitrator))))
    (when record
      (dolist (channel (ensure-list channels))
        (let ((state (gethash channel (arbitrator-channels arbitrator))))
          (when (and state (find driver (channel-state-requests state)
                                 :key #'channel-request-driver))
            (let ((old-owner (channel-owner arbitrator channel)))
              (setf (channel-state-requests state)
                    (delete driver (channel-state-requests state)
                            :key #'channel-request-driver)
                    (driver-record-channels record)
                    (delete channel (driver-record-channels record) :test #'equal))
              (setf notifications
                    (nconc notifications
                           (settle-channel arbitrator channel state old-owner time blend)))))))
      (forget-driver-if-idle arbitrator driver))
    (notify arbitrator notifications)
    (values)))

(defun release-driver (arbitrator driver &key time blend)
  "Release every channel of DRIVER and, first, of its slaves (recursively); detach
the slaves and detach DRIVER from its master.  Afterwards ARBITRATOR holds no
reference to DRIVER or its slaves."
  (check-arbitrator 'release-driver arbitrator)
  (check-driver 'release-driver driver)
  (multiple-value-setq (time blend) (check-time-and-blend 'release-driver arbitrator time blend))
  (dolist (slave (driver-slaves arbitrator driver))
    (release-driver arbitrator slave :time time :blend blend))
  (let ((master (driver-master arbitrator driver)))
    (when master
      (remove-slave arbitrator master driver)))
  (release-channels arbitrator driver (channels-of arbitrator driver) :time time :blend blend)
  (forget-driver-if-idle arbitrator driver)
  (values))

;;; ---------------------------------------------------------------------------
;;; Masters and slaves (Pantomime's BaseDriver::addSlave)

(defun add-slave (arbitrator master slave)
  "Make SLAVE a slave of MASTER: its requests without :priority use MASTER's, its
losses are reported to MASTER after itself, and RELEASE-DRIVER of MASTER
releases it.  A slave has one master; adding it to another moves it.  Signals
ARBITRATION-ERROR when MASTER is SLAVE or one of SLAVE's slaves."
  (check-arbitrator 'add-slave arbitrator)
  (check-driver 'add-slave master 'master)
  (check-driver 'add-slave slave 'slave)
  (when (or (eq master slave) (member slave (masters-of arbitrator master)))
    (arbitration-fail "driver ~A cannot be a slave of ~A: masters would form a cycle"
                      (argument-value-text slave) (argument-value-text master)))
  (let ((old (driver-master arbitrator slave)))
    (when old (remove-slave arbitrator old slave)))
  (setf (driver-record-master (driver-record arbitrator slave)) master)
  (push slave (driver-record-slaves (driver-record arbitrator master)))
  slave)

(defun remove-slave (arbitrator master slave)
  "Detach SLAVE from MASTER; SLAVE keeps its requests at their priorities."
  (let ((slave-record (gethash slave (arbitrator-drivers arbitrator)))
        (master-record (gethash master (arbitrator-drivers arbitrator))))
    (when (and slave-record (eq (driver-record-master slave-record) master))
      (setf (driver-record-master slave-record) nil)
      (forget-driver-if-idle arbitrator slave))
    (when master-record
      (setf (driver-record-slaves master-record)
            (delete slave (driver-record-slaves master-record)))
      (forget-driver-if-idle arbitrator master))
    (values)))
