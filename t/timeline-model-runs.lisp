;;;; timeline-model-runs.lisp -- the reference model of the timed controller
;;;; (timeline-model.lisp), part 2: a run taking its op lines from the trace
;;;; as it plays, and the model's clock: what falls due (op ends, state
;;;; changes, timers and triggers going off) in time order.

(in-package #:player-tests)

;;; Runs

(defun tm-start-run (context name kind first-step time result)
  "Start NAME's run (KIND :EVENT or :RESUME, from directive FIRST-STEP) at TIME."
  (let* ((index (tm-expect context (list kind name :time time)
                           (format nil "~(~A~) ~A starting at ~A" kind name (float time 1d0))))
         (event (find name (model-events (tmx-model context)) :key #'mevent-name))
         ;; It plans from the state due then (TM-GATE's).
         (base (tm-state-at context time))
         (run (multiple-value-bind (footprint names) (tm-plan context name first-step base)
                (make-tm-run :name name :kind kind :start time :at time
                             :directives (mevent-directives event)
                             :pos first-step
                             :line index :base base :plan-names names
                             :result result
                             :block (tm-new-block context)
                             :footprint footprint))))
    (setf (tmr-next-key run) (tm-fresh-key run))
    (when (tmx-active context)
      (tm-count context :beside))
    (push run (tmx-runs context))
    (setf (tmx-active context) (append (tmx-active context) (list run)))
    (when (eq kind :resume) (tm-count context :resumed))
    run))

(defun tm-run-state (context run)
  "The state RUN plans its next step in: the one it started from with its own
changes so far (the controller plans an event ahead when it starts; the events
playing beside it touch none of its variables)."
  (let ((state (copy-seq (tmr-base run))))
    (dolist (change (sort (remove-if-not (lambda (change)
                                           (and (eq (tmc-run change) run) (<= (tmc-time change) (tmr-at run))))
                                         (copy-list (tmx-changes context)))
                          (lambda (a b) (tm-key< (tmc-time a) (tmc-key a) (tmc-time b) (tmc-key b)))))
      (loop for (i . k) in (tmc-data change) do (setf (svref state i) k)))
    state))

(defun tm-step (context run)
  "Play RUN's next thing at its schedule: begin its directives due then until
it consumes an op line, or is complete."
  (loop
    (when (or (tmr-complete run) (tmr-cut run))
      (return))
    (cond ((tmr-macro run) (tm-consume-sub-op context run) (return))
          ((plusp (tmr-remaining run)) (tm-consume-op context run) (return))
          ((>= (tmr-pos run) (length (tmr-directives run)))
           (setf (tmr-complete run) t (tmr-end run) (tmr-at run)))
          (t (tm-begin-directive context run)))))

(defun tm-begin-directive (context run)
  "Work out how many ops RUN's next directive takes, from the state at its start."
  (let* ((directive (nth (tmr-pos run) (tmr-directives run)))
         (state (tm-run-state context run))
         (distance (tm-distance context (tm-directive-goal context directive) state)))
    (cond ((null distance)
           (setf (tmr-failed run) t
                 (tmr-fail-goal run) (tm-directive-goal-form context directive)
                 (tmr-complete run) t
                 (tmr-end run) (tmr-at run)))
          ((eq (first directive) :op) (setf (tmr-remaining run) (1+ distance)))
          ((zerop distance) (incf (tmr-pos run)))
          (t (setf (tmr-remaining run) distance)))))

(defun tm-next-line (context run what)
  "RUN's next op line, which the model expects to be WHAT: the first op line
after RUN's :event or :resume line that no run has taken and that RUN's plan
plays (the ops of runs playing side by side are disjoint)."
  (or (let ((line (find-if (lambda (line)
                             (and (not (tmo-claimed line)) (> (tmo-index line) (tmr-line run))
                                  (member (tmo-name line) (tmr-plan-names run))))
                           (tmx-op-lines context))))
        (when line
          (setf (tmo-claimed line) t)
          line))
      (tm-fail "~A ~A (from ~A): the model expects ~A at ~A, but the trace shows no more ops of it"
               (tmr-kind run) (tmr-name run) (float (tmr-start run) 1d0) what (float (tmr-at run) 1d0))))

(defun tm-check-op-line (run line duration)
  "LINE must start at RUN's schedule and last DURATION."
  (unless (= (tmo-start line) (tmr-at run))
    (tm-fail "~A ~A: op ~A (line ~D) starts at ~A; the previous one ended at ~A"
             (tmr-kind run) (tmr-name run) (tmo-name line) (tmo-index line)
             (float (tmo-start line) 1d0) (float (tmr-at run) 1d0)))
  (unless (or (eq (mop-kind (tmo-mop line)) :macro) (= (tmo-end line) (+ (tmo-start line) duration)))
    (tm-fail "op ~A (line ~D) is shown ending at ~A; it starts at ~A and lasts ~A"
             (tmo-name line) (tmo-index line) (float (tmo-end line) 1d0) (float (tmo-start line) 1d0)
             (float duration 1d0)))
  (setf (tmo-run line) run
        (tmo-directive line) (tmr-pos run)
        (tmo-effective-end line) (+ (tmr-at run) duration)))

(defun tm-consume-op (context run)
  "RUN's next plan op (or the requested op of an (:op X) directive)."
  (let* ((line (tm-next-line context run "a plan op"))
         (model (tmx-model context))
         (op (tmo-mop line))
         (directive (nth (tmr-pos run) (tmr-directives run)))
         (requested (and (eq (first directive) :op) (= 1 (tmr-remaining run))))
         (state (tm-run-state context run))
         (real (tm-state-at context (tmr-at run)))
         (duration (tm-op-duration (tmx-spec context) op)))
    (tm-check-op-line run line duration)
    (cond ((and requested (not (eq (tmo-name line) (second directive))))
           (tm-fail "~A ~A: op ~A (line ~D) where the requested op ~A should run"
                    (tmr-kind run) (tmr-name run) (tmo-name line) (tmo-index line) (second directive)))
          ((and (not requested) (not (member op (model-plan-operators model))))
           (tm-fail "~A ~A: op ~A (line ~D) is must-ask, yet inside a plan"
                    (tmr-kind run) (tmr-name run) (tmo-name line) (tmo-index line))))
    (unless (and (model-op-applicable-p op state) (model-op-applicable-p op real))
      (tm-fail "op ~A (line ~D) starts at ~A, but its precondition is false in the state then, ~A (as planned: ~A)"
               (tmo-name line) (tmo-index line) (float (tmo-start line) 1d0) (tm-state-text context real)
               (tm-state-text context state)))
    (tm-count context :ops)
    (if (eq (mop-kind op) :macro)
        (progn (push line (tmx-macros context))
               (setf (tmr-macro run) line
                     (tmr-macro-before run) state
                     (tmr-macro-seq run) (mop-seq op)
                     (tmr-next-key run) (tm-fresh-key run)))
        (progn (push line (tmx-ops context))
               (tm-add-change context (+ (tmr-at run) duration) (mop-effects op) run line (tm-fresh-key run))
               (incf (tmr-at run) duration)
               (setf (tmr-next-key run) (tm-fresh-key run))
               (tm-op-done context run)))))

(defun tm-consume-sub-op (context run)
  "The next sub-op of RUN's macro under way; after its last, the macro's end."
  (let* ((name (first (tmr-macro-seq run)))
         (line (tm-next-line context run (format nil "sub-op ~A of macro ~A" name (tmo-name (tmr-macro run)))))
         (op (tmo-mop line))
         (duration (tm-op-duration (tmx-spec context) op)))
    (unless (eq (tmo-name line) name)
      (tm-fail "macro ~A: sub-op ~A (line ~D) where its :seq has ~A"
               (tmo-name (tmr-macro run)) (tmo-name line) (tmo-index line) name))
    (tm-check-op-line run line duration)
    (setf (tmo-macro line) (tmr-macro run))
    (push line (tmx-ops context))
    (tm-add-change context (+ (tmr-at run) duration) (mop-effects op) run line (tm-fresh-key run))
    (incf (tmr-at run) duration)
    (pop (tmr-macro-seq run))
    (if (tmr-macro-seq run)
        (setf (tmr-next-key run) (tm-fresh-key run))
        (let* ((macro (tmr-macro run))
               (mop (tmo-mop macro))
               (after (model-apply-effects mop (tmr-macro-before run)))
               ;; The variables its sub-ops or its effects touch take their
               ;; values in the state it started from with its effects.
               (touched (remove-duplicates
                         (append (mapcar #'car (mop-effects mop))
                                 (loop for sub in (mop-seq mop)
                                       append (mapcar #'car (mop-effects (model-find-op (tmx-model context) sub))))))))
          (setf (tmo-expected-end macro) (tmr-at run)
                (tmo-effective-end macro) (tmr-at run))
          ;; Tagged with the last sub-op: the macro's end goes with it.
          (setf (tmc-macro-end (tm-add-change context (tmr-at run)
                                              (loop for i in touched collect (cons i (svref after i)))
                                              run line (tm-fresh-key run)))
                t)
          (setf (tmr-macro run) nil
                (tmr-next-key run) (tm-fresh-key run))
          (tm-op-done context run)))))

(defun tm-op-done (context run)
  "A top-level op of RUN's directive is over: when it was the directive's last,
its goal must hold, and the next directive follows."
  (when (zerop (decf (tmr-remaining run)))
    (let ((directive (nth (tmr-pos run) (tmr-directives run))))
      (when (eq (first directive) :state)
        (let ((state (tm-run-state context run)))
          (unless (model-eval (second directive) state)
            (tm-fail "~A ~A: after its plan for directive ~D the goal does not hold in ~A"
                     (tmr-kind run) (tmr-name run) (tmr-pos run) (tm-state-text context state))))))
    (incf (tmr-pos run))))

(defun tm-check-result (run)
  "What SEND-EVENT returned for RUN, now that the model knows how it ended."
  (let ((result (tmr-result run)))
    (unless (eq result :none)
      (let ((expected (if (tmr-failed run) (list nil (tmr-fail-goal run)) (list t))))
        (unless (equal result expected)
          (tm-fail "send-event of ~A returned ~S; its run ~:[succeeded~;failed~] so the model expects ~S"
                   (tmr-name run) result (tmr-failed run) expected))))))

;;; The clock

(defun tm-key< (time-a key-a time-b key-b)
  (or (< time-a time-b) (and (= time-a time-b) (< key-a key-b))))

(defun tm-next-happening (context limit)
  "The first thing due by LIMIT: (TIME KEY KIND THING), KIND :STEP (a run's next
op or end), :CHANGE or :TIMER; or NIL."
  (let ((best nil))
    (flet ((consider (time key kind thing)
             (when (and (<= time limit) (or (null best) (tm-key< time key (first best) (second best))))
               (setf best (list time key kind thing)))))
      (dolist (run (tmx-active context))
        (consider (tmr-at run) (tmr-next-key run) :step run))
      (dolist (change (tmx-changes context))
        (unless (tmc-applied change)
          (consider (tmc-time change) (tmc-key change) :change change)))
      (dolist (timer (tmx-timers context))
        (when (tmts-time timer)
          (consider (tmts-time timer) (tmts-key timer) :timer timer))))
    best))

(defun tm-busy-p (context)
  "Is an event running or waiting?"
  (or (tmx-active context) (tmx-queue context)))

(defun tm-advance (context limit &key (dispatch t))
  "Play everything due by LIMIT, in time order (equal times by key): runs'
ops and ends, state changes (and the triggers they fire), timers.  The events
timers and triggers send at an instant are dispatched, in the order they went
off, once everything else due then has happened (unless DISPATCH is false:
then they wait for the advance under way)."
  (loop
    (let ((next (tm-next-happening context limit)))
      (cond ((and next (not (and dispatch (tmx-deferred context) (> (first next) (tmx-now context)))))
             (destructuring-bind (time key kind thing) next
               (declare (ignore key))
               (if (eql time (tmx-instant context))
                   (when (> (incf (tmx-instant-count context)) 20000)
                     (tm-fail "the model does not move on at time ~A" (float time 1d0)))
                   (setf (tmx-instant context) time (tmx-instant-count context) 0))
               (setf (tmx-now context) time)
               (ecase kind
                 (:change (tm-apply-change context thing))
                 (:timer (tm-fire-timer context thing))
                 (:step (tm-step context thing)
                  (when (tmr-complete thing)
                    (tm-finish-run context thing))))))
            ((and dispatch (tmx-deferred context))
             (let ((sends (tmx-deferred context)))
               (setf (tmx-deferred context) '())
               (loop for (name source) in sends
                     do (tm-dispatch context name (tmx-now context) nil :none source))))
            (t (return)))))
  (setf (tmx-now context) (max limit (tmx-now context))))

(defun tm-finish (context)
  "FINISH-EVENTS: while an event runs or waits, play everything up to the next thing due."
  (loop while (tm-busy-p context)
        do (let ((next (tm-next-happening context (expt 10 9))))
             (tm-advance context (if next (first next) (tmx-now context)))
             (unless next (return)))))

(defun tm-apply-change (context change)
  "CHANGE falls due: the state takes it, then the triggers look."
  (setf (tmc-applied change) t)
  (loop for (i . k) in (tmc-data change) do (setf (svref (tmx-state context) i) k))
  (tm-check-triggers context (tmc-time change)))

(defun tm-check-triggers (context time)
  "After a state change at TIME, each trigger whose condition went from false
to true shows (:trigger NAME :time TIME) and sends its event."
  (dolist (entry (tmx-triggers context))
    (let* ((trigger (car entry))
           (holds (model-eval (tmg-condition trigger) (tmx-state context))))
      (when (and holds (not (cdr entry)))
        (setf (cdr entry) t)
        (tm-count context :triggers)
        (tm-expect context (list :trigger (tmg-name trigger) :time time)
                   (format nil "trigger ~A's condition becoming true at ~A" (tmg-name trigger) (float time 1d0)))
        (tm-defer context (tmg-event trigger) :trigger))
      (setf (cdr entry) holds))))

(defun tm-arm-timer (context timer-state time)
  "Make TIMER-STATE go off its :after after TIME."
  (setf (tmts-time timer-state) (+ time (tmt-after (tmts-timer timer-state)))
        (tmts-key timer-state) (* (tm-new-block context) +tm-block+)))

(defun tm-fire-timer (context timer-state)
  "A timer goes off: its line, its re-arming if it repeats, its event."
  (let ((timer (tmts-timer timer-state))
        (time (tmts-time timer-state)))
    (tm-count context :timers)
    (setf (tmts-time timer-state) nil)
    (tm-expect context (list :timer (tmt-name timer) :time time)
               (format nil "timer ~A going off at ~A" (tmt-name timer) (float time 1d0)))
    (when (tmt-repeat timer)
      (tm-count context :repeats)
      (tm-arm-timer context timer-state time))
    (tm-defer context (tmt-event timer) :timer)))

(defun tm-defer (context name source)
  "Event NAME, sent now by a timer or trigger (SOURCE), waits until everything
else due now has happened."
  (setf (tmx-deferred context) (append (tmx-deferred context) (list (list name source)))))

(defun tm-finish-run (context run)
  "RUN is complete: its :fail and :state lines, then the waiting events no
running event meets start."
  (let ((end (tmr-end run)))
    (when (tmr-failed run)
      (tm-count context :fails)
      (tm-expect context (list :fail (tmr-name run) :goal (tmr-fail-goal run) :time end)
                 (format nil "~(~A~) ~A failing at ~A" (tmr-kind run) (tmr-name run) (float end 1d0))))
    (tm-expect context (list :state (copy-seq (tmx-state context)))
               (format nil "~(~A~) ~A ending at ~A" (tmr-kind run) (tmr-name run) (float end 1d0)))
    (tm-check-result run)
    (setf (tmx-active context) (remove run (tmx-active context)))
    (tm-start-waiting context end)))
