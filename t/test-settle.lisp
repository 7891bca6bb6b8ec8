;;;; test-settle.lisp -- issue 27, "the body agrees with the state": channels a
;;;; finished or cut script drove settle to the pose of the controller's state,
;;;; so a run's last pose depends on its final state, never on the path taken.
;;;; The reference for a state's pose is an independent one: the same state
;;;; played from a fresh start (the starting-pose path, not the settling one).

(in-package #:player-tests)

(def-suite* settle :in player-tests)

;;;# The mechanism, on a bare body

(defun settle-test-body ()
  "A humanoid body in its rest pose."
  (player.body:make-body 'settler 'player.body:humanoid))

(defun elbow-index (body)
  "The pose index of the humanoid's left elbow flexion."
  (player.body:dof-index (player.body:body-skeleton body) 'player.body:l_elbow :x))

(defun bend-elbow (body degrees stop)
  "Drive BODY's left elbow to DEGREES from time 0 until STOP; the driver."
  (player.body:body-add-driver
   body (player.body:make-driver (player.body:parse-motor-frame
                                  `(:direct :set ((player.body:l_elbow :x ,degrees)) :duration 0.2))
                                 body 0 :stop stop)))

(test a-channel-let-go-holds-until-told-to-settle
  "A channel whose driver ends holds its angle (between a script's items);
told to settle, it eases to the settled pose, without a jump, over seconds
that follow its travel."
  (let* ((body (settle-test-body))
         (i (elbow-index body))
         (driver (bend-elbow body -60 0.5)))
    (player.body:body-evaluate body 1)
    (is (< (abs (- -60 (aref (player.body:body-pose body) i))) 1d-6) "held at -60")
    (player.body:body-settle-channels body (list driver) 1)
    (is (< (abs (- -60 (aref (player.body:body-pose body) i))) 1d-6) "no jump when settling starts")
    (let ((seconds (player.body:settle-seconds 60)))
      (is (< 0.3 seconds 1.5))
      (player.body:body-evaluate body (+ 1 (/ seconds 2)))
      (is (< -59 (aref (player.body:body-pose body) i) -1) "on the way at half time")
      (is (< (abs (- (+ 1 seconds) (player.body:body-settled-time body))) 1d-9))
      (player.body:body-evaluate body (+ 1 seconds))
      (is (< (abs (aref (player.body:body-pose body) i)) 1d-6) "at rest at the end"))))

(test settling-takes-longer-the-farther-the-joints-travel
  "The settling's length follows the travel, within its bounds."
  (is (< (player.body:settle-seconds 30) (player.body:settle-seconds 90) (player.body:settle-seconds 120)))
  (is (= player.body:*shortest-settle* (player.body:settle-seconds 0)))
  (is (= player.body:*longest-settle* (player.body:settle-seconds 1000))))

(test a-new-settled-pose-turns-the-channels-at-rest
  "BODY-SETTLE-TO moves the channels nobody drives to the new pose; a channel
still driven keeps its driver's angle."
  (let* ((body (settle-test-body))
         (i (elbow-index body))
         (shoulder (player.body:dof-index (player.body:body-skeleton body) 'player.body:l_shoulder :z))
         (pose (player.body:make-pose (player.body:body-skeleton body))))
    (setf (aref pose i) -30d0 (aref pose shoulder) 20d0)
    (bend-elbow body -90 nil)
    (player.body:body-settle-to body pose 1)
    (player.body:body-evaluate body 3)
    (is (< (abs (- 20 (aref (player.body:body-pose body) shoulder))) 1d-6))
    (is (< (abs (- -90 (aref (player.body:body-pose body) i))) 1d-6))))

;;;# Peedy: the issue's measurement

(defun settle-peedy ()
  "specs/peedy.lisp, loaded afresh."
  (first (load-spec (checkout-file "specs/peedy.lisp"))))

(defun settled-frame (spec events policy initial &key scripts)
  "Simulate EVENTS on SPEC from INITIAL under POLICY (silent) and show its last
frame: (values SIMULATION BODY)."
  (let* ((simulation (player::simulate spec :initial initial :events events :when-busy policy
                                            :silent t :stream nil :scripts scripts))
         (performance (player.performance::simulation-performance simulation)))
    (player.performance:performance-frame performance (player.performance::simulation-end simulation))
    (values simulation (player.performance:performance-body performance))))

(defun resting-channels (&rest bodies)
  "The pose indices no driver owns in any of BODIES."
  (loop for i below (length (player.body:body-pose (first bodies)))
        when (every (lambda (body) (null (svref (player.body::body-owners body) i))) bodies)
          collect i))

(defun pose-disagreements (a b &key (degrees 2))
  "The channels at rest in bodies A and B whose angles differ by more than
DEGREES, with rotation and position beyond 2 degrees and 1 cm, as a list."
  (append (loop for i in (resting-channels a b)
                for x = (aref (player.body:body-base a) i)
                for y = (aref (player.body:body-base b) i)
                when (> (abs (- x y)) degrees) collect (list i x y))
          (let ((turn (player.performance::rotation-degrees (player.body:property-value a 'player.body:rotation)
                                                            (player.body:property-value b 'player.body:rotation))))
            (and (> turn degrees) (list (list :rotation turn))))
          (let ((gap (player.body:vdistance (player.body:property-value a (quote position))
                                            (player.body:property-value b (quote position)))))
            (and (> gap 0.01) (list (list :position gap))))))

(test peedy-sits-the-same-after-a-preempted-flight-as-after-a-queued-one
  "The issue's measurement: flying, told to sit at 2 s, Peedy ends seated the
same way whether the sit preempted the lap or waited for it (before: 12
channels apart by up to 45 degrees, and turned 90 degrees)."
  (let ((spec (settle-peedy))
        (events '((ev-fly-to . 0) (ev-sit . 2))))
    (multiple-value-bind (preempted a) (settled-frame spec events :preempt '((posture . fly)))
      (multiple-value-bind (queued b) (settled-frame spec events :queue '((posture . fly)))
        (declare (ignore queued))
        (is (null (pose-disagreements a b)))
        (is (> (player.performance::simulation-end preempted)
               (player::controller-clock (player.performance::simulation-controller preempted)))
            "the frames go on while the body settles")))))

;;;# The property: the last pose depends only on the final state

(defun plannable-state (spec controller)
  "CONTROLLER's plannable variables as an alist, for :initial."
  (let ((names (mapcar #'player.spec::var-name (player.spec::plannable-variables spec))))
    (remove-if-not (lambda (entry) (member (car entry) names)) (player::controller-state controller))))

(defun fresh-start-problems (spec simulation body &key scripts)
  "How BODY, SIMULATION's last frame, differs from the pose SPEC's final
state gives from a fresh start (as for POSE-DISAGREEMENTS)."
  (let ((state (plannable-state spec (player.performance::simulation-controller simulation))))
    (multiple-value-bind (fresh fresh-body) (settled-frame spec '() :queue state :scripts scripts)
      (declare (ignore fresh))
      (pose-disagreements body fresh-body))))

(defparameter *settle-peedy-events*
  '(ev-fly-to ev-sit ev-fly ev-land ev-circle ev-stand ev-rest ev-hop ev-whistle
    ev-hello ev-preen ev-sleep ev-wake ev-nap ev-search ev-found ev-stop ev-applause ev-no ev-look
    ev-listen ev-think ev-voice)
  "Peedy's events the random streams draw from (the camera's and the timers' left out).")

(defun random-peedy-stream (prng)
  "A random stream of 2 to 6 of Peedy's events, arriving 0 to 2.5 s apart."
  (let ((time 0))
    (loop repeat (rs-between prng 2 6)
          collect (cons (rs-pick prng *settle-peedy-events*) time)
          do (incf time (/ (rs-below prng 11) 4)))))

(test peedys-last-pose-depends-only-on-his-final-state
  "Random streams of Peedy's events under each policy, from a random posture:
the last frame's channels at rest, rotation and position are within 2 degrees
\(and 1 cm) of what the final state gives from a fresh start."
  (let ((spec (settle-peedy)))
    (dolist (policy '(:queue :preempt :override :interleave))
      (loop for seed below (sweep-count 8 2)
            do (let* ((prng (make-rs-prng (+ seed (* 100 (length (string policy))))))
                      (initial (list (cons 'posture (rs-pick prng '(stand sit fly)))))
                      (events (random-peedy-stream prng)))
                 (multiple-value-bind (simulation body) (settled-frame spec events policy initial)
                   (let ((problems (fresh-start-problems spec simulation body)))
                     (is (null problems) "~A from ~S, ~S: ~S" policy initial events problems))))))))

(test random-placeholder-bodies-end-in-their-final-states-pose
  "The same property on random specs played by placeholders: their states all
settle to the rest pose, whatever gestures were cut."
  (loop for seed from 1 to (sweep-count 6 2)
        do (let* ((forms (random-spec seed :op-event-count 3))
                  (spec (define-spec 'settle-random forms :package (find-package '#:player-tests)))
                  (prng (make-rs-prng seed))
                  (names (event-names spec)))
             (unwind-protect
                  (dolist (policy '(:queue :preempt :override :interleave))
                    (let ((events (let ((time 0))
                                    (loop repeat 5
                                          collect (cons (rs-pick prng names) time)
                                          do (incf time (/ (rs-below prng 9) 4))))))
                      (multiple-value-bind (simulation body) (settled-frame spec events policy '())
                        (let ((problems (fresh-start-problems spec simulation body)))
                          (is (null problems) "seed ~D, ~A, ~S: ~S" seed policy events problems)))))
               (remove-spec 'settle-random)))))
