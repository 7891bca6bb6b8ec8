;;;; settle.lisp -- the performance's side of settling (body/settling.lisp):
;;;; when a settling script is over, cut or not, the channels it drove ease
;;;; to the settled pose; when the settled pose changes (the controller's
;;;; state did), every channel at rest turns toward the new one.  The body's
;;;; place goes too: its rotation always settles (facing belongs to the pose),
;;;; its position to the pose's :position when the state's :pose-when gives
;;;; one, else to its resting place: where the last root motion (a :clip item
;;;; played with :root :move) carried it, or where it was placed.  A walk
;;;; moves the character for good; a hop or a crouch a script animates does
;;;; not.  Both are replayed, like the scripts, so scrubbing back gives the
;;;; same frames.

(in-package #:player.performance)

(defstruct (settle-target (:constructor make-settle-target (time angles position rotation)))
  "From TIME on, the first character's settled pose is ANGLES (a full pose),
at POSITION (a vec3, or NIL: its resting place, see RESTING-POSITION) turned
by ROTATION (a quat)."
  (time 0d0 :type double-float) angles position rotation)

(defparameter *settle-metres-as-degrees* 180d0
  "Degrees of joint travel a metre of the body's own travel counts as when
timing its settling: half a metre a second at *SETTLE-SPEED*.")

(defun performance-settle-to (performance angles position rotation time)
  "From TIME on, PERFORMANCE's first character settles to the pose ANGLES
\(a full pose of its skeleton), standing at POSITION (a vec3, or NIL for its
resting place: where root motion left it, else where it was placed) turned by
ROTATION (a quat).  Returns the SETTLE-TARGET."
  (check-argument 'performance-settle-to 'performance performance #'performance-p
                  "a performance (from make-performance)")
  (check-seconds 'performance-settle-to 'time time)
  (let ((target (make-settle-target (float time 1d0) (copy-seq angles) position rotation)))
    (setf (performance-settle-targets performance)
          (merge 'list (performance-settle-targets performance) (list target) #'< :key #'settle-target-time))
    ;; Not yet replayed: it waits in the replay's list; else the replay starts over.
    (if (and (performance-time performance) (< (settle-target-time target) (performance-time performance)))
        (setf (replay-stale performance) t)
        (setf (cdr (replay-settle-state performance))
              (merge 'list (cdr (replay-settle-state performance)) (list target) #'< :key #'settle-target-time)))
    target))

(defun initial-settle-target (performance)
  "The settled place at the start: where the starting pose puts the first
character (else its resting place), turned as it was placed."
  (let ((start (performance-starting-pose performance))
        (character (first (performance-characters performance))))
    (make-settle-target 0d0 nil (and start (pose-when-position (starting-pose-entry start)))
                        (character-spec-rotation character))))

(defun run-end-time (run)
  "When RUN is over: its stop, or the end of its one iteration; NIL for a loop not stopped."
  (let ((stop (script-run-stop run)))
    (if (script-run-loop run)
        stop
        (let ((end (+ (script-run-start run) (script-duration (script-run-script run)))))
          (if stop (min stop end) end)))))

(defun unsettled-run-p (run)
  "Does RUN settle when over, and has the replay not settled it yet?"
  (and (script-run-settles run) (not (script-run-settled run)) (run-end-time run)))

(defun next-settle-time (performance)
  "The time of the replay's next settling, or NIL: a settling run over, or a new settled pose."
  (let ((next (let ((target (second (replay-settle-state performance))))
                (and target (settle-target-time target)))))
    (dolist (run (replay-runs performance) next)
      (when (unsettled-run-p run)
        (let ((end (run-end-time run)))
          (when (or (null next) (< end next))
            (setf next end)))))))

(defun run-drivers (run)
  "Every driver RUN and the runs it started made in this replay, their slaves too."
  (append (mapcan (lambda (driver) (cons driver (copy-list (slave-drivers driver))))
                  (script-run-drivers run))
          (mapcan #'run-drivers (script-run-children run))))

(defun settle-due (performance time)
  "Do the settling due at TIME (the replay having come to it): settle the runs
over by then, then take up the settled poses due by then."
  (dolist (run (replay-runs performance))
    (when (and (unsettled-run-p run) (<= (run-end-time run) time))
      (setf (script-run-settled run) t)
      (let ((body (performance-body performance (script-run-body run))))
        (body-settle-channels body (remove body (run-drivers run) :key #'driver-body :test-not #'eq) time))))
  (loop for target = (second (replay-settle-state performance))
        while (and target (<= (settle-target-time target) time))
        do (pop (cdr (replay-settle-state performance)))
           (setf (car (replay-settle-state performance)) target)
           (body-settle-to (performance-body performance) (settle-target-angles target) time))
  (settle-place performance time))

(defun property-bound-p (performance object property time)
  "Does a binding of the replay drive OBJECT's PROPERTY after TIME?"
  (some (lambda (b) (and (eq (binding-object b) object) (string-equal (binding-property b) property)
                         (or (null (binding-end b)) (> (binding-end b) time))))
        (replay-bindings performance)))

(defun rotation-degrees (a b)
  "The angle in degrees between rotations A and B."
  (let ((dot (min 1d0 (abs (+ (* (quat-w a) (quat-w b)) (* (quat-x a) (quat-x b))
                              (* (quat-y a) (quat-y b)) (* (quat-z a) (quat-z b)))))))
    (* 2d0 (/ 180d0 pi) (acos dot))))

(defun settle-property (performance body property target travel time)
  "Ease BODY's PROPERTY from its value at TIME to TARGET, over the seconds
TRAVEL degrees take to settle, unless a script drives it or it is there."
  (when (and (> travel 1d-3) (not (property-bound-p performance body property time)))
    (let* ((seconds (settle-seconds travel))
           (control (make-keys-control (list (cons 0d0 (property-value body property))
                                             (cons seconds target))
                                       :interpolation :ease))
           (binding (make-binding body property control time (+ time seconds))))
      (setf (replay-bindings performance)
            (append (remove-if (lambda (b) (and (eq (binding-object b) body)
                                                (string-equal (binding-property b) property)))
                               (replay-bindings performance))
                    (list binding))))))

(defun root-motion-binding-p (binding body time)
  "Is BINDING a root motion (a :clip item's :root :move) carrying BODY, started by TIME?"
  (and (eq (binding-object binding) body)
       (typep (binding-control binding) 'root-motion-control)
       (<= (binding-start binding) time)))

(defun resting-position (performance body time)
  "Where BODY, the first character, rests at TIME when its settled pose gives
no position: where the latest root motion started by then carried it (at its
end, or at TIME if it goes on), else where the character was placed.  Each
root motion starts where the body stands, so the latest holds every walk's
travel."
  (let ((latest nil))
    (dolist (run (replay-runs performance))
      (dolist (binding (script-run-bindings run))
        (when (and (root-motion-binding-p binding body time)
                   (or (null latest) (>= (binding-start binding) (binding-start latest))))
          (setf latest binding))))
    (if latest
        (control-value (binding-control latest)
                       (- (min time (or (binding-end latest) time)) (binding-start latest)))
        (character-spec-position (first (performance-characters performance))))))

(defun settle-place (performance time)
  "Settle the first character's rotation, and its position (to the settled
pose's, else to its resting place), toward the settled pose in force at TIME."
  (let ((target (car (replay-settle-state performance))))
    (when target
      (let* ((body (performance-body performance))
             (position (or (settle-target-position target) (resting-position performance body time))))
        (settle-property performance body 'rotation (settle-target-rotation target)
                         (rotation-degrees (property-value body 'rotation) (settle-target-rotation target))
                         time)
        (settle-property performance body 'position position
                         (* *settle-metres-as-degrees* (vdistance (property-value body 'position) position))
                         time)))))

(defun performance-settled-time (performance time)
  "When PERFORMANCE, played to TIME, has come to rest: the latest of TIME, the
end of every settling on the way, every settling still due, and every binding
with an end; scripts that loop unstopped do not count."
  (check-argument 'performance-settled-time 'performance performance #'performance-p
                  "a performance (from make-performance)")
  (check-seconds 'performance-settled-time 'time time)
  (let ((end (float time 1d0)))
    ;; Each settling can start another (a script over after TIME): go on until none does.
    (loop repeat 100
          do (performance-frame performance end)
             (let ((next (max end
                              (or (next-settle-time performance) end)
                              (reduce #'max (scene-objects (performance-scene performance))
                                      :key (lambda (object) (if (typep object 'body) (body-settled-time object) 0d0))
                                      :initial-value 0d0)
                              (reduce #'max (replay-bindings performance)
                                      :key (lambda (b) (or (binding-end b) 0d0)) :initial-value 0d0))))
               (when (<= next end)
                 (return))
               (setf end next)))
    ;; A fresh replay again, as SIMULATE leaves it: a caller holding the
    ;; bodies of the scene and playing from 0 keeps them.
    (rebuild-scene performance)
    end))
