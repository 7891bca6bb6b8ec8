;;;; footprints.lisp -- what a planned event touches: the body channels of the
;;;; ops it will play and the variables their preconditions and effects (and
;;;; its own assignments) mention.  The plan is known before anything plays,
;;;; so the footprint is exact for the state the event starts from.  Two
;;;; events whose footprints are disjoint cannot disturb each other, so a
;;;; timed controller plays them side by side instead of applying a :when-busy
;;;; policy: Peedy turns his head to a voice while he flies his lap.

(in-package #:player.control)

(defstruct (footprint (:constructor make-footprint (channels fields runtime)))
  "CHANNELS: lower-case strings, or :ALL; FIELDS: the plannable variables' one-hot
fields, as a mask; RUNTIME: the runtime variables."
  (channels '() :type (or list (eql :all)))
  (fields 0 :type integer)
  (runtime '() :type list))

(defvar *everything-footprint* (make-footprint :all 0 '())
  "The footprint of an event that meets every other (some op of it on no known
channel): its variables never matter, so one footprint serves them all.")

;; Inline: it runs for every event a timed controller plays.
(declaim (inline meets-everything-p))
(defun meets-everything-p (footprint)
  "Does FOOTPRINT meet every other, whatever it is (no known channels)?"
  (member (footprint-channels footprint) '(:all nil)))

(defun footprints-meet-p (a b)
  "Do footprints A and B share a channel or a variable?  An event with no op
on a known channel (its channels :ALL, or none) meets every other: only two
events that both play on known, disjoint channels run side by side."
  (or (meets-everything-p a) (meets-everything-p b)
      (intersection (footprint-channels a) (footprint-channels b) :test #'string=)
      (logtest (footprint-fields a) (footprint-fields b))
      (intersection (footprint-runtime a) (footprint-runtime b))))

(defun op-footprint (timeline op)
  "(CHANNELS . FIELDS) of OP on TIMELINE: its channels as the presenter knows
them and the fields its precondition and effects mention (worked out once)."
  (let ((table (timeline-op-footprints timeline)))
    (or (gethash op table)
        (setf (gethash op table)
              (cons (op-channel-set (timeline-presenter timeline) op)
                    (op-variable-fields op (spec-of (timeline-controller timeline))))))))

(defun channel-union (a b)
  "Channel sets A and B together (:ALL when either is)."
  (cond ((or (eq a :all) (eq b :all)) :all)
        ((null a) b)
        ((null b) a)
        (t (union a b :test #'string=))))

(defun run-footprint-from-items (timeline run)
  "The footprint of RUN as planned: the channels and variables of the ops its
items play, and the variables its changes set."
  (let ((channels '()) (fields 0) (runtime '()))
    (dolist (item (run-items run))
      (case (agenda-item-kind item)
        (:op (when (and (timeline-declared-channels timeline) (null (op-channels (agenda-item-op item))))
               ;; On every channel, as OP-FOOTPRINT would say (below).
               (return-from run-footprint-from-items *everything-footprint*))
             (let ((footprint (op-footprint timeline (agenda-item-op item))))
               ;; One op on every channel: the run meets everything, whatever
               ;; its variables (FOOTPRINTS-MEET-P never looks at them).
               (when (eq (car footprint) :all)
                 (return-from run-footprint-from-items *everything-footprint*))
               (setf channels (channel-union channels (car footprint))
                     fields (logior fields (cdr footprint)))))
        (:macro-start (setf fields (logior fields (cdr (op-footprint timeline (agenda-item-op item))))))
        (:delta (setf fields (logior fields (agenda-item-a item))))
        (:value (pushnew (agenda-item-a item) runtime))))
    (make-footprint channels fields runtime)))

;; Inline: it runs for every event a timed controller plays.
(declaim (inline compiled-event-runs-code-p))
(defun compiled-event-runs-code-p (compiled)
  "EVENT-RUNS-CODE-P of the event COMPILED, worked out once per compiled event."
  (let ((known (compiled-event-runs-code compiled)))
    (if (eq known :unknown)
        (setf (compiled-event-runs-code compiled)
              (and (event-runs-code-p (compiled-event-event compiled)) t))
        known)))

;;;# What two events met on

(defun footprint-clash (a b spec)
  "What footprints A and B, which meet, have in common, for the :CLASH of a
trace line: :ALL when either plays an op on no known channel (it may use any)
or none at all, else the channels both use (strings, sorted); then the
variables both mention (symbols), the plannable ones in SPEC's order, then the
runtime ones by slot -- none when either plays an op on no known channel: its
variables are not worked out (*EVERYTHING-FOOTPRINT*)."
  (append (if (or (meets-everything-p a) (meets-everything-p b))
              (list :all)
              (sort (copy-list (intersection (footprint-channels a) (footprint-channels b) :test #'string=))
                    #'string<))
          (let ((shared (logand (footprint-fields a) (footprint-fields b))))
            (loop for var in (plannable-variables spec)
                  when (logtest shared (var-field-mask var)) collect (var-name var)))
          (mapcar #'var-name (sort (copy-list (intersection (footprint-runtime a) (footprint-runtime b)))
                                   #'< :key #'var-slot))))
