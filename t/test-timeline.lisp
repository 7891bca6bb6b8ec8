;;;; test-timeline.lisp -- the timed controller: the CHI'95 paper's fly/sit
;;;; example under each policy, cuts and their states, timers and triggers,
;;;; the whole-event API as the special case of events that never meet, the
;;;; CLI's EV@T and --at, and the errors of bad timed input.

(in-package #:player-tests)

(def-suite* timeline :in player-tests)

(defparameter *fly-sit-forms*
  '((state-variable posture string stand (stand sit fly))
    (autoscript posture fly (flap))
    (op take-off :precond posture.stand :add posture.fly :duration 1.25 :interrupt :anytime)
    (op fly-loop :precond posture.fly :duration 3 :interrupt (:at 0.75 1.5 2.25))
    (op land :precond posture.fly :add posture.stand :duration 1.5
             :interrupt (:at 0.85) :if-cut (:add posture.stand))
    (op sit :precond posture.stand :add posture.sit :duration 1.5)
    (op standup :precond posture.sit :add posture.stand :duration 1)
    (event ev-fly :op take-off :op fly-loop :op land)
    (event ev-sit :state posture.sit))
  "Peedy's flight and perch, cut down: take-off may stop at any moment, the
lap at each quarter turn, the landing once his feet reach (then he stands).")

(defun call-with-fly-sit (function &optional (forms *fly-sit-forms*))
  "Call FUNCTION with a throwaway spec of FORMS (default *FLY-SIT-FORMS*)."
  (let ((spec (define-spec 'fly-sit forms :package (find-package '#:player-tests))))
    (unwind-protect (funcall function spec)
      (remove-spec 'fly-sit))))

(defun fly-sit-trace (sit-time policy &key (forms *fly-sit-forms*))
  "The trace of ev-fly at 0 and ev-sit at SIT-TIME under POLICY, played out."
  (let ((spec (define-spec 'fly-sit forms :package (find-package '#:player-tests))))
    (unwind-protect
         (let ((c (make-controller spec :timed t)))
           (send-event c 'ev-fly :at 0)
           (send-event c 'ev-sit :at sit-time :when-busy policy)
           (finish-events c)
           (trace-of c))
      (remove-spec 'fly-sit))))

(defparameter *flight-lines*
  '("(:event ev-fly :time 0)"
    "(:op take-off :script take-off :start 0 :end 1.25)"
    "(:autoscript-start flap :var posture :value fly :time 1.25)"
    "(:op fly-loop :script fly-loop :start 1.25 :end 4.25)")
  "The first lines of every fly/sit trace: he takes off and starts his lap.")

(test fly-then-sit-sequential
  "Queue: he sits only after he has landed."
  (is (equal (append *flight-lines*
                     '("(:queued ev-sit :time 1.8 :behind ev-fly)"
                       "(:op land :script land :start 4.25 :end 5.75)"
                       "(:autoscript-stop flap :var posture :value fly :time 5.75)"
                       "(:state (posture . stand))"
                       "(:event ev-sit :time 5.75)"
                       "(:op sit :script sit :start 5.75 :end 7.25)"
                       "(:state (posture . sit))"))
             (fly-sit-trace 1.8 :queue))))

(test fly-then-sit-preempt
  "Preempt: the lap is cut at its next quarter turn (1.25 + 0.75 = 2) and the
plan to sit starts from there: he is still flying, so he lands first."
  (is (equal (append *flight-lines*
                     '("(:cut fly-loop :time 2 :by ev-sit :end 2)"
                       "(:event ev-sit :time 2)"
                       "(:op land :script land :start 2 :end 3.5)"
                       "(:autoscript-stop flap :var posture :value fly :time 3.5)"
                       "(:op sit :script sit :start 3.5 :end 5)"
                       "(:state (posture . sit))"))
             (fly-sit-trace 1.8 :preempt))))

(test fly-then-sit-override
  "Override: the flight wins and the sit is dropped, as the trace says."
  (is (equal (append *flight-lines*
                     '("(:dropped ev-sit :time 1.8 :busy-with ev-fly :clash (:all))"
                       "(:op land :script land :start 4.25 :end 5.75)"
                       "(:autoscript-stop flap :var posture :value fly :time 5.75)"
                       "(:state (posture . stand))"))
             (fly-sit-trace 1.8 :override))))

(test fly-then-sit-interleave
  "Interleave: he starts his flight, sits instead, then reconsiders and
completes it: the lap he was cut in is re-planned from sitting."
  (is (equal (append *flight-lines*
                     '("(:cut fly-loop :time 2 :by ev-sit :end 2)"
                       "(:event ev-sit :time 2)"
                       "(:op land :script land :start 2 :end 3.5)"
                       "(:autoscript-stop flap :var posture :value fly :time 3.5)"
                       "(:op sit :script sit :start 3.5 :end 5)"
                       "(:state (posture . sit))"
                       "(:resume ev-fly :time 5)"
                       "(:op standup :script standup :start 5 :end 6)"
                       "(:op take-off :script take-off :start 6 :end 7.25)"
                       "(:autoscript-start flap :var posture :value fly :time 7.25)"
                       "(:op fly-loop :script fly-loop :start 7.25 :end 10.25)"
                       "(:op land :script land :start 10.25 :end 11.75)"
                       "(:autoscript-stop flap :var posture :value fly :time 11.75)"
                       "(:state (posture . stand))"))
             (fly-sit-trace 1.8 :interleave))))

(test cut-states
  "A cut op leaves the state before it, or its :if-cut state; :anytime cuts at
once; the plan after the cut starts from whatever the cut left."
  ;; Take-off cut at 0.4: still standing, so he just sits.
  (is (equal '("(:event ev-fly :time 0)"
               "(:op take-off :script take-off :start 0 :end 1.25)"
               "(:cut take-off :time 0.4 :by ev-sit :end 0.4)"
               "(:event ev-sit :time 0.4)"
               "(:op sit :script sit :start 0.4 :end 1.9)"
               "(:state (posture . sit))")
             (fly-sit-trace 0.4 :preempt)))
  ;; Landing cut once his feet reach (4.25 + 0.85): :if-cut says standing.
  (let ((lines (fly-sit-trace 4.5 :preempt)))
    (is (equal (list "(:cut land :time 5.1 :by ev-sit :end 5.1)"
                     "(:event ev-sit :time 5.1)"
                     "(:autoscript-stop flap :var posture :value fly :time 5.1)"
                     "(:op sit :script sit :start 5.1 :end 6.6)"
                     "(:state (posture . sit))")
               (last lines 5))))
  ;; An op that is never interrupted runs to its end: the cut falls there.
  (let ((lines (fly-sit-trace 0.4 :preempt
                              :forms (subst '(op take-off :precond posture.stand :add posture.fly :duration 1.25)
                                            (third *fly-sit-forms*) *fly-sit-forms* :test #'equal))))
    (is (member "(:cut take-off :time 1.25 :by ev-sit :end 1.25)" lines :test #'string=))
    (is (member "(:event ev-sit :time 1.25)" lines :test #'string=))
    (is (member "(:op land :script land :start 1.25 :end 2.75)" lines :test #'string=))))

(test state-answers-for-now
  "STATE-VALUE gives the state at the controller's time, not the planned end."
  (call-with-fly-sit
   (lambda (spec)
    (let ((c (make-controller spec :timed t)))
      (send-event c 'ev-fly)
      (is (string-equal "stand" (state-value c 'posture)))
      (is (controller-busy-p c))
      (advance c 1.3)
      (is (string-equal "fly" (state-value c 'posture)))
      (is (= 1.3d0 (controller-time c)))
      (advance c 5.75)
      (is (string-equal "stand" (state-value c 'posture)))
      (is (not (controller-busy-p c)))))))

(test cut-inside-a-macro
  "A cut inside a macro-op closes the macro's line at the cut and cancels its
declared effects: the state is what its finished sub-ops made."
  (with-spec (spec macro-cut
               (state-variable a boolean false)
               (state-variable b boolean false)
               (op s1 :add a :duration 1)
               (op s2 :add b :duration 2 :interrupt :anytime)
               (macro-op m :precond (not b) :add b :seq (:op s1 :op s2))
               (event ev-m :op m)
               (event ev-x :state (not a)))
    (let ((c (make-controller spec :timed t)))
      (send-event c 'ev-m)
      (send-event c 'ev-x :at 1.5 :when-busy :preempt)
      (finish-events c)
      (is (equal '("(:event ev-m :time 0)"
                   "(:op m :script m :start 0 :end 1.5)"
                   "(:op s1 :script s1 :start 0 :end 1)"
                   "(:op s2 :script s2 :start 1 :end 3)"
                   "(:cut s2 :time 1.5 :by ev-x :end 1.5)"
                   "(:event ev-x :time 1.5)")
                 (subseq (trace-of c) 0 6)))
      (is (eq t (state-value c 'a)) "the macro's first sub-op finished")
      (is (null (state-value c 'b)) "neither the cut s2 nor the macro's effect applied"))))

;;; The whole-event API is the case where events never meet

(defun untimed-and-timed-traces (spec events &optional initial)
  "SPEC's traces for EVENTS sent one after another, untimed and timed."
  (let ((untimed (make-controller spec :initial-state initial))
        (timed (make-controller spec :initial-state initial :timed t)))
    (dolist (event events) (send-event untimed event))
    (play-events timed events)
    (values (trace-of untimed) (trace-of timed))))

(test events-that-never-meet-play-as-whole-events
  "Sent one after another, events on a timed controller give exactly the trace
of the whole-event API: Peedy's tour, and random specs."
  (let ((spec (peedy-spec)))
    ;; Without the trigger that makes him dance when music starts (the
    ;; whole-event API has no triggers).
    (setf (player.spec::spec-triggers spec) '())
    (multiple-value-bind (untimed timed)
        (untimed-and-timed-traces spec '(ev-hello ev-search ev-give ev-search ev-found ev-next-track ev-stop
                                         ev-listen ev-wake ev-help ev-thanks ev-fly-to ev-circle ev-land
                                         ev-sleep ev-nap ev-goodbye ev-wake ev-cd-done ev-bad-speech))
      (is (equal untimed timed))))
  (loop for seed from 1 to 40
        do (multiple-value-bind (forms model) (random-spec seed :op-event-count 3)
             (declare (ignore model))
             (let ((spec (define-spec 'never-meet forms :package (find-package '#:player-tests))))
               (unwind-protect
                    (let ((events (loop repeat 8 for all = (event-names spec)
                                        collect (nth (random (length all)) all))))
                      (multiple-value-bind (untimed timed) (untimed-and-timed-traces spec events)
                        (is (equal untimed timed) "seed ~D: ~S" seed events)))
                 (remove-spec 'never-meet))))))

;;; Timers and triggers

(defparameter *idle-forms*
  '((state-variable posture string stand (stand sit))
    (state-variable lamp boolean false)
    (op sit :precond posture.stand :add posture.sit :duration 1)
    (op stand :precond posture.sit :add posture.stand :duration 1)
    (op on :add lamp :duration 0.5)
    (op off :sub lamp :duration 0.5)
    (op wave :duration 1)
    (event ev-rest :state posture.sit)
    (event ev-hello :op wave)
    (event ev-on :state lamp)
    (event ev-off :state (not lamp))
    (event ev-look :op wave)))

(defun idle-trace (extra-forms sends until)
  "The trace of a spec of *IDLE-FORMS* and EXTRA-FORMS, with SENDS ((EVENT . TIME)...)
arriving, advanced to UNTIL."
  (let ((spec (define-spec 'idle (append *idle-forms* extra-forms) :package (find-package '#:player-tests))))
    (unwind-protect
         (let ((c (make-controller spec :timed t)))
           (play-events c sends :until until)
           (trace-of c))
      (remove-spec 'idle))))

(defun lines-starting (prefix lines)
  "The LINES that start with PREFIX."
  (remove-if-not (lambda (line) (alexandria:starts-with-subseq prefix line)) lines))

(test timer-goes-off-and-restarts-on-input
  (is (equal '("(:timer idle-sit :time 20)")
             (lines-starting "(:timer" (idle-trace '((timer idle-sit :after 20 :event ev-rest :restart-on :any))
                                                  '() 30))))
  ;; Input at 15 re-arms it: it goes off at 35.
  (is (equal '("(:timer idle-sit :time 35)")
             (lines-starting "(:timer" (idle-trace '((timer idle-sit :after 20 :event ev-rest :restart-on :any))
                                                  '((ev-hello . 15)) 40))))
  ;; Only the listed events restart it.
  (is (equal '("(:timer idle-sit :time 20)")
             (lines-starting "(:timer" (idle-trace '((timer idle-sit :after 20 :event ev-rest :restart-on (ev-look)))
                                                  '((ev-hello . 15)) 40))))
  (is (equal '("(:timer idle-sit :time 35)")
             (lines-starting "(:timer" (idle-trace '((timer idle-sit :after 20 :event ev-rest :restart-on (ev-look)))
                                                  '((ev-look . 15)) 40))))
  ;; The timer's event follows its line and plays.
  (let ((lines (idle-trace '((timer idle-sit :after 20 :event ev-rest)) '() 25)))
    (is (equal '("(:timer idle-sit :time 20)" "(:event ev-rest :time 20)" "(:op sit :script sit :start 20 :end 21)")
               (subseq lines 0 3)))))

(test repeating-timer
  (is (equal '("(:timer tick :time 2)" "(:timer tick :time 4)" "(:timer tick :time 6)")
             (lines-starting "(:timer" (idle-trace '((timer tick :after 2 :event ev-hello :repeat t)) '() 7)))))

(test trigger-fires-once-per-rising-edge
  (let ((lines (idle-trace '((trigger lit :when lamp :event ev-hello))
                           '((ev-on . 1) (ev-on . 3) (ev-off . 5) (ev-on . 7)) 10)))
    ;; On at 1.5 (fires), on again at 3 (already on: no edge), off at 5.5, on at 7.5 (fires).
    (is (equal '("(:trigger lit :time 1.5)" "(:trigger lit :time 7.5)") (lines-starting "(:trigger" lines)))
    (is (= 2 (count "(:event ev-hello" lines :test (lambda (prefix line) (alexandria:starts-with-subseq prefix line))))))
  ;; A condition true from the start is not an edge.
  (is (null (lines-starting "(:trigger" (idle-trace '((trigger standing :when posture.stand :event ev-hello)) '() 10)))))

(test triggers-that-never-settle-are-an-error
  "Zero-length ops and triggers that undo each other for ever are stopped with a
TIMELINE-ERROR that says so, instead of hanging."
  (with-spec (spec flicker
               (state-variable x boolean false)
               (op set-x :add x :duration 0)
               (op clear-x :sub x :duration 0)
               (event ev-set :op set-x)
               (event ev-clear :op clear-x)
               (trigger on :when x :event ev-clear)
               (trigger off :when (not x) :event ev-set))
    (let ((c (make-controller spec :timed t :presenter (make-null-presenter))))
      (send-event c 'ev-set)
      (signals timeline-error (advance c 1))
      (handler-case (progn (make-controller spec :timed t :presenter (make-null-presenter))
                           (let ((c (make-controller spec :timed t :presenter (make-null-presenter))))
                             (send-event c 'ev-set)
                             (advance c 1)))
        (timeline-error (e)
          (is (search "does not move on at time 0" (princ-to-string e))))))))

(test peedy-idles-then-sleeps
  "Peedy's spec: 20 s without input he sits, 60 s he dozes off; the music
starting makes him dance."
  (let* ((spec (peedy-spec))
         (c (make-controller spec :timed t)))
    (advance c 90)
    (let ((lines (trace-of c)))
      (is (equal '("(:timer idle-sit :time 20)" "(:timer idle-sleep :time 60)") (lines-starting "(:timer" lines))))
    (is (string-equal "sit" (state-value c 'posture)))
    (is (string-equal "sleep" (state-value c 'alert))))
  (let ((c (make-controller (peedy-spec) :timed t)))
    (play-events c '(ev-search ev-found))
    (is (member "(:trigger music-starts :time 5)" (trace-of c) :test #'string=))))

;;; Bad input

(defun timeline-spec-error (forms)
  "The message of the SPEC-ERROR defining a spec of FORMS signals, or NIL."
  (handler-case (progn (define-spec 'bad-timeline forms :package (find-package '#:player-tests)) nil)
    (spec-error (e) (princ-to-string e))))

(test bad-timed-input-is-one-clear-error
  (flet ((error-of (&rest forms)
           (timeline-spec-error (append '((state-variable p boolean false)
                                          (op go :add p :duration 1)
                                          (event ev :op go))
                                        forms))))
    (is (search "event sit: unknown :when-busy policy :sometimes" (error-of '(event sit (:when-busy :sometimes) :op go))))
    (is (search "unknown :when-busy policy" (timeline-spec-error '((:when-busy :later) (state-variable p boolean false)))))
    (is (search "op ask: op ask is must-ask" (error-of '(op ask :must-ask true :interrupt :anytime :if-cut (:sub p)))))
    (is (search ":if-cut needs :interrupt" (error-of '(op stop :sub p :if-cut (:add p)))))
    (is (search ":interrupt takes :never, :anytime or (:at" (error-of '(op stop :sub p :interrupt :sometimes))))
    (is (search "interruption point 3 lies after" (error-of '(op stop :sub p :duration 2 :interrupt (:at 3)))))
    (is (search "timer t1: a timer needs :event" (error-of '(timer t1 :after 5))))
    (is (search "timer t1: :after must be a positive number" (error-of '(timer t1 :after -1 :event ev))))
    (is (search "timer t1: unknown event nope" (error-of '(timer t1 :after 1 :event nope))))
    (is (search "trigger t2: :when takes a state expression, not 42" (error-of '(trigger t2 :when 42 :event ev))))
    (is (search "trigger t2: malformed expression" (error-of '(trigger t2 :when (p p p p) :event ev))))
    (is (search "trigger t2: a trigger needs :when" (error-of '(trigger t2 :event ev))))))

(test critical-time-the-script-lacks
  "(:at NAME) needs a script with that critical time: the body presenter says
which ones the script has; a bare trace presenter says it needs a library."
  (let ((library (checkout-file "specs/peedy-scripts.lisp")))
    (with-spec (spec crit
                 (state-variable p boolean false)
                 ;; Peedy's library starts him in a pose by his posture.
                 (state-variable posture string stand (fly stand sit))
                 (op bow :duration 1.25 :interrupt (:at stroke))
                 (op shrug :duration 1 :interrupt (:at nope))
                 (event ev :op bow))
      (let ((message (handler-case (progn (make-controller spec :timed t
                                                                    :presenter (player::make-body-presenter spec :scripts library :body 'parrot))
                                          nil)
                       (spec-error (e) (princ-to-string e)))))
        (is (search "op shrug: :interrupt (:at nope): script shrug has no critical time nope" message)))
      (is (search "only a script library gives"
                  (handler-case (progn (make-controller spec :timed t) nil)
                    (spec-error (e) (princ-to-string e))))))))

(test timed-api-argument-errors
  (call-with-fly-sit
   (lambda (spec)
    (let ((timed (make-controller spec :timed t))
          (untimed (make-controller spec)))
      (signals argument-error (send-event timed 'ev-sit :when-busy :sometimes))
      (signals argument-error (send-event untimed 'ev-sit :when-busy :preempt))
      (signals argument-error (advance untimed 1))
      (advance timed 2)
      (signals argument-error (advance timed 1))
      (signals argument-error (send-event timed 'ev-sit :at 1))
      (is (= 2 (controller-time timed)) "a refused call changes nothing")))))

;;; The command line

(test cli-timed-events
  (multiple-value-bind (out err code) (player-command "run" "specs/peedy.lisp"
                                                  "--events" "ev-fly-to@0,ev-sit@2")
    (declare (ignore err))
    (is (= 0 code))
    (is (search "(:cut fly-loop :time 2 :by ev-sit :end 2)" out)))
  (multiple-value-bind (out err code) (player-command "run" "specs/peedy.lisp" "--at" "61")
    (declare (ignore err))
    (is (= 0 code))
    (is (search "(:timer idle-sleep :time 60)" out)))
  (multiple-value-bind (out err code) (player-command "run" "specs/peedy.lisp"
                                                  "--events" "ev-fly-to@2,ev-sit@1")
    (declare (ignore out))
    (is (= 2 code))
    (is (search "times may not decrease" err)))
  (multiple-value-bind (out err code) (player-command "run" "specs/peedy.lisp"
                                                  "--events" "ev-fly-to@x")
    (declare (ignore out))
    (is (= 2 code))
    (is (search "EVENT@SECONDS" err)))
  ;; The C++ backend plays the same timed scenario, line for line.
  (let ((lisp (player-command "run" "specs/peedy.lisp" "--events" "ev-fly-to@0,ev-sit@2" "--at" "30"))
        (c++ (player-command "run" "specs/peedy.lisp" "--events" "ev-fly-to@0,ev-sit@2" "--at" "30"
                             "--backend" "c++")))
    (is (search "(:timer idle-sit :time 22)" lisp))
    (is (string= lisp c++))))

;;; Parallel events on disjoint channels

(defparameter *channel-forms*
  '((state-variable holding boolean false)
    (op search :add holding :duration 3 :channels (wings legs))
    (op glance :duration 1 :channels (head))
    (op nod :duration 1 :channels head)
    (op shrug :duration 1)
    (event ev-search :op search)
    (event ev-voice :op glance)
    (event ev-nod (:when-busy :override) :op nod)
    (event ev-shrug (:when-busy :override) :op shrug))
  "A search on the wings and legs; a glance and a nod of the head; a shrug
that declares no channels.")

(defun timed-trace-of-forms (name forms sends)
  "The trace of SENDS ((EVENT . TIME)...) on a timed controller of the spec
NAME made of FORMS, defined for the call and removed after."
  (let ((spec (define-spec name forms :package (find-package '#:player-tests))))
    (unwind-protect
         (let ((c (make-controller spec :timed t)))
           (play-events c sends)
           (trace-of c))
      (remove-spec name))))

(defun channel-trace (sends)
  "The trace of SENDS ((EVENT . TIME)...) on a spec of *CHANNEL-FORMS*."
  (timed-trace-of-forms 'channels *channel-forms* sends))

(test disjoint-events-play-side-by-side
  "An event on other channels, touching other variables, plays at once beside
the running one; one that meets it on a channel follows its policy."
  (is (equal '("(:event ev-search :time 0)"
               "(:op search :script search :start 0 :end 3)"
               "(:event ev-voice :time 1)"
               "(:op glance :script glance :start 1 :end 2)"
               "(:dropped ev-nod :time 1.5 :busy-with ev-voice :clash (\"head\"))"
               "(:state (holding . nil))"
               "(:state (holding . t))")
             (channel-trace '((ev-search . 0) (ev-voice . 1) (ev-nod . 1.5)))))
  ;; An op without declared channels meets everything.
  (is (equal "(:dropped ev-shrug :time 1 :busy-with ev-search :clash (:all))"
             (third (channel-trace '((ev-search . 0) (ev-shrug . 1))))))
  ;; A nod after the glance has ended plays beside the search too.
  (is (member "(:op nod :script nod :start 2.5 :end 3.5)"
              (channel-trace '((ev-search . 0) (ev-voice . 1) (ev-nod . 2.5))) :test #'string=)))

(test check-reports-ops-sharing-a-channel
  (let ((spec (define-spec 'channels *channel-forms* :package (find-package '#:player-tests))))
    (unwind-protect
         (let ((shared (remove :shared-channel (check-spec spec) :key #'player::diagnostic-kind :test-not #'eq)))
           (is (= 1 (length shared)))
           (is (search "ops glance and nod both drive head" (player::diagnostic-message (first shared)))))
      (remove-spec 'channels))))

;;; On the body

(test a-cut-stops-the-script-on-the-body
  "Simulated, a preempted lap stops its script at the cut: the fly-loop run's
stop is the cut time, and the landing starts there."
  (let* ((simulation (player::simulate (peedy-spec) :events '((ev-fly-to . 0) (ev-sit . 2)) :stream nil))
         (runs (player.performance::performance-runs (player.performance::simulation-performance simulation)))
         (lap (find "fly-loop" runs :key (lambda (run) (string (player.performance::script-name (player.performance::script-run-script run))))
                                    :test #'string-equal))
         (land (find "land" runs :key (lambda (run) (string (player.performance::script-name (player.performance::script-run-script run))))
                                 :test #'string-equal)))
    (is (= 1.25d0 (player.performance::script-run-start lap)))
    (is (eql 2d0 (player.performance::script-run-stop lap)))
    (is (= 2d0 (player.performance::script-run-start land)))
    ;; The sit ends at 5 s; the frames go on while the body settles (issue 27).
    (is (= 5d0 (player::controller-clock (player.performance::simulation-controller simulation))))
    (is (<= 5d0 (player.performance::simulation-end simulation) 6.5d0))))

(test finish-events-gives-up-on-endless-events
  "A timer that repeats faster than its event plays keeps the controller busy
for ever: FINISH-EVENTS says so instead of hanging."
  (let ((player.control::*finish-events-limit* 5000))
    (with-spec (spec endless
                 (state-variable x boolean false)
                 (op wave :duration 2)
                 (event ev-wave :op wave)
                 (timer tick :after 1 :event ev-wave :repeat t))
      (let ((c (make-controller spec :timed t :presenter (make-null-presenter))))
        (send-event c 'ev-wave)
        (handler-case (progn (finish-events c) (fail "finish-events returned"))
          (timeline-error (e)
            (is (search "events never stop coming" (princ-to-string e)))))))))
