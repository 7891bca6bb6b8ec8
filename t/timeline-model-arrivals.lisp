;;;; timeline-model-arrivals.lisp -- the reference model of the timed
;;;; controller (timeline-model.lisp), part 3: an event arriving -- resolved
;;;; by its :when-busy policy against the runs its footprint meets, cuts at
;;;; the next interruption points -- and the start gate every run passes.

(in-package #:player-tests)

;;; Arrivals, cuts and the start gate

(defun tm-untried-p (context)
  "Does a running event meet everything (no op on a known channel)?  Then an
event arriving is not planned on trial: it meets every running one."
  (some (lambda (run) (member (car (tmr-footprint run)) '(:all nil))) (tmx-active context)))

(defun tm-finishing-ops (context footprint &optional (time (tmx-now context)))
  "The ops of interrupted (or finished) runs, begun by NOW and still playing
after TIME, whose run's footprint meets FOOTPRINT."
  (remove-if-not (lambda (op)
                   (let ((run (tmo-run op)))
                     (and (not (member run (tmx-active context)))
                          (<= (tmo-start op) (tmx-now context))
                          (> (tmo-effective-end op) time)
                          (tm-meet-p footprint (tmr-footprint run)))))
                 (tmx-ops context)))

(defun tm-gate (context name first-step time)
  "The start gate for event NAME's run from its top-level directive FIRST-STEP
at TIME: planned from the state due then, it starts then only if its plan's
footprint meets no active run and no op of an interrupted run still playing
after TIME; with only such ops in the way, TIME becomes the latest of their
ends and it is planned again.  Returns its start time, or NIL when an active
run is in its way (every plan meets an active run that meets everything)."
  (loop
    (when (tm-untried-p context)
      (return nil))
    ;; Every change due by TIME: a run leaving the queue when another ends
    ;; starts in the middle of an instant, before the changes due then that
    ;; come after that end are applied.
    (let* ((state (tm-state-at context time))
           (footprint (tm-plan context name first-step state)))
      (when (some (lambda (run) (tm-meet-p footprint (tmr-footprint run))) (tmx-active context))
        (return nil))
      (let ((finishing (tm-finishing-ops context footprint time)))
        (unless finishing
          (return time))
        (tm-count context :after-finishing)
        (setf time (reduce #'max finishing :key #'tmo-effective-end))))))

(defun tm-start-or-wait (context name time result)
  "Event NAME's run, arriving at TIME, starts when the start gate lets it, or
waits first in the queue (SEND-EVENT then answers T) when an active run is in
its way."
  (let ((start (tm-gate context name 0 time)))
    (cond (start (tm-start-run context name :event 0 start result))
          (t (unless (member result '(:none (t)) :test #'equal)
               (tm-fail "send-event of ~A at ~A (waiting at the start gate) returned ~S, not T"
                        name (float time 1d0) result))
             (tm-count context :gate-waits)
             (push (list name :event 0 :none) (tmx-queue context))))))

(defun tm-start-waiting (context time)
  "Start the waiting runs, first first, each at TIME or when the start gate
lets it (TM-GATE), until one finds an active run in its way."
  (loop for next = (first (tmx-queue context))
        while next
        do (destructuring-bind (name kind first-step result) next
             (let ((start (tm-gate context name first-step time)))
               (unless start
                 (return))
               (when (tmx-active context)
                 (tm-count context :queue-beside))
               (pop (tmx-queue context))
               (tm-start-run context name kind first-step start result)))))

(defun tm-stop-time (context line time)
  "When op LINE, running at TIME, stops: its next interruption point."
  (let ((interrupt (gethash (tmo-name line) (tms-interrupts (tmx-spec context))))
        (start (tmo-start line))
        (end (tmo-effective-end line)))
    (cond ((eq interrupt :never) end)
          ((eq interrupt :anytime) time)
          (t (or (loop for point in interrupt
                       for at = (+ start point)
                       when (<= time at end) return at)
                 end)))))

(defun tm-first-directive-with-work (context run)
  "The first of RUN's directives from its position that would do anything from
the state at its schedule (an op, or a failure), or NIL."
  (let ((state (tm-run-state context run)))
    (loop for position from (tmr-pos run) below (length (tmr-directives run))
          for directive = (nth position (tmr-directives run))
          unless (and (eq (first directive) :state)
                      (eql 0 (tm-distance context (second directive) state)))
            return position)))

(defun tm-cut (context run time by footprint)
  "Event BY (of FOOTPRINT) cuts RUN at TIME.  Returns (VALUES START RESUME):
when BY can start as far as RUN and the runs cut before it are concerned, and
the directive RUN would resume from (NIL: nothing left of it)."
  (let* ((live (remove-if-not (lambda (op) (and (<= (tmo-start op) time) (> (tmo-effective-end op) time)))
                              (tmx-ops context)))
         (own (remove-if-not (lambda (op) (eq (tmo-run op) run)) live))
         ;; Ops of runs over (cut) that meet BY still finishing.
         (others (remove-if (lambda (op)
                              (let ((other (tmo-run op)))
                                (or (eq other run) (member other (tmx-active context))
                                    (not (tm-meet-p footprint (tmr-footprint other))))))
                            live))
         (start time)
         (shown '())
         (finishing nil)
         (macro-cut nil)
         (resume nil))
    (when (rest own)
      (tm-fail "~A ~A has ~D ops running at ~A" (tmr-kind run) (tmr-name run) (length own) (float time 1d0)))
    (dolist (op others) (setf start (max start (tmo-effective-end op))))
    (let ((op (first own)))
      (when op
        (let ((stop (tm-stop-time context op time)))
          (setf start (max start stop))
          (if (< stop (tmo-effective-end op))
              (let ((cut-effects (gethash (tmo-name op) (tms-cut-effects (tmx-spec context)))))
                (tm-count context :cut-short)
                (setf (tmo-effective-end op) stop
                      (tmo-cut op) t
                      resume (tmo-directive op)
                      macro-cut (tmo-macro op))
                (when cut-effects
                  (tm-count context :if-cut)
                  (when (= stop time) (tm-count context :if-cut-at-the-send-time))
                  ;; Made by the cut, not by RUN's plan: no run to cancel it with.
                  (tm-add-change context stop cut-effects nil op (* (tm-new-block context) +tm-block+)))
                (push op shown))
              (setf finishing op
                    macro-cut (and (tmo-macro op)
                                   (or (tmr-macro run) (not *tm-macro-completes-on-its-last-sub-op*))
                                   (tmo-macro op)))))))
    ;; Nothing of RUN due after TIME happens, but the finishing op's end.
    (setf (tmx-changes context)
          (remove-if (lambda (change)
                       (and (eq (tmc-run change) run) (> (tmc-time change) time)
                            (not (and finishing (eq (tmc-op change) finishing)
                                      (or (not (tmc-macro-end change)) (not macro-cut))))))
                     (tmx-changes context)))
    (when macro-cut
      (tm-count context :macro-cuts)
      (setf (tmo-expected-end macro-cut) start
            (tmo-effective-end macro-cut) start))
    (unless resume
      (setf resume (cond (macro-cut (tmo-directive macro-cut))
                         ((plusp (tmr-remaining run)) (tmr-pos run))
                         (t (tm-first-directive-with-work context run)))))
    (setf (tmr-cut run) t (tmr-macro run) nil
          ;; RUN is over when its own op is (not when BY may start: that
          ;; waits for earlier runs' ops too).
          (tmr-end run) (reduce #'max own :key #'tmo-effective-end :initial-value time)
          (tmx-active context) (remove run (tmx-active context)))
    (if shown
        (dolist (op shown)
          (tm-expect context (list :cut (tmo-name op) :time (tmo-effective-end op) :by by
                                   :end (tmo-effective-end op))
                     (format nil "~A cutting op ~A of ~A at ~A" by (tmo-name op) (tmr-name run) (float time 1d0))))
        (tm-expect context (if finishing
                               (list :cut (tmo-name finishing) :time start :by by :end start)
                               (list :cut nil :time start :by by))
                   (format nil "~A cutting ~A at ~A (no op stopped short)" by (tmr-name run) (float time 1d0))))
    (values start resume)))

(defun tm-clash (context a b)
  "What footprints A and B, which meet, share: :ALL when either has no known
channel, else their common channels; then the names of their common
variables, unless either plays an op on no known channel (a set: TM-SAME-LINE-P compares lists as sets)."
  (let ((variables (model-variables (tmx-model context))))
    (append (if (or (member (car a) '(:all nil)) (member (car b) '(:all nil)))
                (list :all)
                (intersection (car a) (car b) :test #'string=))
            ;; The controller works out no variables for a plan with an op
            ;; on no known channel: it meets everything anyway.
            (unless (or (eq (car a) :all) (eq (car b) :all))
              (mapcar (lambda (index) (mvar-name (svref variables index)))
                      (intersection (cdr a) (cdr b)))))))

(defun tm-dispatch (context name time given-policy result source)
  "Event NAME arrives at TIME from SOURCE (:USER, :TIMER or :TRIGGER) with
:when-busy GIVEN-POLICY (or none); RESULT is what SEND-EVENT returned (:NONE
when no one asked)."
  (let* ((spec (tmx-spec context))
         (policy (or given-policy
                     (gethash name (tms-event-policies spec))
                     (tms-default-policy spec)
                     :queue))
         ;; Its trial plan, from the state now (none when a running event
         ;; meets everything anyway): what it would do if it started now.
         (untried (tm-untried-p context))
         (trial (and (tmx-active context) (not untried)
                     (tm-plan context name 0 (tmx-state context))))
         (footprint (or trial '(:all)))
         (met (if untried
                  (tmx-active context)
                  (remove-if-not (lambda (run) (tm-meet-p footprint (tmr-footprint run))) (tmx-active context)))))
    ;; Timers it restarts.
    (dolist (timer (tmx-timers context))
      (let ((restart-on (tmt-restart-on (tmts-timer timer))))
        (when (if (eq restart-on :any) (eq source :user) (member name restart-on))
          (tm-count context :timer-restarts)
          (tm-arm-timer context timer time))))
    (cond ((null (tmx-active context))
           (tm-count context :idle)
           (tm-start-or-wait context name time result))
          ((null met)
           (tm-count context :parallel)
           (tm-start-or-wait context name time result))
          (t
           (when (eq source :user) (tm-count context :busy))
           (tm-count context policy)
           (ecase policy
             (:queue
              (unless (member result '(:none (t)) :test #'equal)
                (tm-fail "send-event of ~A at ~A (queued) returned ~S, not T" name (float time 1d0) result))
              (tm-expect context (list :queued name :time time
                                       :behind (if (tmx-queue context)
                                                   (first (first (last (tmx-queue context))))
                                                   (tmr-name (first met))))
                         (format nil "~A sent at ~A while ~A runs, :queue" name (float time 1d0) (tmr-name (first met))))
              (setf (tmx-queue context) (append (tmx-queue context) (list (list name :event 0 :none)))))
             (:override
              (unless (member result '(:none (nil :dropped)) :test #'equal)
                (tm-fail "send-event of ~A at ~A (dropped) returned ~S, not NIL :DROPPED" name (float time 1d0) result))
              (tm-expect context (list :dropped name :time time :busy-with (tmr-name (first met))
                                       :clash (tm-clash context footprint (tmr-footprint (first met))))
                         (format nil "~A sent at ~A while ~A runs, :override" name (float time 1d0) (tmr-name (first met)))))
             ((:preempt :interleave)
              (when (rest met) (tm-count context :multi-cuts))
              (let ((start time) (resumptions '()))
                (dolist (run met)
                  (multiple-value-bind (at resume) (tm-cut context run time name footprint)
                    (setf start (max start at))
                    (when (and (eq policy :interleave) resume)
                      (push (list (tmr-name run) :resume resume :none) resumptions))))
                ;; What falls due now happens before the newcomer plans (the
                ;; events timers and triggers send then wait for the
                ;; dispatching that is under way).
                (tm-advance context time :dispatch nil)
                (setf (tmx-queue context) (append (nreverse resumptions) (tmx-queue context)))
                ;; Its plan from the state the cuts leave passes the start
                ;; gate: it may wait, first, ahead of the runs it interrupted.
                (tm-start-or-wait context name start result))))))))

(defun tm-send (context name time given-policy result)
  "Event NAME sent at TIME with :when-busy GIVEN-POLICY (or none); RESULT is
what SEND-EVENT returned."
  (tm-advance context time)
  (tm-count context :sends)
  (tm-dispatch context name time given-policy result :user))
