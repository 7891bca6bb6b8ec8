;;;; replay.lisp -- a performance played to a time: the scene rebuilt at the
;;;; start, each run expanded into cues (its items at their times), cues played
;;;; in order up to the time asked for, property bindings kept, and the frame
;;;; that follows.  Asked for an earlier time, the replay starts over, so the
;;;; same time always gives the same frame (performance.lisp says why).

(in-package #:player.performance)

(defparameter *stage-name* '%stage
  "The name of the group object a performance with an origin hangs its scene from.")

(defun performance-stage (performance)
  "The group object PERFORMANCE's scene hangs from (see PERFORMANCE-ORIGIN), or NIL."
  (and (performance-origin performance)
       (find-object (performance-scene performance) *stage-name* nil)))

(defun rebuild-scene (performance)
  "Start the replay over: a fresh scene at its initial state, every run unplayed."
  (let* ((scene (make-instance 'scene))
         (library (performance-library performance))
         (stage (and (performance-origin performance)
                     (add-object scene (make-instance 'scene-object :name *stage-name* :kind :group
                                                                    :position (performance-origin performance))))))
    (dolist (spec (performance-characters performance))
      (let ((body (make-body (character-spec-name spec) (character-spec-skeleton spec)
                             :scene scene :position (character-spec-position spec)
                             :rotation (character-spec-rotation spec)
                             :blend-time (performance-blend-time performance))))
        (setf (object-parent body) stage)
        (setf (body-seed body) (performance-seed performance))
        (unless (character-spec-visible spec)
          (setf (property-value body 'visible) nil))
        (when (performance-poses performance)
          (setf (body-pose-library body) (performance-poses performance)))))
    (setf (performance-scene performance) scene)
    (start-performance-pose performance)
    (start-performance-idle-life performance)
    (dolist (spec (script-library-objects library))
      (let ((object (apply #'make-instance
                           (if (scene-object-spec-prop-model spec) 'model-prop 'scene-object)
                           :name (scene-object-spec-name spec)
                           :kind (scene-object-spec-kind spec)
                           :position (scene-object-spec-position spec)
                           :rotation (scene-object-spec-rotation spec)
                           (and (scene-object-spec-prop-model spec)
                                (list :prop-model (scene-object-spec-prop-model spec))))))
        (loop for (name type value) in (scene-object-spec-properties spec)
              do (define-property object name type value))
        (setf (object-parent object) stage)
        (add-object scene object)))
    (setf (performance-scene performance) scene)
    (dolist (spec (script-library-objects library))
      (when (scene-object-spec-parent spec)
        (setf (object-parent (find-object scene (scene-object-spec-name spec)))
              (resolve-parent performance (scene-object-spec-parent spec) nil))))
    (dolist (run (performance-runs performance))
      (reset-run run))
    (setf (replay-settle-state performance) (cons (initial-settle-target performance)
                                                  (performance-settle-targets performance)))
    (setf (replay-runs performance) (reverse (performance-runs performance))
          (replay-cues performance) '()
          (replay-bindings performance) '()
          (replay-clips performance) '()
          (performance-time performance) nil
          (replay-stale performance) nil)))

(defun reset-run (run)
  "Forget what an earlier replay made of RUN."
  (setf (script-run-iterations run) 0
        (script-run-next-begin run) nil
        (script-run-settled run) nil
        (script-run-drivers run) '()
        (script-run-bindings run) '()
        (script-run-children run) '()
        (script-run-clips run) '()))

(defun resolve-parent (performance parent body-name)
  "The scene parent PARENT (NIL, an object's name or (OBJECT JOINT-OR-ROLE)) names,
:SELF being the body BODY-NAME."
  (let ((scene (performance-scene performance)))
    (flet ((object (name)
             (find-object scene (if (eq name :self) (or body-name (performance-character performance)) name))))
      (cond ((null parent) (performance-stage performance))
            ((symbolp parent) (object parent))
            (t (let ((object (object (first parent))))
                 (cons object (joint-name-for object (second parent) parent))))))))

(defun joint-name-for (object joint-or-role form)
  "The name of OBJECT's joint JOINT-OR-ROLE (a role keyword gives its joint, or a
chain's last joint)."
  (unless (typep object 'body)
    (anim-fail 'anim-error form "~A is not a body, so nothing can hang from its joints"
               (lisp-text (object-name object))))
  (let ((joint (if (keywordp joint-or-role)
                   (skeleton-role (body-skeleton object) joint-or-role)
                   (find-joint (body-skeleton object) joint-or-role))))
    (when (consp joint) (setf joint (car (last joint))))
    (unless joint
      (anim-fail 'anim-error form "body ~A has no joint or role ~A" (lisp-text (object-name object))
                 (lisp-text joint-or-role)))
    (body-joint-name joint)))

(defun expand-runs (performance time)
  "Turn into cues every iteration of every run that starts by TIME."
  (dolist (run (replay-runs performance))
    (expand-run performance run time)))

(defun expand-run (performance run time)
  "Add RUN's cues for its iterations starting at or before TIME (and before
its stop).  A looping script of :beats takes each iteration at the tempo of
its start (RUN-ITERATION-SCRIPT, tempo.lisp)."
  (loop for k = (script-run-iterations run)
        for begin = (or (script-run-next-begin run) (script-run-start run))
        for iteration = (run-iteration-script performance run begin)
        for duration = (script-duration iteration)
        while (and (<= begin time)
                   (or (zerop k) (and (script-run-loop run) (plusp duration)))
                   (or (null (script-run-stop run)) (< begin (script-run-stop run))))
        do (incf (script-run-iterations run))
           (setf (script-run-next-begin run) (+ begin duration))
           ;; Items due at the same time play in the order they are written.
           (setf (replay-cues performance)
                 (merge 'list (replay-cues performance)
                        (stable-sort (loop for item in (script-items iteration)
                                           collect (make-cue (+ begin (script-item-at item)) item
                                                             run (+ begin duration)))
                                     #'< :key #'cue-time)
                        #'< :key #'cue-time))))

(defun item-end (cue)
  "When CUE's item ends: its :for, its iteration's end, its run's stop, whichever
is first.  Speech and sounds are not cut by the iteration's end: NIL when
nothing else cuts them."
  (let* ((item (cue-item cue))
         (run (cue-run cue))
         (ends (remove nil (list (and (script-item-until item)
                                      (+ (cue-time cue) (script-item-until item)))
                                 (and (not (typep item '(or say-item sound-item)))
                                      (cue-iteration-end cue))
                                 (script-run-stop run)))))
    (and ends (reduce #'min ends))))

(defun bring-to (performance time)
  "Set every bound property and evaluate every body for TIME."
  (let ((scene (performance-scene performance)))
    (setf (replay-bindings performance)
          (loop for binding in (replay-bindings performance)
                for end = (binding-end binding)
                for at = (if (and end (< end time)) end time)
                do (setf (property-value (binding-object binding) (binding-property binding))
                         (let ((control (binding-control binding)))
                           (if (control-p control)
                               (control-value control (- at (binding-start binding)))
                               control)))
                unless (and end (<= end time)) collect binding))
    (dolist (object (scene-objects scene))
      (when (typep object 'body)
        (body-evaluate object time)))
    ;; Dynamic props fall and collide (src/physics/), after what placed the rest.
    (advance-scene-physics scene time)
    (setf (performance-time performance) time)))

(defun play-cue (performance cue)
  "Carry out CUE's item at its time."
  (let* ((item (cue-item cue))
         (run (cue-run cue))
         (time (cue-time cue))
         (end (item-end cue))
         (body-name (script-run-body run)))
    (flet ((object (name)
             (find-object (performance-scene performance) (if (eq name :self) body-name name))))
      (etypecase item
        (motor-item
         (let* ((body (performance-body performance body-name))
                (driver (make-driver (motor-item-call item) body time :stop end)))
           (push driver (script-run-drivers run))
           (body-add-driver body driver)
           ;; A clip played with :root :move carries the body: its position is
           ;; bound, for the item's span, to the clip's travel from here.
           (when (moves-root-p driver)
             (add-binding performance run body 'position
                          (make-root-motion-control driver (property-value body 'position)
                                                    (property-value body 'rotation))
                          time end))))
        (animate-item
         (add-binding performance run (object (animate-item-object item)) (animate-item-property item)
                      (animate-item-control item) time end))
        (set-item
         (add-binding performance run (object (set-item-object item)) (set-item-property item)
                      (set-item-value item) time time))
        (play-item
         (let* ((script (find-script (performance-library performance) (play-item-script item) t))
                (child (make-script-run script time end body-name (script-loop script))))
           (push child (script-run-children run))
           (setf (replay-runs performance) (append (replay-runs performance) (list child)))
           (expand-run performance child time)))
        ((or say-item sound-item)
         (play-audio-item performance item run time end body-name))
        (attach-item
         (reparent-object (object (attach-item-object item))
                          (resolve-parent performance (attach-item-parent item) body-name)
                          :keep-world (attach-item-keep-world item)))))))

(defun add-binding (performance run object property control start end)
  "Bind CONTROL (or a constant) to OBJECT's PROPERTY from START to END; the
newest binding of a property replaces the older ones."
  (let ((binding (make-binding object property control start end)))
    (setf (replay-bindings performance)
          (append (remove-if (lambda (b) (and (eq (binding-object b) object)
                                              (string-equal (binding-property b) property)))
                             (replay-bindings performance))
                  (list binding)))
    (push binding (script-run-bindings run))
    (bring-to performance start)))

(defun performance-frame (performance time)
  "PERFORMANCE's scene at TIME (seconds): every run's cues due by then played in
order, every body evaluated.  An earlier TIME than the last replays from the
start.  Returns the scene (PERFORMANCE-SCENE; its objects change with the next call)."
  (check-argument 'performance-frame 'performance performance #'performance-p "a performance (from make-performance)")
  (check-seconds 'performance-frame 'time time)
  (let ((time (float time 1d0)))
    (when (or (replay-stale performance)
              (and (performance-time performance) (< time (performance-time performance))))
      (rebuild-scene performance))
    ;; The time the scene was last brought to when only motor items have
    ;; played since: they only schedule drivers, so the next motor cue at that
    ;; time finds the scene as it was, and the drivers start together at the
    ;; next evaluation (in order), rather than each cue evaluating every body
    ;; again (which made a script starting many drivers at once quadratic).
    ;; Any other item sees them started.
    (let ((brought nil))
      (loop
        (expand-runs performance time)
        (let ((cue (first (replay-cues performance)))
              (settle-time (next-settle-time performance)))
          (cond ((and settle-time (<= settle-time time)
                      (or (null cue) (< settle-time (cue-time cue))))
                 ;; A script over, or a new settled pose, before the next cue (cues at
                 ;; the same instant first: a channel a new script takes then never settles).
                 (bring-to performance settle-time)
                 (settle-due performance settle-time)
                 (setf brought nil))
                ((not (and cue (<= (cue-time cue) time)))
                 (return))
                (t
                 (pop (replay-cues performance))
                 (when (or (null (script-run-stop (cue-run cue)))
                           (< (cue-time cue) (script-run-stop (cue-run cue))))
                   (unless (and (eql brought (cue-time cue)) (typep (cue-item cue) 'motor-item))
                     (bring-to performance (cue-time cue)))
                   (play-cue performance cue)
                   (setf brought (and (typep (cue-item cue) 'motor-item) (cue-time cue)))))))))
    (bring-to performance time)
    (check-property-reactions performance time)
    (setf (scene-caption (performance-scene performance)) (caption-at performance time))
    (performance-scene performance)))
