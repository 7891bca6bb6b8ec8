;;;; recorder.lisp -- planning an event ahead.  A timed controller runs an
;;;; event's compiled closures at once, as the whole-event API does, but with
;;;; a RECORDER as presenter: every op, macro span, failure and state change
;;;; becomes an agenda item due at its time, and nothing reaches the real
;;;; presenter or the autoscripts until the timeline gets there.

(in-package #:player)

(defclass recorder (presenter)
  ((timeline :initarg :timeline :reader recorder-timeline)
   (run :initform nil :accessor recorder-run
        :documentation "The EVENT-RUN being planned.")
   (last-op :initform nil :accessor recorder-last-op
            :documentation "The :OP item recorded last, whose end delta comes next.")
   (last-macro-end :initform nil :accessor recorder-last-macro-end
                   :documentation "The :MACRO-END item recorded last, whose end delta comes next.")
   (open-macros :initform '() :accessor recorder-open-macros
                :documentation "The :MACRO-START items of the macros still running, innermost first."))
  (:documentation "The presenter of a controller while it plans an event ahead
(see RECORDER.LISP).  Durations come from the real presenter's PLANNED-OP-DURATION."))

(defun record-item (recorder kind time)
  "A new pending item of KIND at TIME for the run RECORDER is planning."
  (let* ((timeline (recorder-timeline recorder))
         (run (recorder-run recorder))
         (item (make-agenda-item kind (to-double time) (incf (timeline-seq timeline)) run)))
    (setf (agenda-item-step item) (controller-step (timeline-controller timeline)))
    (push item (run-items run))
    item))

(defmethod present-op ((recorder recorder) op start)
  (let* ((real (controller-presenter* (recorder-timeline recorder)))
         (duration (to-double (planned-op-duration real op start)))
         (item (record-item recorder :op start)))
    (setf (agenda-item-op item) op
          (agenda-item-start item) (to-double start)
          (agenda-item-end item) (+ (to-double start) duration)
          (recorder-last-op recorder) item)
    duration))

(defmethod present-macro-start ((recorder recorder) op start)
  (let ((item (record-item recorder :macro-start start)))
    (setf (agenda-item-op item) op (agenda-item-start item) (to-double start))
    (push item (recorder-open-macros recorder))))

(defmethod present-macro-end ((recorder recorder) op start end)
  (let ((opening (pop (recorder-open-macros recorder)))
        (item (record-item recorder :macro-end end)))
    (setf (agenda-item-op item) op (agenda-item-start item) (to-double start)
          (agenda-item-end item) (to-double end)
          (agenda-item-end opening) (to-double end)
          (agenda-item-owner opening) item
          (recorder-last-macro-end recorder) item)))

(defmethod present-failure ((recorder recorder) event goal time)
  (declare (ignore event))
  (setf (agenda-item-goal (record-item recorder :fail time)) goal))

(defmethod record-change ((recorder recorder) kind controller time a b op)
  (declare (ignore controller))
  (let ((item (record-item recorder kind time)))
    (setf (agenda-item-a item) a (agenda-item-b item) b)
    (let ((last-op (recorder-last-op recorder))
          (last-macro-end (recorder-last-macro-end recorder)))
      (cond ((null op))
            ((and last-op (eq op (agenda-item-op last-op)))
             (setf (agenda-item-owner item) last-op))
            ((and last-macro-end (eq op (agenda-item-op last-macro-end)))
             (setf (agenda-item-owner item) last-macro-end))))
    item))
