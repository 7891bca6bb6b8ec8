;;;; test-properties.lisp -- property tests: random specs against a reference BFS.
;;;;
;;;; For each of *PROPERTY-SEEDS*, RANDOM-SPEC makes a spec and its model; the spec
;;;; is compiled once, and every event is sent from every plannable state, on a
;;;; fresh controller whose presenter records each top-level op (and the sub-ops of
;;;; each macro) with the state it started in. Each run must agree with
;;;; REFERENCE-DISTANCES: a shortest plan when there is one within :max-depth
;;;; (every op's precondition holding when it starts, the goal holding at the
;;;; end), and otherwise failure with the goal as written and the state unchanged.

(in-package #:player-tests)

(def-suite* properties :in player-tests)

(defparameter *property-seeds* (loop for seed from 1 to 240 collect seed)
  "The seeds of the random specs the property test checks with RANDOM-SPEC's
defaults (fixed, so failures reproduce).")

(defparameter *property-stress-options*
  '(:enum-probability 0.8 :precondition-probability 0.95 :macro-count 3 :goal-count 6)
  "RANDOM-SPEC options of the second, denser family: mostly enumerated
variables, nearly every op guarded, more macros and goals, so longer plans.")

(defparameter *property-stress-seeds* (loop for seed from 1 to 60 collect seed)
  "The seeds checked with *PROPERTY-STRESS-OPTIONS*.")

(defvar *property-statistics* nil
  "A plist describing the last property run: specs, states, runs, time...")

(defun property-cases ()
  "Every (SEED . RANDOM-SPEC-OPTIONS) the property test checks: in the fast
tier, 24 of the plain seeds and 6 of the stress ones."
  (append (mapcar #'list (sweep-sample *property-seeds* 24))
          (mapcar (lambda (seed) (cons seed *property-stress-options*))
                  (sweep-sample *property-stress-seeds* 6))))

;;; A presenter that records what ran

(defclass recording-presenter (null-presenter)
  ((model :initarg :model :reader recording-model)
   (depth :initform 0 :accessor recording-depth
          :documentation "How many macro-ops are running.")
   (log :initform '() :accessor recording-log
        :documentation "Top-level entries (KIND NAME STATE SUB-OP-NAMES), newest first."))
  (:documentation "Records each top-level op or macro-op with the model state it
started in, and, for a macro, the names of the sub-ops it ran (newest first)."))

(defun recorded-state (presenter)
  "The model state of the running controller."
  (model-state-from-alist (recording-model presenter) (controller-state *controller*)))

(defmethod present-op ((presenter recording-presenter) op start)
  (if (zerop (recording-depth presenter))
      (push (list :op (op-name op) (recorded-state presenter) '()) (recording-log presenter))
      (push (op-name op) (fourth (first (recording-log presenter)))))
  (call-next-method))

(defmethod present-macro-start ((presenter recording-presenter) op start)
  (if (zerop (recording-depth presenter))
      (push (list :macro (op-name op) (recorded-state presenter) '()) (recording-log presenter))
      (push (op-name op) (fourth (first (recording-log presenter)))))
  (incf (recording-depth presenter))
  (call-next-method))

(defmethod present-macro-end ((presenter recording-presenter) op start end)
  (decf (recording-depth presenter))
  (call-next-method))

;;; Checking one run

(defun state-text (model state)
  "STATE (a model state vector) as readable text: (v0 . t) (v1 . lo) ..."
  (let ((*package* (find-package '#:player-user)))
    (format nil "(~{~A~^ ~})"
            (loop for (name . value) in (model-state-alist model state)
                  collect (format nil "(~(~A . ~A~))" name value)))))

(defun check-recorded-plan (model event start log distance final)
  "NIL when LOG (the top-level entries of a successful run of EVENT from START,
oldest first) is a correct shortest plan of DISTANCE operators (plus the requested
op of an :op event) ending in FINAL; otherwise a string saying what is wrong."
  (destructuring-bind (key argument) (first (mevent-directives event))
    (let ((expected (+ distance (if (eq key :op) 1 0)))
          (state start))
      (unless (= (length log) expected)
        (return-from check-recorded-plan
          (format nil "ran ~D top-level op(s) ~S; the reference's shortest is ~D~:[~; plus the requested op~]"
                  (length log) (mapcar #'second log) distance (eq key :op))))
      (loop for (kind name at subs) in log
            for position from 1
            for op = (model-find-op model name)
            for lastp = (= position expected)
            do (flet ((wrong (control &rest arguments)
                        (return-from check-recorded-plan
                          (format nil "op ~D (~A): ~?" position name control arguments))))
                 (cond ((null op) (wrong "not an op of the model"))
                       ((not (eq kind (if (eq (mop-kind op) :macro) :macro :op)))
                        (wrong "presented as ~(~A~) but the model's kind is ~(~A~)" kind (mop-kind op)))
                       ((not (equalp at state))
                        (wrong "started in ~A but the ops before lead to ~A"
                              (state-text model at) (state-text model state)))
                       ((not (model-op-applicable-p op state))
                        (wrong "its precondition does not hold in ~A" (state-text model state)))
                       ((and (not (and lastp (eq key :op)))
                             (not (member op (model-plan-operators model))))
                        (wrong "a must-ask op inside a plan"))
                       ((and (eq key :op) lastp (not (eq name argument)))
                        (wrong "the last op should be the requested ~A" argument))
                       ((not (equal (reverse subs) (mop-seq op)))
                        (wrong "ran sub-ops ~S instead of its :seq ~S" (reverse subs) (mop-seq op))))
                 (setf state (model-apply-effects op state))))
      (cond ((not (equalp final state))
             (format nil "ended in ~A but the ops run lead to ~A"
                     (state-text model final) (state-text model state)))
            ((and (eq key :state) (not (model-eval argument final)))
             (format nil "the goal does not hold in the final state ~A" (state-text model final)))))))

(defun check-run (model machine event distance start)
  "Send EVENT from START on a fresh controller of MACHINE. Returns (VALUES
PROBLEM LOG): PROBLEM is NIL when the run agrees with the reference DISTANCE
(NIL: no plan within :max-depth), else a string."
  (let* ((presenter (make-instance 'recording-presenter :model model))
         (controller (make-controller machine :initial-state (model-state-alist model start)
                                              :presenter presenter)))
    (unless (equalp (model-state-from-alist model (controller-state controller)) start)
      (return-from check-run
        (values (format nil "the controller starts in ~S, not the requested state"
                        (controller-state controller))
                '())))
    (multiple-value-bind (result goal-form) (send-event controller (mevent-name event))
      (let ((final (model-state-from-alist model (controller-state controller)))
            (log (reverse (recording-log presenter))))
        (values
         (cond ((null distance)
                (cond (result
                       (format nil "succeeded (~S) with ~D op(s) ~S, but the reference finds no plan of at most ~D ops"
                               result (length log) (mapcar #'second log) (model-max-depth model)))
                      ((not (equal goal-form (model-goal-form model event)))
                       (format nil "failed naming goal ~S, not ~S" goal-form (model-goal-form model event)))
                      ((not (equalp final start))
                       (format nil "failed but changed the state to ~A" (state-text model final)))
                      (log (format nil "failed after running ops ~S" (mapcar #'second log)))))
               ((not (eq result t))
                (format nil "returned ~S ~S, but the reference has a plan of ~D op(s)"
                        result goal-form distance))
               (t (check-recorded-plan model event start log distance final)))
         log)))))

(defun event-goal-ast (model event)
  "The model goal EVENT's first directive plans for: its :state, or the
requested op's precondition (true when it has none)."
  (destructuring-bind (key argument) (first (mevent-directives event))
    (ecase key
      (:state argument)
      (:op (or (mop-precond (model-find-op model argument)) '(:const t))))))

(defun describe-problem (seed options forms model event start problem log)
  "The failure message for PROBLEM: seed, event, goal, start state, ops run, spec forms."
  (let ((*package* (find-package '#:player-user))
        (*print-pretty* nil))
    (format nil "seed ~D, event ~S from state ~A:~%  ~A~%  top-level ops run (with the state each started in): ~:[none~;~:*~{~A~^, ~}~]~%  reproduce: (player-tests::check-random-spec ~D~@[ :generator-options '~S~])~%  spec:~{~%    ~S~}"
            seed (render-event model event) (state-text model start) problem
            (mapcar (lambda (entry) (format nil "~A in ~A" (second entry) (state-text model (third entry))))
                    log)
            seed options forms)))

(defun check-random-spec (seed &key (max-problems 3) generator-options)
  "Check every event of (APPLY #'RANDOM-SPEC SEED GENERATOR-OPTIONS) from every
state. Returns (VALUES PROBLEMS STATISTICS): at most MAX-PROBLEMS failure
messages, and a plist. Each event of the spec must have a single :state or :op
directive."
  (multiple-value-bind (forms model) (apply #'random-spec seed generator-options)
    (let ((problems '()) (runs 0) (failing-runs 0) (macro-runs 0) (longest 0)
          (name (model-name model)))
      (flet ((note (event start problem log)
               (when (< (length problems) max-problems)
                 (push (describe-problem seed generator-options forms model event start problem log) problems))))
        (handler-case
            (unwind-protect
                 (let* ((spec (define-spec name forms :package (find-package '#:player-user)))
                        (machine (compile-spec spec))
                        (predecessors (reference-predecessors model))
                        (count (model-state-count model)))
                   (unless (= count (machine-state-count machine))
                     (note (first (model-events model)) (model-index-state model 0)
                           (format nil "the machine has ~D states; the model ~D"
                                   (machine-state-count machine) count)
                           '()))
                   (dolist (event (model-events model))
                     (let ((distances (reference-distances model (event-goal-ast model event)
                                                           :predecessors predecessors)))
                       (dotimes (index count)
                         (let ((start (model-index-state model index))
                               (distance (svref distances index)))
                           (incf runs)
                           (if distance
                               (setf longest (max longest distance))
                               (incf failing-runs))
                           (multiple-value-bind (problem log)
                               (handler-case (let ((*package* (find-package '#:player-user)))
                                               (check-run model machine event distance start))
                                 (error (e) (values (format nil "error: ~A" e) '())))
                             (when (find :macro log :key #'first) (incf macro-runs))
                             (when problem (note event start problem log))))))))
              (remove-spec name))
          (error (e)
            (push (let ((*package* (find-package '#:player-user)))
                    (format nil "seed ~D: error defining or compiling the spec: ~A~%  spec: ~S" seed e forms))
                  problems)))
        (values (nreverse problems)
                (list :states (model-state-count model) :events (length (model-events model))
                      :runs runs :failing-runs failing-runs :macro-runs macro-runs
                      :longest-plan longest))))))

;;; The tests

(test reference-bfs-on-a-hand-made-model
  "The reference BFS itself, on a model small enough to work out by hand."
  (let* ((a 0) (b 1) (c 2)
         (model (make-spec-model
                 :name 'hand-made :max-depth 30
                 :variables (vector (make-model-variable :name 'a)
                                    (make-model-variable :name 'b)
                                    (make-model-variable :name 'c :kind :enumerated
                                                         :domain (vector 'x 'y 'z)))
                 :ops (list (make-model-op :name 'set-a :effects `((,a . 1)))
                            (make-model-op :name 'set-b :precond `(:is ,a 1) :effects `((,b . 1)))
                            (make-model-op :name 'clear-a :effects `((,a . 0)))
                            (make-model-op :name 'ask-b :must-ask t :effects `((,b . 1)))
                            (make-model-op :name 'c-y :precond `(:is ,c 0) :effects `((,c . 1)))
                            (make-model-op :name 'c-z :precond `(:is ,c 1) :effects `((,c . 2)))
                            (make-model-op :name 'jump :kind :macro :precond `(:is ,b 1)
                                           :effects `((,c . 2)) :seq '(ask-b)))))
         (predecessors (reference-predecessors model)))
    (flet ((distance (goal a-value b-value c-value &key (max-depth 30))
             (svref (reference-distances model goal :max-depth max-depth :predecessors predecessors)
                    (model-state-index model (vector a-value b-value c-value)))))
      ;; State numbering round-trips and covers 2 * 2 * 3 states.
      (is (= 12 (model-state-count model)))
      (is (every (lambda (i) (= i (model-state-index model (model-index-state model i))))
                 (loop for i below 12 collect i)))
      (is (equalp #(1 0 2) (model-state-from-alist model '((a . t) (b . nil) (c . z)))))
      ;; The evaluator.
      (is (model-eval `(:and (:is ,a 1) (:not (:is ,c 0))) #(1 0 2)))
      (is (not (model-eval `(:or (:is ,b 1) (:const nil)) #(1 0 2))))
      ;; B: set-a then set-b; the must-ask ask-b is not a plan operator.
      (is (eql 2 (distance `(:is ,b 1) 0 0 0)))
      (is (eql 1 (distance `(:is ,b 1) 1 0 0)))
      (is (eql 0 (distance `(:is ,b 1) 0 1 2)))
      ;; (not A) and B: set-a, set-b, clear-a.
      (is (eql 3 (distance `(:and (:not (:is ,a 1)) (:is ,b 1)) 0 0 1)))
      (is (eql 1 (distance `(:and (:not (:is ,a 1)) (:is ,b 1)) 1 1 1)))
      ;; C = z: c-y, c-z; the macro jump does it in one step once B holds.
      (is (eql 2 (distance `(:is ,c 2) 0 0 0)))
      (is (eql 1 (distance `(:is ,c 2) 0 1 0)))
      (is (eql 1 (distance `(:is ,c 2) 0 0 1)))
      ;; Nothing leads back to C = x.
      (is (null (distance `(:is ,c 0) 1 1 2)))
      (is (null (distance '(:const nil) 0 0 0)))
      (is (eql 0 (distance '(:const t) 1 0 1)))
      ;; :max-depth bounds the plans.
      (is (null (distance `(:is ,b 1) 0 0 0 :max-depth 1)))
      (is (eql 1 (distance `(:is ,b 1) 1 0 0 :max-depth 1)))
      (is (null (distance `(:is ,b 1) 1 0 0 :max-depth 0)))
      (is (eql 0 (distance `(:is ,b 1) 1 1 0 :max-depth 0))))))

(test random-specs-are-deterministic-and-small
  "The same seed gives the same spec; every property spec stays within 1000 states."
  (is (equal (random-spec 17) (random-spec 17)))
  (is (not (equal (random-spec 17) (random-spec 18))))
  (is (every (lambda (entry)
               (<= (model-state-count (nth-value 1 (apply #'random-spec entry))) 1000))
             (property-cases))))

(test random-specs-match-reference-bfs
  "For every random spec, event and plannable state, the controller runs a
shortest plan with every precondition holding and reaches the goal, or fails
with the goal as written and the state unchanged, exactly as the reference BFS says."
  (let ((start (get-internal-real-time))
        (problems '()) (problem-count 0) (specs 0)
        (totals (list :states 0 :events 0 :runs 0 :failing-runs 0 :macro-runs 0)) (longest 0))
    (dolist (entry (property-cases))
      (destructuring-bind (seed . options) entry
        (multiple-value-bind (found statistics) (check-random-spec seed :generator-options options)
          (incf specs)
          (when found
            (incf problem-count)
            (setf problems (let ((all (append problems found)))
                             (subseq all 0 (min 3 (length all))))))
          (loop for (key value) on statistics by #'cddr
                do (if (eq key :longest-plan)
                       (setf longest (max longest value))
                       (incf (getf totals key) value))))))
    (setf *property-statistics*
          (list* :specs specs :longest-plan longest
                 :seconds (/ (float (- (get-internal-real-time) start)) internal-time-units-per-second)
                 totals))
    (is (>= specs (sweep-count 200 30)))
    ;; The generator must keep exercising the interesting cases.
    (is (plusp (getf totals :failing-runs)) "no run was expected to fail")
    (is (plusp (getf totals :macro-runs)) "no plan used a macro-op")
    (is (>= longest 4) "the longest plan had only ~D ops" longest)
    (is (null problems) "~D of ~D random specs disagree with the reference BFS; the first problems:~{~%~%~A~}"
        problem-count specs problems)))

(test random-spec-event-generator
  "Events from an :EVENT-GENERATOR (with :assign, :if, :label and :time
directives) render into a spec Player accepts, deterministically."
  (flet ((generator (prng model)
           (list (make-model-event
                  :name (rs-symbol "extra")
                  :directives `((:label ,(rs-symbol "l1"))
                                (:state ,(random-condition prng model))
                                (:assign 0 ,(rs-below prng 2))
                                (:if ,(random-expression prng model)
                                     (:assign 0 1) (:time 2))
                                (:time 1))))))
    (multiple-value-bind (forms model) (random-spec 5 :event-generator #'generator :max-depth 30)
      (is (equal forms (random-spec 5 :event-generator #'generator :max-depth 30)))
      (is (= 1 (count (rs-symbol "extra") (model-events model) :key #'mevent-name)))
      (let ((spec (define-spec (model-name model) forms :package (find-package '#:player-user))))
        (unwind-protect
             (let ((controller (make-controller (compile-spec spec) :presenter (make-null-presenter))))
               (is (member (send-event controller (rs-symbol "extra")) '(t nil))))
          (remove-spec (model-name model)))))))
