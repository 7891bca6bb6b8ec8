;;;; test-explain.lisp -- EXPLAIN-PLAN and `player explain` (issue 14, item 5):
;;;; the explained ops are the controller's, each names the literal it achieves,
;;;; and an unreachable goal says why.

(in-package #:player-tests)

(def-suite* explain :in player-tests)

(defun peedy-machine ()
  "Peedy (specs/peedy.lisp), compiled."
  (compile-spec (first (load-spec (checkout-file "specs/peedy.lisp")))))

(defun explained-ops (steps)
  "The names of the ops among explanation STEPS, in order."
  (mapcar #'explained-op-name (remove-if-not #'explained-op-p steps)))

(defun explanation-lines (steps)
  "STEPS as PRINT-EXPLANATION writes them, a list of lines."
  (lines (with-output-to-string (out) (print-explanation steps out))))

(defun has-line (fragment lines)
  "The first of LINES containing FRAGMENT, or NIL."
  (find-if (lambda (line) (search fragment line)) lines))

;;;# The controller's ops, as a presenter sees them

(defclass top-op-recorder (presenter)
  ((ops :initform '() :accessor recorded-ops)
   (depth :initform 0 :accessor macro-depth))
  (:documentation "Records the names of the ops an event runs, macro-ops as
one op (not their sub-ops): what an explanation lists."))

(defmethod present-op :before ((presenter top-op-recorder) op start)
  (declare (ignore start))
  (when (zerop (macro-depth presenter))
    (push (op-name op) (recorded-ops presenter))))

(defmethod present-macro-start ((presenter top-op-recorder) op start)
  (declare (ignore start))
  (when (zerop (macro-depth presenter))
    (push (op-name op) (recorded-ops presenter)))
  (incf (macro-depth presenter)))

(defmethod present-macro-end ((presenter top-op-recorder) op start end)
  (declare (ignore op start end))
  (decf (macro-depth presenter)))

(defun controller-ops (machine initial event)
  "(VALUES OPS SUCCEEDED): the ops a controller of MACHINE runs for EVENT from
INITIAL, and whether the event succeeded."
  (let* ((recorder (make-instance 'top-op-recorder))
         (controller (make-controller machine :initial-state initial :presenter recorder))
         (result (send-event controller event)))
    (values (reverse (recorded-ops recorder)) (eq result t))))

(defun peedy-states ()
  "Every plannable state of Peedy, as :initial alists."
  (let ((states (list '())))
    (loop for (var . values) in '((holding-note t nil) (posture fly stand sit)
                                  (alert snore sleep awake) (wing-at-ear t nil)
                                  (wearing-phones t nil) (music-playing t nil))
          do (setf states (loop for state in states
                                nconc (loop for value in values
                                            collect (acons var value state)))))
    states))

;;;# Peedy

(test explained-ops-are-the-controllers-from-every-state
  ;; Every event (but ev-idle, whose :if compares the clock) from every one of
  ;; Peedy's 144 states: the explained ops are those a controller runs, and the
  ;; explanation ends in an unreachable goal exactly when the event fails.
  (let ((machine (peedy-machine))
        (mismatches '())
        (checked 0))
    (dolist (event (remove 'player-user::ev-idle (event-names machine)))
      (dolist (initial (peedy-states))
        (let ((steps (explain-plan machine :initial initial :event event)))
          (multiple-value-bind (ops succeeded) (controller-ops machine initial event)
            (incf checked)
            (unless (and (equal ops (explained-ops steps))
                         (eq succeeded (notany #'explained-unreachable-p steps)))
              (push (list event initial ops (explained-ops steps)) mismatches))))))
    (is (= (* 37 144) checked))
    (is (null mismatches) "~D mismatches, e.g. ~S" (length mismatches) (first mismatches))))

(test explained-goal-is-the-events-plan
  ;; --goal G explains what an event with :state G does.
  (let ((machine (peedy-machine)))
    (loop for (goal . event) in '((player-user::listening . player-user::ev-listen)
                                  (player-user::alert.snore . player-user::ev-nap)
                                  (player-user::sit-op . player-user::ev-rest))
          do (dolist (initial (peedy-states))
               (let ((steps (explain-plan machine :initial initial :goal goal)))
                 (multiple-value-bind (ops succeeded) (controller-ops machine initial event)
                   (is (equal ops (explained-ops steps)) "~A from ~S" goal initial)
                   (is (eq succeeded (notany #'explained-unreachable-p steps)))))))))

(test each-op-names-the-literal-it-achieves
  (let* ((steps (explain-plan (peedy-machine) :initial '((posture . sit)) :goal 'player-user::posture.fly))
         (ops (remove-if-not #'explained-op-p steps))
         (lines (explanation-lines steps)))
    (is (equal '(player-user::standup player-user::take-off) (explained-ops steps)))
    (is (eq :precondition (explained-op-reason (first ops))))
    (is (eq 'player-user::take-off (explained-op-target (first ops))))
    (is (equal '(player-user::posture.stand) (explained-op-literals (first ops))))
    (is (eq :goal (explained-op-reason (second ops))))
    (is (string= "peedy, from holding-note=false posture=sit alert=awake wing-at-ear=false wearing-phones=false music-playing=false"
                 (first lines)))
    (is (equal '("goal posture.fly:"
                 "  1. standup        (posture: sit -> stand)  for take-off's precondition posture.stand"
                 "  2. take-off       (posture: stand -> fly)  achieves the goal posture.fly")
               (rest lines)))))

(test a-literal-for-a-later-step-names-that-step
  ;; From a doze on the perch with the wing at his ear, the headphones need
  ;; him awake, ears free and standing: each op names what it is for.
  (let ((lines (explanation-lines
                (explain-plan (peedy-machine) :initial '((alert . sleep) (posture . sit) (wing-at-ear . t))
                                              :goal 'player-user::listening))))
    (is (has-line "1. lower-wing     (wing-at-ear: true -> false)  for standup's precondition (not wing-at-ear), at step 3" lines) "~S" lines)
    (is (has-line "2. soft-wake      (alert: sleep -> awake)  for standup's precondition alert.awake" lines))
    (is (has-line "standup        (posture: sit -> stand)  for put-on-phones's precondition posture.stand" lines))
    (is (has-line "put-on-phones  (wearing-phones: false -> true)  achieves wearing-phones of the goal listening" lines))))

(test an-event-with-two-directives
  ;; ev-bad-speech is :state wing-at-ear, then :op huh: the second starts from
  ;; the state the first leaves.
  (let* ((steps (explain-plan (peedy-machine) :initial '((alert . snore) (posture . sit))
                                              :event "ev-bad-speech"))
         (lines (explanation-lines steps)))
    (is (equal '(player-user::hard-wake player-user::raise-wing player-user::huh) (explained-ops steps)))
    (is (equal '("event ev-bad-speech"
                 ":state wing-at-ear"
                 "  1. hard-wake      (alert: snore -> awake)  for raise-wing's precondition alert.awake"
                 "  2. raise-wing     (wing-at-ear: false -> true)  achieves the goal wing-at-ear"
                 ":op huh"
                 "  huh's precondition (alert.awake and wing-at-ear) already holds"
                 "  3. huh             requested by ev-bad-speech")
               (rest lines)))))

(test an-already-true-goal-says-so
  (let ((steps (explain-plan (peedy-machine) :goal '(and posture.stand alert.awake))))
    (is (null (explained-ops steps)))
    (is (explained-goal-holds (find-if #'explained-goal-p steps)))
    (is (equal '("goal (and posture.stand alert.awake) already holds: nothing to do")
               (rest (explanation-lines steps))))))

(test peedy-cannot-fly-asleep
  ;; A sleeping parrot cannot be flying (CHECK says so): in flight he is
  ;; awake, and only a doze (on the perch) sends him into deep sleep.
  (let* ((steps (explain-plan (peedy-machine) :goal '(and posture.fly alert.snore)))
         (lines (explanation-lines steps)))
    (is (explained-unreachable-p (car (last steps))))
    (is (has-line "goal (and posture.fly alert.snore) is unreachable from this state: preconditions block it" lines)
        "~S" lines)
    (is (has-line "  from holding-note=false posture=fly alert=awake wing-at-ear=false wearing-phones=false music-playing=false, the goal lacks alert.snore:" lines) "~S" lines)
    (is (has-line "    nod-off is blocked: its precondition needs alert.sleep" lines))
    (is (has-line "  (and 9 more reachable states as near)" lines))))

;;;# Unreachable goals in a small spec

(defmacro with-door-machine ((machine) &body body)
  "Run BODY with MACHINE a compiled spec whose door opens only with a key no op gives."
  `(with-machine (,machine door-without-key
                  (state-variable door string closed (closed open))
                  (state-variable key boolean false)
                  (state-variable inside boolean false)
                  (state-variable light boolean false)
                  (op open-door :precond key :add door.open)
                  (op enter :precond door.open :add inside)
                  (op wish-for-key :must-ask true :add key)
                  (op switch-on :add light)
                  (op ring :duration 0.5)
                  (event ev-enter :op ring :state light :state inside :op ring)
                  (event ev-key :state key))
     ,@body))

(test unreachable-literal-no-op-adds
  (with-door-machine (m)
    (let* ((steps (explain-plan m :goal 'key))
           (why (car (last steps))))
      (is (explained-unreachable-p why))
      (is (equal '("goal key is unreachable from this state: no op adds what it needs"
                   "  no op's effects set key (only must-ask wish-for-key, which plans cannot use)")
                 (rest (explanation-lines steps)))))))

(test unreachable-because-a-precondition-blocks
  (with-door-machine (m)
    (let ((lines (explanation-lines (explain-plan m :goal 'inside))))
      (is (equal '("goal inside is unreachable from this state: preconditions block it"
                   "  from door=closed key=false inside=false light=false, the goal lacks inside:"
                   "    enter is blocked: its precondition needs door.open"
                   "  from door=closed key=false inside=false light=true, the goal lacks inside:"
                   "    enter is blocked: its precondition needs door.open")
                 (rest lines))))
    ;; With the key, the door opens: a plan.
    (is (equal '(open-door enter) (explained-ops (explain-plan m :initial '((key . true)) :goal 'inside))))))

(test an-event-stops-at-its-unreachable-goal
  (with-door-machine (m)
    (let* ((steps (explain-plan m :event 'ev-enter))
           (lines (explanation-lines steps)))
      (is (equal '(ring switch-on) (explained-ops steps)))
      (is (equal "ev-enter stops here: the rest of its directives are skipped" (car (last lines))))
      (multiple-value-bind (ops succeeded) (controller-ops m '() 'ev-enter)
        (is (equal ops (explained-ops steps)))
        (is (not succeeded))))))

(test unreachable-because-an-op-undoes-a-literal
  ;; Setting A clears B, and B can be set only while A is false.
  (with-machine (m seesaw
                 (state-variable a boolean false)
                 (state-variable b boolean true)
                 (op set-a :add a :sub b)
                 (op set-b :precond (not a) :add b)
                 (event both :state (and a b)))
    (let ((lines (explanation-lines (explain-plan m :event 'both))))
      (is (has-line "from a=false b=true, the goal lacks a:" lines) "~S" lines)
      (is (has-line "set-a would undo b" lines))
      (is (has-line "from a=true b=false, the goal lacks b:" lines))
      (is (has-line "set-b is blocked: its precondition needs (not a)" lines)))))

(test a-contradictory-goal-never-holds
  (with-door-machine (m)
    (is (has-line "goal (and key (not key)) can never hold"
                  (explanation-lines (explain-plan m :goal '(and key (not key))))))))

;;;# Errors

(test explain-plan-errors
  (with-door-machine (m)
    (signals unknown-event (explain-plan m :event 'ev-nope))
    (signals unknown-name-error (explain-plan m :goal 'nosuch))
    (signals spec-error (explain-plan m :goal '(and key nosuch.value)))
    (signals unknown-name-error (explain-plan m :goal 'key :initial '((nosuch . t))))
    (signals domain-error (explain-plan m :goal 'inside :initial '((door . ajar))))
    (signals argument-error (explain-plan m))
    (signals argument-error (explain-plan m :goal 'key :event 'ev-key))
    (signals argument-error (explain-plan m :goal 'key :initial 'key))
    (signals argument-error (explain-plan 42 :goal 'key))
    (signals argument-error (print-explanation '(1 2)))))

(test explain-command
  (multiple-value-bind (out err code)
      (player-command "explain" "specs/peedy.lisp" "--initial" "posture=sit" "--goal" "posture.fly")
    (is (= 0 code))
    (is (string= "" err))
    (is (equal "  2. take-off       (posture: stand -> fly)  achieves the goal posture.fly"
               (car (last (lines out))))))
  (multiple-value-bind (out err code)
      (player-command "explain" "specs/peedy.lisp" "--initial" "alert=snore" "--event" "ev-search")
    (is (= 0 code) "~A" err)
    (is (has-line "1. hard-wake      (alert: snore -> awake)  for search's precondition alert.awake" (lines out))
        "~S" out))
  (multiple-value-bind (out err code)
      (player-command "explain" "specs/peedy.lisp" "--goal" "(and posture.fly alert.snore)")
    (is (= 0 code) "~A" err)
    (is (has-line "preconditions block it" (lines out)))))

(defun check-explain-error (expected-code fragment &rest arguments)
  "bin/player ARGUMENTS must fail with EXPECTED-CODE and one error line containing FRAGMENT."
  (multiple-value-bind (out err code) (apply #'player-command arguments)
    (declare (ignore out))
    (is (= expected-code code) "exit code ~A for ~S" code arguments)
    (is (eql 0 (search "player: error: " err)) "stderr ~S" err)
    (is (search fragment err) "stderr ~S lacks ~S" err fragment)
    (is (= 1 (count #\Newline err)) "stderr ~S is not one line" err)))

(test explain-command-exit-codes
  (check-explain-error 2 "exactly one of --goal EXPR and --event EV" "explain" "specs/peedy.lisp")
  (check-explain-error 2 "exactly one of --goal EXPR and --event EV"
                   "explain" "specs/peedy.lisp" "--goal" "posture.sit" "--event" "ev-search")
  (check-explain-error 2 "--goal takes one state expression" "explain" "specs/peedy.lisp" "--goal" "(and posture.sit")
  (check-explain-error 1 "unknown event ev-nope" "explain" "specs/peedy.lisp" "--event" "ev-nope")
  (check-explain-error 1 "unknown variable or state class perch" "explain" "specs/peedy.lisp" "--goal" "perch")
  (check-explain-error 1 "unknown variable nosuch in the initial state"
                   "explain" "specs/peedy.lisp" "--initial" "nosuch=1" "--goal" "posture.sit"))
