;;;; test-c++-timeline.lisp -- the C++ backend's timed layer against the Lisp
;;;; timed controller: a timed scenario played on the generated C++ must print
;;;; the trace of PLAY-EVENTS on (MAKE-CONTROLLER MACHINE :TIMED T), line for
;;;; line: the fly/sit example under every policy and many cut times, Peedy
;;;; with his timers and trigger and his glance beside his lap, and random
;;;; specs with random :interrupt points, :if-cut states, durations, policies,
;;;; timers and triggers, their events arriving while others play -- some
;;;; with ops on a few channels and events on disjoint variables, so that
;;;; events play side by side.  The specs are built into a few programs
;;;; (BUILD-TIMED-C++-BATCH), on threads, before anything is compared: g++
;;;; dominates the time.

(in-package #:player-tests)

(def-suite* c++-timeline :in player-tests)

(defun lisp-timed-trace (machine initial-state events &key until when-busy)
  "The Lisp timed controller's trace lines for the scenario EVENTS (see PLAY-EVENTS)."
  (let ((controller (make-controller machine :timed t :initial-state initial-state)))
    (play-events controller events :until until :when-busy when-busy)
    (trace-of controller)))

(defun compare-timed-backends (machine initial-state events &key until when-busy runner)
  "NIL when both backends print the same trace for the timed scenario, else
a description of the first difference.  RUNNER, if given, plays the scenario
in C++ (see TIMED-RUNNER); else RUN-C++-TRACE builds MACHINE's driver."
  (flet ((trace-by (backend function)
           (handler-case (funcall function)
             (error (e) (return-from compare-timed-backends
                          (format nil "from ~S, events ~S: ~A signals: ~A" initial-state events backend e))))))
    (let ((lisp (trace-by "Lisp" (lambda () (lisp-timed-trace machine initial-state events
                                                               :until until :when-busy when-busy))))
          (c++ (trace-by "C++" (lambda ()
                                 (if runner
                                     (funcall runner initial-state events until when-busy)
                                     (run-c++-trace machine :initial-state initial-state :events events
                                                            :until until :when-busy when-busy))))))
      (destructuring-bind (&optional index lisp-line c++-line) (first-difference lisp c++)
        (when index
          (let ((*package* (find-package '#:player-user)))
            (format nil "from ~S, events ~S~@[ until ~A~]~@[ when busy ~(~A~)~]: line ~D differs~%    Lisp: ~A~%    C++:  ~A~%  (~D Lisp lines, ~D C++ lines)"
                    initial-state events until when-busy (1+ index) lisp-line c++-line
                    (length lisp) (length c++))))))))

;;; The programs: every spec of the suite, built once per session

;; Defined with the tests that use them, below.
(defvar *fly-sit-forms*)
(defvar *c++-macro-cut-forms*)
(defvar *c++-flicker-forms*)
(defvar *c++-timeline-seeds*)
(defvar *c++-channel-seeds*)

(defvar *timed-batches* nil
  "An alist KEY -> (MACHINE . RUNNER) of the suite's specs, built by ENSURE-TIMED-BATCHES.")

(defvar *timed-batch-problems* '()
  "Descriptions of the suite's specs that could not be defined or built.")

(defvar *timed-build-seconds* 0
  "How long building the suite's programs took.")

(defun machine-of-forms (name forms package)
  "The machine of a throwaway spec NAME of FORMS (the spec forgotten again)."
  (let ((spec (define-spec name forms :package package)))
    (unwind-protect (compile-spec spec)
      (remove-spec name))))

(defun timed-runner (executable index machine)
  "A function (INITIAL EVENTS UNTIL WHEN-BUSY) playing on controller INDEX of EXECUTABLE."
  (lambda (initial events until when-busy)
    (player.cpp::run-timed-c++-batch executable index machine :initial-state initial :events events
                                                          :until until :when-busy when-busy)))

(defun build-batches-in-parallel (batches &key (threads 2))
  "Build each of BATCHES (lists of (KEY . MACHINE)), THREADS at a time, into
*TIMED-BATCHES*; a batch that fails to build is noted in *TIMED-BATCH-PROBLEMS*."
  (let ((queue (copy-list batches))
        (lock (sb-thread:make-mutex :name "timed c++ builds")))
    (flet ((work ()
             (loop (let ((batch (sb-thread:with-mutex (lock) (pop queue))))
                     (unless batch (return))
                     (handler-case
                         (let ((executable (player.cpp::build-timed-c++-batch (mapcar #'cdr batch))))
                           (sb-thread:with-mutex (lock)
                             (loop for (key . machine) in batch
                                   for i from 0
                                   do (push (list* key machine (timed-runner executable i machine))
                                            *timed-batches*))))
                       (error (e)
                         (let ((text (format nil "building ~S: ~A" (mapcar #'car batch) e)))
                           (sb-thread:with-mutex (lock) (push text *timed-batch-problems*)))))))))
      (mapc #'sb-thread:join-thread
            (loop repeat threads collect (sb-thread:make-thread #'work :name "timed c++ build"))))))

(defun ensure-timed-batches ()
  "Define and build every spec the suite compares (once per session)."
  (unless *timed-batches*
    (let ((start (get-internal-real-time))
          (tests (find-package '#:player-tests))
          (fixed '()) (random '()))
      (setf *timed-batch-problems* '())
      (push (cons :fly-sit (machine-of-forms 'fly-sit *fly-sit-forms* tests)) fixed)
      (push (cons :macro-cut (machine-of-forms 'c++-macro-cut *c++-macro-cut-forms* tests)) fixed)
      (push (cons :flicker (machine-of-forms 'c++-flicker *c++-flicker-forms* tests)) fixed)
      (dolist (seed *c++-timeline-seeds*)
        (multiple-value-bind (forms model extras) (c++-timeline-spec seed)
          (handler-case
              (push (cons (list :random seed model extras forms)
                          (machine-of-forms (rs-symbol "c++-timeline-~D" seed) forms (find-package '#:player-user)))
                    random)
            (error (e) (push (describe-timed-problem seed forms (format nil "defining the spec: ~A" e))
                             *timed-batch-problems*)))))
      (dolist (seed *c++-channel-seeds*)
        (multiple-value-bind (forms variables) (channel-spec-forms seed)
          (handler-case
              (push (cons (list :channels seed variables forms)
                          (machine-of-forms (rs-symbol "c++-channels-~D" seed) forms (find-package '#:player-user)))
                    random)
            (error (e) (push (describe-timed-problem seed forms (format nil "defining the spec: ~A" e))
                             *timed-batch-problems*)))))
      ;; Peedy alone is as big as the rest together; the random specs in two.
      ;; Two programs of about the same size: Peedy is as big as two or three
      ;; random specs.
      (let* ((random (reverse random))
             (split (min (length random) (round (+ (length random) 0.5) 2))))
        (build-batches-in-parallel
         (list (cons (cons :peedy (compile-spec (peedy-spec))) (subseq random 0 split))
               (append (reverse fixed) (subseq random split)))
         :threads 2))
      (setf *timed-build-seconds* (/ (float (- (get-internal-real-time) start)) internal-time-units-per-second))
      (format t "~&  c++ timeline: programs built in ~,1F s~%" *timed-build-seconds*)))
  *timed-batches*)

(defun timed-batch (key)
  "(MACHINE . RUNNER) of the suite's spec KEY (:fly-sit, :macro-cut, :flicker,
:peedy), or NIL when it could not be built."
  (cdr (assoc key (ensure-timed-batches) :test #'equal)))

;;; The fly/sit example

(defun batch-runner-or-fail (key)
  "The C++ runner of the suite's spec KEY, or NIL after a failed check saying why."
  (let ((entry (timed-batch key)))
    (is (not (null entry)) "~S was not built: ~{~A~^; ~}" key *timed-batch-problems*)
    entry))

(test c++-fly-then-sit-every-policy
  "ev-sit arriving at many moments of ev-fly, under each policy: the C++
prints the Lisp trace (cuts at quarter turns, the landing's :if-cut, drops,
resumptions), and the four traces at 1.8 s are the ones TEST-TIMELINE expects."
  (destructuring-bind (&optional machine . runner) (batch-runner-or-fail :fly-sit)
    (when machine
      (dolist (policy *when-busy-policies*)
        (dolist (time '(0 0.4 1.25 1.8 2 2.6 4.25 4.5 5.1 5.5 5.75 8))
          (let ((problem (compare-timed-backends machine '() `((ev-fly . 0) (ev-sit . ,time))
                                                 :when-busy policy :runner runner)))
            (is (null problem) "fly/sit: ~A" problem))))
      (is (equal (fly-sit-trace 1.8 :interleave)
                 (funcall runner '() '((ev-fly . 0) (ev-sit . 1.8)) nil :interleave)))
      ;; Untimed entries wait for the events before them; UNTIL stops midway.
      (dolist (scenario '((:events (ev-fly ev-sit ev-fly))
                          (:events ((ev-fly . 1) ev-sit (ev-fly . 9) (ev-sit . 9.5)) :until 30)
                          (:events ((ev-sit . 0) (ev-fly . 0) (ev-sit . 0)) :until 3)
                          (:events ((ev-fly . 0)) :until 2.1)))
        (dolist (policy '(nil :preempt :interleave))
          (let ((problem (compare-timed-backends machine '((posture . stand)) (getf scenario :events)
                                                 :when-busy policy :until (getf scenario :until)
                                                 :runner runner)))
            (is (null problem) "fly/sit: ~A" problem)))))))

(defparameter *c++-macro-cut-forms*
  '((state-variable a boolean false)
    (state-variable b boolean false)
    (state-variable c boolean false)
    (op s1 :add a :duration 1)
    (op s2 :add b :duration 2 :interrupt :anytime :if-cut (:add c))
    (op s3 :add c :duration 1)
    (macro-op m :precond (not b) :add b :seq (:op s1 :op s2))
    (macro-op n :precond (not c) :add (b c) :seq (:op s1 :op s3))
    (autoscript c true (glow))
    (event ev-m :op m)
    (event ev-n :op n :op s1)
    (event ev-x :state (not a))
    ;; Two macros on disjoint channels and variables: played side by side,
    ;; the one opened first ends first.
    (state-variable p boolean false)
    (state-variable q boolean false)
    (op p1 :duration 1 :channels (wings))
    (op p2 :add p :duration 1 :channels (wings))
    (op q1 :duration 1 :channels (head))
    (op q2 :add q :duration 1 :channels (head))
    (macro-op mp :precond (not p) :add p :seq (:op p1 :op p2))
    (macro-op mq :precond (not q) :add q :seq (:op q1 :op q2))
    (event ev-mp :op mp)
    (event ev-mq :op mq))
  "Macros cut inside, one whose last sub-op finishes through the cut, and two
macros of events playing side by side whose spans cross.")

(test c++-cut-inside-a-macro
  "A cut inside a macro-op, and a macro whose last sub-op finishes through the
cut, print as in Lisp."
  (destructuring-bind (&optional machine . runner) (batch-runner-or-fail :macro-cut)
    (when machine
      (dolist (time '(0 0.5 1 1.5 2.5 3))
        (dolist (first '(ev-m ev-n))
          (dolist (policy '(:preempt :interleave))
            (let ((problem (compare-timed-backends machine '() `((,first . 0) (ev-x . ,time))
                                                   :when-busy policy :runner runner)))
              (is (null problem) "macro cut: ~A" problem))))))))

(test c++-crossing-macros-of-events-side-by-side
  "Two events beside each other on disjoint channels, their macros' spans
crossing (the first opened ends first): each macro line gets its own :end, in
C++ as in Lisp."
  (destructuring-bind (&optional machine . runner) (batch-runner-or-fail :macro-cut)
    (when machine
      (let ((lines (funcall runner '() '((ev-mp . 0) (ev-mq . 1)) nil nil)))
        (is (member "(:op mp :script mp :start 0 :end 2)" lines :test #'string=) "lines: ~S" lines)
        (is (member "(:op mq :script mq :start 1 :end 3)" lines :test #'string=) "lines: ~S" lines))
      (dolist (scenario '(((ev-mp . 0) (ev-mq . 1)) ((ev-mq . 0) (ev-mp . 0.5)) ((ev-mp . 0) (ev-mq . 0))))
        (let ((problem (compare-timed-backends machine '() scenario :runner runner)))
          (is (null problem) "crossing macros: ~A" problem))))))

;;; Peedy: timers, a trigger, a glance beside his lap

(test c++-peedy-timed
  "Peedy on a timed controller: idle timers, the music trigger, flights cut
short, a glance at a voice while he flies his lap (his eyes are free), in
C++ as in Lisp."
  (destructuring-bind (&optional machine . runner) (batch-runner-or-fail :peedy)
    (when machine
      (dolist (scenario '((() 90)
                          (((ev-fly-to . 0) (ev-sit . 2)) 90)
                          ((ev-search ev-found) 30)
                          (((ev-hello . 1) (ev-search . 3) ev-found (ev-wake . 30) (ev-fly-to . 31)
                            (ev-sit . 31.5) (ev-land . 33)) 150)
                          (((ev-search . 0) (ev-found . 0.5) (ev-next-track . 1) (ev-stop . 7)) 70)
                          ((ev-sleep ev-wake ev-help) nil)
                          (((ev-circle . 0) (ev-voice . 1) (ev-voice . 1.3) (ev-voice . 2) (ev-circle . 2.5)
                            (ev-voice . 3.2) (ev-land . 4)) nil)))
        (destructuring-bind (events until) scenario
          (dolist (initial '(() ((alert . snore) (posture . sit)) ((posture . fly))))
            (let ((problem (compare-timed-backends machine initial events :until until :runner runner)))
              (is (null problem) "Peedy: ~A" problem)))))
      ;; The glance plays beside the lap, in both.
      (let ((lines (funcall runner '((posture . fly)) '((ev-circle . 0) (ev-voice . 1)) nil nil)))
        (is (equal '("(:event ev-circle :time 0)" "(:op fly-loop :script fly-loop :start 0 :end 3)"
                     "(:event ev-voice :time 1)" "(:op glance :script glance :start 1 :end 1.6)")
                   (subseq lines 1 5))
            "Peedy's glance: ~S" lines)))))

;;; Errors

(defparameter *c++-flicker-forms*
  '((state-variable x boolean false)
    (op set-x :add x :duration 0)
    (op clear-x :sub x :duration 0)
    (event ev-set :op set-x)
    (event ev-clear :op clear-x)
    (trigger on :when x :event ev-clear)
    (trigger off :when (not x) :event ev-set))
  "Two triggers that fire each other for ever at one instant.")

(test c++-timed-errors
  "Critical times named in :interrupt are refused at emit time; a timeline
that cannot move on makes the C++ stop with the message the Lisp signals;
bad scenarios are argument errors."
  (with-spec (spec c++-named-point
               (state-variable p boolean false)
               (op bow :add p :duration 1.25 :interrupt (:at stroke))
               (event ev :op bow))
    (let ((message (handler-case (progn (run-c++-trace (compile-spec spec) :events '((ev . 0))) nil)
                     (player-error (e) (princ-to-string e)))))
      (is (search "op bow: :interrupt (:at stroke) names critical times; give seconds for C++" message)
          "message: ~A" message)))
  (destructuring-bind (&optional machine . runner) (batch-runner-or-fail :flicker)
    (when machine
      (signals timeline-error (lisp-timed-trace machine '() '((ev-set . 0)) :until 1))
      ;; The C++ takes about 5 s to reach its limit of 100,000 items at one
      ;; instant (the Lisp 0.03 s), a tenth of the fast tier: only `make test` runs it.
      (when (eq *test-tier* :full)
        (let ((message (handler-case (progn (funcall runner '() '((ev-set . 0)) 1 nil) nil)
                         (player-error (e) (princ-to-string e)))))
          (is (search "does not move on at time 0" message) "message: ~A" message)))))
  (call-with-fly-sit
   (lambda (spec)
     (let ((machine (compile-spec spec)))
       (signals argument-error (run-c++-trace machine :events '((ev-fly . -1))))
       (signals argument-error (run-c++-trace machine :events '((ev-fly . 5)) :until 2))
       (signals argument-error (run-c++-trace machine :events '((ev-fly . 0)) :when-busy :sometimes))
       (signals player-error (run-c++-trace machine :events '((ev-fly . 3) (ev-sit . 1))))))))

;;; Random specs, random interruptions, events meeting

(defparameter *c++-timeline-seeds* (loop for seed from 1 to 5 collect seed)
  "The seeds of the random timed specs compared across backends.")

(defparameter *c++-channel-seeds* (loop for seed from 1 to 6 collect seed)
  "The seeds of the random specs with ops on channels compared across backends.")

(defparameter *c++-timeline-runs-per-spec* (sweep-count 16 4)
  "Random scenarios played on each random timed spec, 4 in the fast tier (which
builds the same programs, so both tiers share them in the C++ cache).")

(defun form-head-p (form name)
  "Is FORM a list headed by a symbol named NAME?"
  (and (consp form) (symbolp (first form)) (string= (symbol-name (first form)) name)))

(defun random-interrupt (prng duration)
  "A random :interrupt for an op of DURATION seconds."
  (case (rs-below prng 4)
    (0 (extra-symbol "never"))
    (1 (extra-symbol "anytime"))
    (t (cons (extra-symbol "at")
             (loop repeat (rs-between prng 1 3)
                   collect (* duration (rs-pick prng '(0 0.25 0.5 0.75 1))))))))

(defun never-interrupt-p (interrupt)
  "Is INTERRUPT the symbol never?"
  (and (symbolp interrupt) (string= (symbol-name interrupt) "NEVER")))

(defun timed-op-form (prng form model extras)
  "Op FORM with a random :duration, :interrupt and :if-cut."
  (let* ((duration (rs-pick prng '(0.5 1 1 1.5 2 3)))
         (interrupt (random-interrupt prng duration))
         (must-ask (getf (cddr form) :must-ask)))
    (append form
            (list :duration duration :interrupt interrupt)
            (when (and (not must-ask) (not (never-interrupt-p interrupt)) (rs-chance prng 0.6))
              (list :if-cut (random-plannable-literal prng model extras))))))

(defun timed-event-form (prng form)
  "Event FORM, sometimes with its own :when-busy policy."
  (if (rs-chance prng 0.4)
      (list* (first form) (second form)
             (list :when-busy (rs-pick prng *when-busy-policies*))
             (cddr form))
      form))

(defun random-timer-forms (prng events condition)
  "Spec forms adding a timer or two sending EVENTS, and sometimes a trigger
on CONDITION (a function of no arguments making a state expression)."
  (append (loop for i below (rs-between prng 0 2)
                collect (list* (extra-symbol "timer") (rs-symbol "tm~D" i)
                               :after (rs-pick prng '(1.5 2.5 4 7))
                               :event (rs-pick prng events)
                               (append (when (rs-chance prng 0.4) (list :repeat (extra-symbol "true")))
                                       (case (rs-below prng 3)
                                         (0 (list :restart-on :any))
                                         (1 (list :restart-on (rs-sample prng events 2)))))))
          (when (rs-chance prng 0.5)
            (list (list (extra-symbol "trigger") (rs-symbol "tr0")
                        :when (funcall condition)
                        :event (rs-pick prng events))))))

(defun c++-timeline-spec (seed &rest random-spec-options)
  "The forms of random timed spec SEED (C++-RANDOM-SPEC's, given
RANDOM-SPEC-OPTIONS, with timed options), its model and extras: (VALUES
FORMS MODEL EXTRAS)."
  (multiple-value-bind (forms model extras) (apply #'c++-random-spec seed random-spec-options)
    (let* ((prng (make-rs-prng (+ 300000 seed)))
           (events (loop for form in forms when (form-head-p form "EVENT") collect (second form)))
           (forms (mapcar (lambda (form)
                            (cond ((form-head-p form "OP") (timed-op-form prng form model extras))
                                  ((form-head-p form "EVENT") (timed-event-form prng form))
                                  (t form)))
                          forms)))
      (values (append (when (rs-chance prng 0.5)
                        (list (list :when-busy (rs-pick prng *when-busy-policies*))))
                      forms
                      (random-timer-forms prng events
                                          (lambda () (render-expression model (random-literal-ast prng model)))))
              model extras))))

;;; Random specs on channels: a few groups of variables, each with its ops on
;;; a channel of its own (now and then on a shared one, another group's, or
;;; none) and events touching only the group's variables, so that events of
;;; two groups play side by side and the policies apply when they meet.

(defun channel-spec-forms (seed)
  "The forms of random channel spec SEED and its plannable variables as
((NAME . VALUES)...): (VALUES FORMS VARIABLES)."
  (let* ((prng (make-rs-prng (+ 500000 seed)))
         (groups (rs-between prng 2 3))
         (channels '("head" "wings" "legs"))
         (variables '()) (var-forms '()) (op-forms '()) (event-forms '()) (events '()))
    (dotimes (g groups)
      (let* ((a (rs-symbol "g~Da" g)) (b (rs-symbol "g~Db" g)) (n (rs-symbol "g~Dn" g))
             (domain (list (rs-symbol "x") (rs-symbol "y") (rs-symbol "z")))
             (ops '()))
        (push (cons a (list (extra-symbol "true") (extra-symbol "false"))) variables)
        (push (cons b domain) variables)
        (push (list (extra-symbol "state-variable") a (extra-symbol "boolean") (extra-symbol "false")) var-forms)
        (push (list (extra-symbol "state-variable") b (extra-symbol "string") (first domain) domain) var-forms)
        (push (list (extra-symbol "state-variable") n (extra-symbol "integer") 0) var-forms)
        (flet ((literal ()
                 (if (rs-chance prng 0.4)
                     (if (rs-chance prng 0.5) a (list (extra-symbol "not") a))
                     (rs-symbol "g~Db.~A" g (rs-pick prng '("x" "y" "z")))))
               (effect ()
                 (case (rs-below prng 3)
                   (0 (list :add a))
                   (1 (list :sub a))
                   (t (list :add (rs-symbol "g~Db.~A" g (rs-pick prng '("x" "y" "z"))))))))
          (dotimes (k (rs-between prng 2 4))
            (let* ((name (rs-symbol "g~Do~D" g k))
                   (duration (rs-pick prng '(0.5 1 1.5 2 3)))
                   (interrupt (random-interrupt prng duration))
                   (channel (nth g channels))
                   (choice (rs-below prng 100)))
              (push name ops)
              (push (append (list (extra-symbol "op") name)
                            (when (rs-chance prng 0.5) (list :precond (literal)))
                            (effect)
                            (list :duration duration :interrupt interrupt)
                            (when (and (not (never-interrupt-p interrupt)) (rs-chance prng 0.4))
                              (list :if-cut (effect)))
                            (cond ((< choice 75) (list :channels (list channel)))
                                  ((< choice 84) (list :channels (list channel "voice")))
                                  ((< choice 92) (list :channels (list (nth (mod (1+ g) groups) channels))))
                                  (t '())))
                    op-forms)))
          (when (rs-chance prng 0.4)
            (let ((name (rs-symbol "g~Dm" g)))
              (push (append (list (extra-symbol "macro-op") name :precond (literal))
                            (effect)
                            (list :seq (loop repeat 2 append (list :op (rs-pick prng ops)))))
                    op-forms)
              (push name ops)))
          (dotimes (k (rs-between prng 2 3))
            (let ((name (rs-symbol "g~De~D" g k)))
              (push name events)
              (push (append (list (extra-symbol "event") name)
                            (when (rs-chance prng 0.3)
                              (list (list :when-busy (rs-pick prng *when-busy-policies*))))
                            (loop repeat (rs-between prng 1 3)
                                  append (case (rs-below prng 5)
                                           ((0 1) (list :op (rs-pick prng ops)))
                                           (2 (list :state (literal)))
                                           (3 (list :add (list n 1)))
                                           (t (effect)))))
                    event-forms))))))
    (let ((variables (reverse variables))
          (events (reverse events)))
      (values (append (when (rs-chance prng 0.5)
                        (list (list :when-busy (rs-pick prng *when-busy-policies*))))
                      (reverse var-forms) (reverse op-forms) (reverse event-forms)
                      (random-timer-forms prng events
                                          (lambda () (let ((var (rs-pick prng variables)))
                                                       (if (= 2 (length (cdr var)))
                                                           (car var)
                                                           (rs-symbol "~A.~A" (car var)
                                                                      (rs-pick prng (cdr var))))))))
              variables))))

(defun random-channel-initial-state (prng variables)
  "A random initial state of a channel spec's VARIABLES."
  (loop for (name . values) in variables collect (cons name (rs-pick prng values))))

(defun random-timed-scenario (prng machine initial-state &key bounded)
  "(EVENTS UNTIL WHEN-BUSY BUSY TIMED PARALLEL): five to ten entries, mostly
timed and close together, drawn while a Lisp timed controller plays them so
that each time is possible (not before the controller's time); with BOUNDED,
all timed and an UNTIL always given (triggers and timers may keep a random
spec busy for ever); BUSY of the
TIMED timed entries arrive while another event plays, PARALLEL of them start
beside the events playing."
  (let* ((controller (make-controller machine :timed t :initial-state initial-state
                                              :presenter (make-null-presenter)))
         (timeline (player.control::controller-timeline controller))
         (events (event-names machine))
         (when-busy (when (rs-chance prng 0.3) (rs-pick prng *when-busy-policies*)))
         (busy 0) (timed 0) (parallel 0)
         (entries (loop repeat (rs-between prng 5 10)
                        for event = (rs-pick prng events)
                        collect (if (and (not bounded) (rs-chance prng 0.15))
                                    (progn (finish-events controller)
                                           (send-event controller event)
                                           event)
                                    (let ((time (+ (controller-time controller)
                                                   (rs-pick prng '(0 0.25 0.25 0.5 0.5 1 1.5 3)))))
                                      (advance controller time)
                                      (incf timed)
                                      (let ((running (length (player.control::timeline-runs timeline))))
                                        (when (controller-busy-p controller) (incf busy))
                                        (send-event controller event :at time :when-busy when-busy)
                                        (when (and (plusp running)
                                                   (> (length (player.control::timeline-runs timeline)) running))
                                          (incf parallel)))
                                      (cons event time))))))
    (list entries
          (when (or bounded (rs-chance prng 0.5)) (+ (controller-time controller) (rs-pick prng '(0 1 5 20))))
          when-busy busy timed parallel)))

(defun describe-timed-problem (seed forms problem)
  "The failure message for random timed spec SEED."
  (let ((*package* (find-package '#:player-user))
        (*print-pretty* nil))
    (format nil "seed ~D: ~A~%  spec:~{~%    ~S~}" seed problem forms)))

(defun compare-random-timed (kind)
  "Play random scenarios on the suite's random specs of KIND (:random or
:channels); return the problems and the plist of counts."
  (let ((problems '()) (streams 0) (busy 0) (timed 0) (cuts 0) (parallel 0) (specs 0))
    (loop for (key machine . runner) in (reverse (ensure-timed-batches))
          when (and (consp key) (eq (first key) kind))
            do (incf specs)
               (destructuring-bind (seed model-or-variables extras-or-forms &optional forms) (rest key)
                 (let ((prng (make-rs-prng (+ (if (eq kind :random) 400000 600000) seed)))
                       (forms (or forms extras-or-forms)))
                   (loop for i below *c++-timeline-runs-per-spec*
                         for initial = (cond ((zerop i) '())
                                             ((eq kind :random)
                                              (random-initial-state prng model-or-variables extras-or-forms))
                                             (t (random-channel-initial-state prng model-or-variables)))
                         for (events until when-busy b n p) = (random-timed-scenario prng machine initial
                                                                                     :bounded (eq kind :channels))
                         for problem = (compare-timed-backends machine initial events :until until
                                                               :when-busy when-busy :runner runner)
                         do (incf streams)
                            (incf busy b)
                            (incf timed n)
                            (incf parallel p)
                            (incf cuts (count-if (lambda (line) (search "(:cut " line))
                                                 (lisp-timed-trace machine initial events
                                                                   :until until :when-busy when-busy)))
                         when problem
                           do (push (describe-timed-problem seed forms problem) problems)
                              (return)))))
    (values problems (list :specs specs :streams streams :busy busy :timed timed :cuts cuts :parallel parallel))))

(defun report-random-timed (kind problems counts)
  "Check the counts of COMPARE-RANDOM-TIMED and that there were no PROBLEMS."
  (destructuring-bind (&key specs streams busy timed cuts parallel) counts
    (format t "~&  c++ timeline (~(~A~)): ~D streams over ~D specs, ~D of ~D timed events arriving busy, ~D starting beside others, ~D cuts~%"
            kind streams specs busy timed parallel cuts)
    (is (null *timed-batch-problems*) "~{~A~^~%~%~}" *timed-batch-problems*)
    (is (>= streams (* 4 *c++-timeline-runs-per-spec*)) "only ~D streams" streams)
    (is (< (* 0.3 timed) busy (* 0.85 timed)) "~D of ~D timed events arrived busy" busy timed)
    (is (plusp cuts) "no event was cut")
    (is (null problems) "~D random timed specs differ between C++ and Lisp; the first:~{~%~%~A~}"
        (length problems) (let ((all (reverse problems))) (subseq all 0 (min 3 (length all)))))
    parallel))

(test c++-timeline-random-specs-match-lisp
  "Random specs with random durations, :interrupt points, :if-cut states,
per-event and spec-wide :when-busy policies, timers and triggers, played with
random timed scenarios (about half the events arriving while another plays):
the C++ trace equals the Lisp trace line for line."
  (multiple-value-bind (problems counts) (compare-random-timed :random)
    (report-random-timed :random problems counts)))

(test c++-timeline-random-channels-match-lisp
  "Random specs whose ops play on a few channels, events of different groups
touching different variables, with timers and triggers: many events start
beside those playing, the others meet them and their policies apply; the C++
trace equals the Lisp trace line for line."
  (multiple-value-bind (problems counts) (compare-random-timed :channels)
    (let ((parallel (report-random-timed :channels problems counts)))
      (is (>= parallel (sweep-count 30 10)) "only ~D events started beside others" parallel))))
