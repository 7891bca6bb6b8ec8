;;;; layers.lisp -- how drivers share a body beyond one owner per channel:
;;;; equals that blend, sets of channels taken and lost together, and idle
;;;; life, a layer under every op.  Pantomime's blending driver ("accepts the
;;;; outputs of two or more drivers as inputs") is here the body itself: the
;;;; owner of a channel and its requests of equal priority are averaged by
;;;; their :weight, unless one was made with :usurp.

(in-package #:player.body)

;;;# Equals blend

(defun channel-sharers (arbitrator channel)
  "The drivers CHANNEL's owner blends with in ARBITRATOR, the owner first: every
request at the owner's priority, when there are two or more and the owner did
not usurp; else NIL."
  (let* ((state (gethash channel (arbitrator-channels arbitrator)))
         (requests (and state (channel-state-requests state)))
         (owner (first requests)))
    (when (and owner (rest requests) (not (channel-request-usurp owner))
               (= (channel-request-priority owner) (channel-request-priority (second requests))))
      (loop for request in requests
            while (= (channel-request-priority request) (channel-request-priority owner))
            collect (channel-request-driver request)))))

(defun refresh-sharers (body time)
  "Re-read each channel's sharers; where they changed but the owner did not,
hold the angle the channel has now and crossfade over the body's blend time,
so a driver joining or leaving a blend never makes the channel jump."
  (let ((arbitrator (body-arbitrator body))
        (sharers (body-sharers body))
        (any nil))
    (dotimes (i (length sharers))
      (let ((now (channel-sharers arbitrator i)))
        (when now (setf any t))
        (unless (equal now (svref sharers i))
          (setf (body-sharing-stale-p body) t)
          (unless (= (aref (body-handovers body) i) time)
            ;; A new owner was stamped already by REFRESH-OWNERS.
            (setf (aref (body-held body) i) (aref (body-base body) i)
                  (aref (body-handovers body) i) (float time 1d0)
                  (aref (body-blends body) i) (float (body-blend-time body) 1d0))
            (note-instant-change body i time))
          (setf (svref sharers i) now))))
    (setf (body-shared-p body) any)))

(defun drive-owned (driver time pose)
  "DRIVER writes its angles for TIME into POSE, its writes on channels it
handed over with their set undone."
  (let ((released (driver-released driver)))
    (if (null released)
        (driver-drive driver time pose)
        (let ((saved (mapcar (lambda (i) (aref pose i)) released)))
          (driver-drive driver time pose)
          (loop for i in released for angle in saved do (setf (aref pose i) angle))))))

(defun sharers-channels (body)
  "A table from each driver among some channel's sharers in BODY to those
channels, so composing asks it rather than searching every channel's
sharers for every driver (which made many equals cubic); made again only
when the sharers changed."
  (let ((table (body-sharing body))
        (sharers (body-sharers body)))
    (when (body-sharing-stale-p body)
      (clrhash table)
      (dotimes (i (length sharers))
        (dolist (driver (svref sharers i))
          (push i (gethash driver table))))
      (setf (body-sharing-stale-p body) nil))
    table))

(defun drive-sharing (body time base)
  "Every non-additive driver of BODY writes into BASE in order; a shared
channel then takes its sharers' weighted mean."
  (let ((sums (body-share-sums body))
        (weights (body-share-weights body))
        (sharing (sharers-channels body)))
    (declare (type pose sums weights))
    (fill sums 0d0)
    (fill weights 0d0)
    (dolist (driver (body-active body))
      (unless (driver-additive-p driver)
        (drive-owned driver time base)
        (dolist (i (driver-channels driver))
          (when (member i (gethash driver sharing))
            (let ((weight (driver-weight driver)))
              (incf (aref sums i) (* weight (aref base i)))
              (incf (aref weights i) weight))))))
    (dotimes (i (length base))
      (when (plusp (aref weights i))
        (setf (aref base i) (/ (aref sums i) (aref weights i)))))))

;;;# Sets taken and lost together

(defun owns-or-shares-p (arbitrator driver channel)
  "Does DRIVER own CHANNEL, or blend on it with its owner?"
  (or (eq (channel-owner arbitrator channel) driver)
      (member driver (channel-sharers arbitrator channel))))

(defun take-channel-sets (body driver)
  "DRIVER has just started: a set of its channels granted only in part counts as lost."
  (let ((arbitrator (body-arbitrator body)))
    (dolist (set (driver-channel-sets driver))
      (let ((missing (remove-if (lambda (i) (owns-or-shares-p arbitrator driver i)) set)))
        (when missing
          (setf (driver-lost driver) (union missing (driver-lost driver))))))))

(defun lose-channel-sets (body time)
  "For each active driver told of a loss: where the lost channel belongs to one
of its sets, give up the set (:hand-over) or end (:end), at TIME.  A driver
left with no channel ends too."
  (dolist (driver (body-active body))
    (let ((lost (shiftf (driver-lost driver) '())))
      (when lost
        (let ((sets (remove-if-not (lambda (set) (intersection set lost)) (driver-channel-sets driver))))
          (cond ((null sets))
                ((eq (driver-arg driver :on-channel-loss) :end)
                 (finish-driver body driver time))
                (t
                 (let ((given (reduce #'union sets)))
                   (release-channels (body-arbitrator body) driver given :time time)
                   (setf (driver-released driver) (union given (driver-released driver)))
                   (unless (channels-of (body-arbitrator body) driver)
                     (finish-driver body driver time))))))))))

;;;# Idle life: a layer under every op

(defgeneric driver-yield-seconds (driver)
  (:documentation "Seconds an idle driver takes to come back on a channel an op let
go of; NIL (the default) for the body's blend time.")
  (:method ((driver driver))
    nil))

(defun idle-weight (body fade index time)
  "How much of an idle motion channel INDEX of BODY takes at TIME: none while
an op holds it (fading out over the op's crossfade), all once it has been
free for FADE seconds."
  (declare (type double-float fade time) (type fixnum index))
  (let ((handover (aref (the (simple-array double-float (*)) (body-handovers body)) index)))
    (cond ((svref (body-owners body) index)
           (let ((blend (aref (the (simple-array double-float (*)) (body-blends body)) index)))
             (if (<= blend 0d0) 0d0 (- 1d0 (min 1d0 (max 0d0 (/ (- time handover) blend)))))))
          ((or (<= fade 0d0) (null (svref (body-last-owners body) index))) 1d0)
          (t (min 1d0 (max 0d0 (/ (- time handover) fade)))))))

(defun drive-idle-layer (body driver time pose)
  "DRIVER (idle life) adds its motion to POSE, each channel scaled by its IDLE-WEIGHT."
  (declare (type pose pose))
  (let ((before (body-scratch body))
        (channels (driver-channels driver))
        (fade (float (or (driver-yield-seconds driver) (body-blend-time body)) 1d0))
        (time (float time 1d0)))
    (declare (type pose before))
    (dolist (i channels)
      (setf (aref before i) (aref pose i)))
    (driver-drive driver time pose)
    (dolist (i channels)
      (let ((angle (aref before i)))
        (unless (= angle (aref pose i))
          (setf (aref pose i) (+ angle (* (idle-weight body fade i time) (- (aref pose i) angle)))))))))
