;;;; test-api-arguments.lisp -- issue 11, point 5, "Validated Lisp API": every
;;;; exported function checks its arguments and signals a PLAYER-ERROR naming
;;;; the function and the argument (an ARGUMENT-ERROR, or an older, more
;;;; specific class where one applies), never a raw TYPE-ERROR, CASE-FAILURE or
;;;; FLOATING-POINT-*; a rejected call changes nothing; and the event-symbol
;;;; cache holds only interned symbols.

(in-package #:player-tests)

(def-suite* api-arguments :in player-tests)

;;;# Hostile values

(declaim (ftype (function () (values double-float &optional)) nan))
(defun nan ()
  "A quiet double-float NaN: infinity minus itself, with the invalid trap masked.
(The infinity is read at run time: folded at compile time, SBCL would derive a
zero range for the result and check callers against it with a trapping compare.)"
  (let ((infinity (symbol-value 'sb-ext:double-float-positive-infinity)))
    (sb-int:with-float-traps-masked (:invalid)
      (- infinity infinity))))

(defparameter *big* (expt 10 399) "A 400-digit integer.")

(defun circular-list ()
  "A fresh circular list #1=(a b . #1#)."
  (let ((list (list 'a 'b)))
    (setf (cddr list) list)
    list))

(defun deep-list (depth)
  "A list nested DEPTH levels deep."
  (let ((list nil))
    (dotimes (i depth list) (setf list (list list)))))

(defun hostile-values ()
  "Values no API argument should choke on: odd numbers, odd lists, odd objects."
  (list (nan) sb-ext:double-float-positive-infinity sb-ext:double-float-negative-infinity
        *big* (- *big*) #c(1 2) 1d300 -1 0 1.5f0 "x" "" #\a nil t 'foo :foo (make-symbol "EV-SEARCH")
        (circular-list) '(a . b) (deep-list 3000) #(1 2) (make-hash-table) #'car
        (list (cons 'alert (nan)))))

;;;# Checking a table of bad calls

(defun condition-of (thunk)
  "The condition THUNK signals, or NIL."
  (handler-case (progn (funcall thunk) nil)
    (condition (c) c)))

(defun report-text (condition)
  "CONDITION's report, with float traps masked (a safety net: reports must not trap anyway)."
  (princ-to-string condition))

(defun check-rejected (form thunk class function argument fragment)
  "Check that THUNK (the code of FORM) signals a condition of CLASS; for an
ARGUMENT-ERROR, that it names FUNCTION and ARGUMENT, and that its report reads
\"FUNCTION: ARGUMENT must be ...\"; else that the report contains FRAGMENT."
  (let ((c (condition-of thunk)))
    (cond ((not (typep c class))
           (fail "~S signalled ~A (~A), not ~A" form (and c (type-of c))
                 (and c (ignore-errors (report-text c))) class))
          ((typep c 'argument-error)
           (let ((text (report-text c))
                 (head (format nil "~A: ~A must be " (player.base::lisp-text function) (player.base::lisp-text argument))))
             ;; Argument names are PLAYER's symbols: compare them by name.
             (is (string= (player.base::lisp-text function) (player.base::lisp-text (argument-error-function c)))
                 "~S names ~S, not ~S" form (argument-error-function c) function)
             (is (string= (player.base::lisp-text argument) (player.base::lisp-text (argument-error-argument c)))
                 "~S names ~S, not ~S" form (argument-error-argument c) argument)
             (is (eql 0 (search head text)) "~S: ~S should start with ~S" form text head)
             (is (< (length text) 600) "~S: the report is bounded" form)))
          (t (is (search fragment (report-text c)) "~S: ~S lacks ~S" form (report-text c) fragment)))))

(defmacro rejects (&body entries)
  "Each entry is (FUNCTION ARGUMENT FORM): FORM must signal an ARGUMENT-ERROR
naming FUNCTION and ARGUMENT; or (:class CLASS FRAGMENT FORM): a condition of
CLASS whose report contains FRAGMENT."
  `(progn
     ,@(loop for entry in entries
             collect (if (eq (first entry) :class)
                         (destructuring-bind (class fragment form) (rest entry)
                           `(check-rejected ',form (lambda () ,form) ',class nil nil ,fragment))
                         (destructuring-bind (function argument form) entry
                           `(check-rejected ',form (lambda () ,form) 'argument-error ',function ',argument nil))))))

;;;# Controllers

(defun controller-snapshot (controller)
  "What a rejected call must leave as it was: state, clock, and the trace so far."
  (list (controller-state controller) (controller-clock controller)
        (let ((presenter (controller-presenter controller)))
          (and (typep presenter 'trace-presenter) (length (trace-lines presenter))))))

(test issue-11-cases
  "The cases of issue 11 exactly: :at NaN, a string, a 400-digit bignum and
#C(1 2); :initial-state 'foo and a dotted list; :clock \"x\" and NaN."
  (let* ((machine (peedy-machine))
         (c (make-controller machine :initial-state '((alert . snore))))
         (before (progn (send-event c 'ev-search) (controller-snapshot c))))
    (is (= 400 (length (princ-to-string *big*))))
    (rejects
      (send-event :at (send-event c 'ev-search :at (nan)))
      (send-event :at (send-event c 'ev-search :at "x"))
      (send-event :at (send-event c 'ev-search :at *big*))
      (send-event :at (send-event c 'ev-search :at #c(1 2)))
      (make-controller :initial-state (make-controller machine :initial-state 'foo))
      (make-controller :initial-state (make-controller machine :initial-state '((a . b) . c)))
      (make-controller :clock (make-controller machine :clock "x"))
      (make-controller :clock (make-controller machine :clock (nan))))
    (is (equal before (controller-snapshot c)) "the rejected calls changed nothing")
    (is (search "send-event: :at must be a finite number of seconds"
                (report-text (condition-of (lambda () (send-event c 'ev-search :at (nan)))))))
    (is (search ", not nan" (report-text (condition-of (lambda () (send-event c 'ev-search :at (nan)))))))))

(test controller-api-rejects-bad-arguments
  (let* ((machine (peedy-machine))
         (c (make-controller machine :initial-state '((alert . snore))))
         (before (progn (send-event c 'ev-search) (controller-snapshot c))))
    (rejects
      ;; send-event
      (send-event controller (send-event 42 'ev-search))
      (send-event controller (send-event nil 'ev-search))
      (send-event event (send-event c 42))
      (send-event event (send-event c '(ev-search)))
      (send-event event (send-event c (circular-list)))
      (send-event :at (send-event c 'ev-search :at sb-ext:double-float-positive-infinity))
      (send-event :at (send-event c 'ev-search :at sb-ext:double-float-negative-infinity))
      (send-event :at (send-event c 'ev-search :at 1d16))
      (send-event :at (send-event c 'ev-search :at -1d16))
      (send-event :at (send-event c 'ev-search :at 'soon))
      (:class unknown-event "unknown event nope" (send-event c 'nope))
      (:class unknown-event "unknown event" (send-event c (make-symbol "NOPE")))
      (:class unknown-event "unknown event" (send-event c "no such event"))
      ;; state-value, controller-state
      (state-value controller (state-value 42 'alert))
      (state-value name (state-value c 42))
      (state-value name (state-value c '(alert)))
      (:class unknown-name-error "state-value: unknown variable nope" (state-value c 'nope))
      (controller-state controller (controller-state 'c))
      ;; recompile
      (recompile controller (recompile 42))
      (recompile spec (recompile c 42))
      (recompile spec (recompile c (circular-list)))
      (:class unknown-name-error "no spec named no-such-spec-anywhere" (recompile c 'no-such-spec-anywhere))
      ;; event-names
      (event-names machine (event-names 42))
      (event-names machine (event-names '(peedy))))
    (is (equal before (controller-snapshot c)) "the rejected calls changed nothing"))
  (let ((machine (peedy-machine)))
    (rejects
      (make-controller machine (make-controller 42))
      (make-controller machine (make-controller '(peedy)))
      (:class unknown-name-error "no spec named no-such-spec-anywhere" (make-controller 'no-such-spec-anywhere))
      (make-controller :initial-state (make-controller machine :initial-state (circular-list)))
      (make-controller :initial-state (make-controller machine :initial-state (list (cons 'alert (circular-list)))))
      (make-controller :initial-state (make-controller machine :initial-state '(alert)))
      (make-controller :initial-state (make-controller machine :initial-state '((42 . 1))))
      (make-controller :initial-state (make-controller machine :initial-state "alert=snore"))
      (:class unknown-name-error "unknown variable nope" (make-controller machine :initial-state '((nope . 1))))
      (:class domain-error "alert" (make-controller machine :initial-state '((alert . #c(1 2)))))
      (make-controller :initial-state (make-controller machine :initial-state (list (cons 'alert (nan)))))
      (make-controller :presenter (make-controller machine :presenter 42))
      (make-controller :presenter (make-controller machine :presenter nil))
      (make-controller :clock (make-controller machine :clock sb-ext:double-float-positive-infinity))
      (make-controller :clock (make-controller machine :clock *big*))
      (make-controller :clock (make-controller machine :clock #c(0 1))))))

(test registry-rejects-bad-arguments
  (rejects
    (find-spec name (find-spec 42))
    (find-spec name (find-spec '(peedy)))
    (find-spec name (find-spec (circular-list)))
    (:class unknown-name-error "no spec named no-such-spec-anywhere" (find-spec 'no-such-spec-anywhere))
    (remove-spec name (remove-spec 42))
    (remove-spec name (remove-spec '(a b)))
    (compile-spec spec (compile-spec 42))
    (compile-spec spec (compile-spec (nan)))
    (plan-spec spec (plan-spec 42))
    (plan-spec spec (plan-spec '(a b)))
    (check-spec machine (check-spec 42))
    (plans machine (plans 42 'x))
    (machine-goals machine (machine-goals 'peedy))
    (machine-state-count machine (machine-state-count "x"))
    (emit-c++ machine (emit-c++ 42 "/tmp/x/"))
    (emit-c++ directory (emit-c++ 'peedy 42))
    (run-c++-trace events (run-c++-trace 'peedy :events 'ev-search)))
  (is (null (find-spec 'no-such-spec-anywhere nil)))
  (with-spec (spec string-named-spec (state-variable a boolean false) (op set-a :add a) (event ev :state a))
    (is (eq spec (find-spec "string-named-spec")))
    (is (remove-spec "String-Named-Spec") "remove-spec takes a string, as find-spec does")
    (is (null (find-spec 'string-named-spec nil)))))

(test presenters-reject-bad-arguments
  (rejects
    (make-trace-presenter :stream (make-trace-presenter :stream 42))
    (make-trace-presenter :stream (make-trace-presenter :stream (make-string-input-stream "x")))
    (trace-lines presenter (trace-lines 42))
    (trace-lines presenter (trace-lines (make-null-presenter)))
    (clear-trace presenter (clear-trace nil))
    (trace-line-string line (trace-line-string 42))
    (trace-line-string line (trace-line-string '(event ev)))
    (trace-line-string line (trace-line-string (cons :event (circular-list))))
    (write-trace-line line (write-trace-line '(:state . 3) (make-broadcast-stream)))
    (write-trace-line stream (write-trace-line '(:event ev :time 0) 42)))
  (is (string= "(:event ev :time 0)" (trace-line-string '(:event player-user::ev :time 0)))))

;;;# The event-symbol cache

(test event-symbol-cache-holds-only-interned-symbols
  "Issue 11: 1M fresh uninterned symbols grew the cache by 1M entries (84 MB).
Here 100k, with a null presenter: the cache stays within the spec's events.
(The cache is copied on write, so it is read afresh each time.)"
  (let* ((machine (peedy-machine))
         (events (length (event-names machine)))
         (c (make-controller machine :presenter (make-null-presenter))))
    (flet ((cached () (hash-table-count (player.control::compiled-machine-event-symbols machine))))
      (dotimes (i 100000)
        (send-event c (make-symbol "EV-SEARCH")))
      (is (<= (cached) events) "~D entries for ~D events" (cached) events)
      (is (zerop (cached)) "no uninterned symbol is kept")
      (send-event c 'player-user::ev-search)
      (send-event c "ev-search")
      (is (= 1 (cached)) "an interned symbol is remembered, a string is not")
      (dolist (name (event-names machine))
        (send-event c name))
      (is (<= (cached) events)))))

(test send-event-with-a-symbol-conses-nothing-for-the-lookup
  (let* ((machine (peedy-machine))
         (c (make-controller machine :presenter (make-null-presenter))))
    (send-event c 'player-user::ev-search)
    (let ((cache (player.control::compiled-machine-event-symbols machine)))
      (let ((before (sb-ext:get-bytes-consed)))
        (dotimes (i 1000) (player.control::find-compiled-event c 'player-user::ev-search))
        (is (< (- (sb-ext:get-bytes-consed) before) 1024) "the cached lookup allocates nothing"))
      (is (= 1 (hash-table-count cache))))))

;;;# Animation engine

(test anim-rejects-bad-arguments
  (let ((control (player.body::make-constant-control 1))
        (q (player::quat))
        (nan-quat (player::quat (nan) 0d0 0d0 0d0)))
    (rejects
      (control-value time (control-value control "x"))
      (control-value time (control-value control (nan)))
      (control-value time (control-value control *big*))
      (control-value time (control-value control #c(1 2)))
      (control-value control (control-value 42 0))
      (parse-control form (parse-control (circular-list)))
      (parse-control form (parse-control (deep-list 3000)))
      (:class player::anim-control-error "vec3 takes 3 finite real numbers" (parse-control (list :vec3 1 (nan) 2)))
      (:class player::anim-control-error "finite" (parse-control (list :keys (list (cons (nan) 1) (cons 1 2)))))
      (:class player::anim-control-error "finite" (parse-control (list :keys (list (cons 0 *big*)))))
      (:class player::anim-control-error "frequency" (parse-control (list :noise :frequency (nan))))
      (make-keys-control keys (make-keys-control 42))
      (make-keys-control keys (make-keys-control (circular-list)))
      (:class player::anim-control-error "time" (make-keys-control (list (cons *big* 1))))
      (qslerp a (qslerp 42 q 0.5))
      (qslerp a (qslerp nan-quat q 0.5))
      (qslerp b (qslerp q "x" 0.5))
      (qslerp u (qslerp q q "x"))
      (qslerp u (qslerp q q (nan)))
      (qsquad q1 (qsquad nil q q q 0.5))
      (qsquad q2 (qsquad q 1 q q 0.5))
      (qsquad s1 (qsquad q q nan-quat q 0.5))
      (qsquad s2 (qsquad q q q 'x 0.5))
      (qsquad u (qsquad q q q q #c(0 1)))
      (world-transforms parents (world-transforms 42 #()))
      (world-transforms locals (world-transforms #(nil) #(42)))
      (world-transforms locals (world-transforms #(nil nil) (vector (player.body::identity-transform))))
      (world-transforms worlds (world-transforms #(nil) (vector (player.body::identity-transform)) #(42))))
    (is (typep (condition-of (lambda () (control-value control "x"))) 'player::anim-control-error)
        "a bad time is still an ANIM-CONTROL-ERROR too")
    (is (player.body::quat-p (qslerp q q 1/2)) "a rational U is fine")))

(test scenes-reject-bad-arguments
  (let* ((scene (make-instance 'player::scene))
         (box (player::add-object scene (make-instance 'player::scene-object :name 'box :kind :prop))))
    (rejects
      (find-object scene (find-object 42 'box))
      (find-object name (find-object scene 42))
      (add-object scene (add-object nil box))
      (add-object object (add-object scene 'box))
      (define-property object (define-property 42 'p :number 1))
      (define-property name (define-property box 42 :number 1))
      (define-property type (define-property box 'p :complex 1))
      (:class player::anim-error "a finite number" (define-property box 'p :number (nan)))
      (:class player::anim-error "a finite number" (define-property box 'p :number *big*))
      (property-value object (property-value 42 'position))
      (property-value name (property-value box 42))
      ((setf property-value) object (setf (property-value 42 'position) (player::vec3)))
      (:class player::anim-error "must be a vector" (setf (property-value box 'position) (player::vec3 (nan) 0d0 0d0)))
      (object-world-position object (object-world-position "box"))
      (object-world-transform object (object-world-transform nil))
      (reparent-object object (reparent-object 42 nil))
      (reparent-object new-parent (reparent-object box 42))
      (reparent-object new-parent (reparent-object box (cons box 42))))
    (is (eq box (find-object scene "BOX")))))

;;;# Bodies

(defun api-parrot () (load-skeleton 'parrot))
(defun api-humanoid () (load-skeleton 'humanoid))

(test skeletons-and-poses-reject-bad-arguments
  (let* ((skeleton (api-humanoid))
         (pose (make-pose skeleton))
         (joint (find-joint skeleton 'l_elbow))
         (transforms (player::pose-world-transforms skeleton pose))
         (nan-pose (let ((p (make-pose skeleton))) (setf (aref p 0) (nan)) p)))
    (rejects
      (load-skeleton name-or-path (load-skeleton 42))
      (load-skeleton name-or-path (load-skeleton ""))
      (load-skeleton name-or-path (load-skeleton "/tmp/*.lisp"))
      (load-skeleton name-or-path (load-skeleton '(humanoid)))
      (:class player::skeleton-error "unknown skeleton robot" (load-skeleton 'robot))
      (find-joint skeleton (find-joint 42 'l_elbow))
      (find-joint name (find-joint skeleton 42))
      (skeleton-role skeleton (skeleton-role nil :head))
      (skeleton-role role (skeleton-role skeleton 42))
      (make-pose skeleton (make-pose 'humanoid))
      (dof-index skeleton (dof-index 42 'l_elbow :x))
      (dof-index joint-name (dof-index skeleton 42 :x))
      (dof-index dof-name (dof-index skeleton 'l_elbow 42))
      (:class player::skeleton-error "no joint" (dof-index skeleton 'nope :x))
      (clamp-pose skeleton (clamp-pose 42 pose))
      (clamp-pose pose (clamp-pose skeleton 42))
      (clamp-pose pose (clamp-pose skeleton (make-array 3 :element-type 'double-float)))
      (clamp-pose pose (clamp-pose skeleton nan-pose))
      (clamp-pose pose (clamp-pose skeleton (coerce pose 'simple-vector)))
      (pose-within-limits-p skeleton (pose-within-limits-p "humanoid" pose))
      (pose-within-limits-p pose (pose-within-limits-p skeleton nan-pose))
      (pose-within-limits-p tolerance (pose-within-limits-p skeleton pose -1))
      (pose-within-limits-p tolerance (pose-within-limits-p skeleton pose (nan)))
      (pose-world-transforms skeleton (pose-world-transforms 42 pose))
      (pose-world-transforms pose (pose-world-transforms skeleton #(1 2 3)))
      (pose-world-transforms :placement (pose-world-transforms skeleton pose :placement 42))
      (pose-world-transforms :result (pose-world-transforms skeleton pose :result #(1)))
      (joint-world-position joint (joint-world-position transforms 'l_elbow))
      (joint-world-position transforms (joint-world-position #() joint)))
    (is (pose-within-limits-p skeleton pose))
    (is (= (length pose) (length (clamp-pose skeleton (copy-seq pose)))))))

(test arbitration-rejects-bad-arguments
  (let ((arbitrator (make-arbitrator)))
    (request-channels arbitrator 'a '(0 1) :priority 1)
    (rejects
      (make-arbitrator :blend-time (make-arbitrator :blend-time -1))
      (make-arbitrator :blend-time (make-arbitrator :blend-time (nan)))
      (make-arbitrator :clock (make-arbitrator :clock "x"))
      (request-channels arbitrator (request-channels 42 'a '(0)))
      (request-channels driver (request-channels arbitrator nil '(0) :priority 1))
      (request-channels channels (request-channels arbitrator 'b (circular-list) :priority 1))
      (request-channels :priority (request-channels arbitrator 'b '(0) :priority (nan)))
      (request-channels :priority (request-channels arbitrator 'b '(0) :priority "high"))
      (request-channels :time (request-channels arbitrator 'b '(0) :priority 1 :time (nan)))
      (request-channels :blend (request-channels arbitrator 'b '(0) :priority 1 :blend -1))
      (release-channels arbitrator (release-channels nil 'a '(0)))
      (release-channels driver (release-channels arbitrator nil '(0)))
      (release-channels channels (release-channels arbitrator 'a '(0 . 1)))
      (release-channels :time (release-channels arbitrator 'a '(0) :time *big*))
      (release-driver arbitrator (release-driver 42 'a))
      (release-driver driver (release-driver arbitrator nil))
      (release-driver :blend (release-driver arbitrator 'a :blend (nan)))
      (channel-owner arbitrator (channel-owner 42 0))
      (channel-blend-weight arbitrator (channel-blend-weight 42 0 0))
      (channel-blend-weight time (channel-blend-weight arbitrator 0 (nan)))
      (add-slave arbitrator (add-slave 42 'a 'b))
      (add-slave master (add-slave arbitrator nil 'b))
      (add-slave slave (add-slave arbitrator 'a nil))
      (:class player::arbitration-error "cycle" (add-slave arbitrator 'a 'a)))
    (is (eq 'a (channel-owner arbitrator 0)) "the rejected calls changed nothing")
    (is (equal '(0 1) (player.body::channels-of arbitrator 'a)))))

(defun api-body (&optional scene)
  "A humanoid body called BOB, in SCENE when given."
  (make-body 'bob 'humanoid :scene scene))

(test bodies-and-drivers-reject-bad-arguments
  (let* ((scene (make-instance 'player::scene))
         (body (api-body scene))
         (call (player::parse-motor-frame '(:test-constant :joint l_elbow :dof :x :angle -90)))
         (driver (make-driver call body 0))
         (other (make-driver call (api-body) 0)))
    (body-add-driver body driver)
    (body-evaluate body 1)
    (rejects
      (make-body name (make-body 42 'humanoid))
      (make-body skeleton (make-body 'bob2 42))
      (make-body :scene (make-body 'bob2 'humanoid :scene 42))
      (make-body :position (make-body 'bob2 'humanoid :position '(0 0 0)))
      (make-body :position (make-body 'bob2 'humanoid :position (player::vec3 (nan) 0d0 0d0)))
      (make-body :rotation (make-body 'bob2 'humanoid :rotation (player::quat 0d0 0d0 0d0 0d0)))
      (make-body :blend-time (make-body 'bob2 'humanoid :blend-time -1))
      (make-body name (make-body 'bob 'humanoid :scene scene))
      (body-add-driver body (body-add-driver 42 driver))
      (body-add-driver driver (body-add-driver body 42))
      (body-add-driver driver (body-add-driver body other))
      (body-stop-driver body (body-stop-driver nil driver 2))
      (body-stop-driver driver (body-stop-driver body nil 2))
      (body-stop-driver time (body-stop-driver body driver (nan)))
      (body-evaluate body (body-evaluate 'bob 2))
      (body-evaluate time (body-evaluate body (nan)))
      (body-evaluate time (body-evaluate body "2"))
      (body-evaluate time (body-evaluate body 0))
      (body-joint-position body (body-joint-position 42 'l_elbow))
      (body-joint-position joint-name (body-joint-position body 42))
      (:class player::skeleton-error "no joint nope" (body-joint-position body 'nope))
      (:class player::skeleton-error "no role" (body-joint-position body :tail))
      (resolve-target body (resolve-target '(:point 0 1 2) 42))
      (resolve-target target (resolve-target '(:point 0 1) body))
      (resolve-target target (resolve-target (list :point 0 (nan) 2) body))
      (resolve-target target (resolve-target (circular-list) body))
      (resolve-target pose (resolve-target '(:point 0 1 2) body #(1 2)))
      (make-driver call (make-driver 42 body 0))
      (make-driver body (make-driver call 42 0))
      (make-driver start (make-driver call body (nan)))
      (make-driver :stop (make-driver call body 2 :stop 1))
      (driver-arg driver (driver-arg 42 :angle))
      (driver-arg key (driver-arg driver "angle"))
      (describe-motor-function name (describe-motor-function "gaze"))
      (describe-motor-function stream (describe-motor-function :gaze 42))
      (:class player::motor-error "a motor call is written" (player::parse-motor-frame (circular-list)))
      (:class player::motor-error "a motor call is written" (player::parse-motor-frame (list :gaze :speed (circular-list))))
      (:class player::motor-error "must be" (player::parse-motor-frame (list :gaze :target (list :point 0 (nan) 1)))))
    (is (= 1 (player.body::body-time body)) "the rejected calls changed nothing")
    (is (< (abs (- -90 (aref (body-pose body) (dof-index (body-skeleton body) 'l_elbow :x)))) 1d-9))))

(test bvh-rejects-bad-arguments
  (let* ((skeleton (api-parrot))
         (pose (make-pose skeleton))
         (nan-pose (let ((p (make-pose skeleton))) (setf (aref p 0) (nan)) p))
         (out (make-broadcast-stream)))
    (rejects
      (write-bvh stream (write-bvh 42 skeleton (list pose)))
      (write-bvh stream (write-bvh (make-string-input-stream "") skeleton (list pose)))
      (write-bvh skeleton (write-bvh out 'parrot (list pose)))
      (write-bvh frames (write-bvh out skeleton (list #(1 2 3))))
      (write-bvh frames (write-bvh out skeleton (list nan-pose)))
      (write-bvh frames (write-bvh out skeleton (circular-list)))
      (write-bvh frames (write-bvh out skeleton 42))
      (write-bvh :frame-time (write-bvh out skeleton (list pose) :frame-time 0))
      (write-bvh :frame-time (write-bvh out skeleton (list pose) :frame-time (nan)))
      (write-bvh :placements (write-bvh out skeleton (list pose) :placements (list 42)))
      (write-bvh-file path (write-bvh-file 42 skeleton (list pose)))
      (write-bvh-file path (write-bvh-file "/tmp/*.bvh" skeleton (list pose)))
      (write-bvh-file frames (write-bvh-file "/tmp/player-never-written.bvh" skeleton (list 42))))
    (is (typep (condition-of (lambda () (write-bvh out skeleton 42))) 'player.body::bvh-error)
        "still a BVH-ERROR too")
    (is (not (probe-file "/tmp/player-never-written.bvh")))))

;;;# Scripts and performances

(test scripts-and-performances-reject-bad-arguments
  (let* ((library (elbow-library))
         (script (find-script library 'flex))
         (director (find-director library 'flex-then-grab))
         (performance (elbow-performance))
         (run (perform-script performance 'flex 0)))
    (performance-frame performance 1)
    (rejects
      (load-script-library path (load-script-library 42))
      (load-script-library path (load-script-library ""))
      (load-script-library path (load-script-library 'scripts))
      (:class player::script-error "no script library file" (load-script-library "/nonexistent/lib.lisp"))
      (find-script library (find-script 42 'flex))
      (find-script name (find-script library 42))
      (:class player::script-error "unknown script nope" (find-script library 'nope t))
      (find-director library (find-director nil 'flex-then-grab))
      (find-director name (find-director library '(flex)))
      (script-critical-time script (script-critical-time 'flex 'stroke))
      (script-critical-time name (script-critical-time script 42))
      (director-schedule director (director-schedule 'flex-then-grab library))
      (director-schedule library (director-schedule director 42))
      (director-schedule start (director-schedule director library (nan)))
      (make-performance library (make-performance 42 '((bob humanoid))))
      (make-performance characters (make-performance library 42))
      (make-performance characters (make-performance library '()))
      (make-performance characters (make-performance library '((bob))))
      (make-performance characters (make-performance library '((bob humanoid (0 0 0)))))
      (make-performance characters (make-performance library (circular-list)))
      (make-performance :seed (make-performance library '((bob humanoid)) :seed 1.5))
      (make-performance :blend-time (make-performance library '((bob humanoid)) :blend-time (nan)))
      (perform-script performance (perform-script 42 'flex 0))
      (perform-script name (perform-script performance 42 0))
      (perform-script start (perform-script performance 'flex (nan)))
      (perform-script start (perform-script performance 'flex "0"))
      (perform-script :stop (perform-script performance 'flex 0 :stop *big*))
      (perform-script :body (perform-script performance 'flex 0 :body 'nobody))
      (perform-director performance (perform-director nil 'flex-then-grab 0))
      (perform-director name (perform-director performance 1 0))
      (perform-director start (perform-director performance 'flex-then-grab #c(1 1)))
      (perform-director :body (perform-director performance 'flex-then-grab 0 :body 42))
      (stop-script-run performance (stop-script-run 42 run 1))
      (stop-script-run run (stop-script-run performance 42 1))
      (stop-script-run time (stop-script-run performance run (nan)))
      (performance-frame performance (performance-frame 42 1))
      (performance-frame time (performance-frame performance (nan)))
      (performance-frame time (performance-frame performance sb-ext:double-float-positive-infinity))
      (performance-body performance (performance-body 42))
      (performance-body name (performance-body performance 42)))
    (is (= 1 (length (player.performance::performance-runs performance))) "the rejected calls started nothing")
    (is (eq (find-object (performance-scene performance) 'bob) (performance-body performance)))))

(test presenters-and-simulations-reject-bad-arguments
  (with-elbow-spec (spec)
    (let* ((library (player.performance::parse-script-library-forms
                     (append *elbow-library-forms* '((defscript drop (:duration 0.5))))))
           (simulation (simulate spec :scripts library :events '(ev-flex) :fps 10)))
      (rejects
        (make-body-presenter spec (make-body-presenter 42 :scripts library))
        (make-body-presenter :scripts (make-body-presenter spec :scripts 42))
        (make-body-presenter :body (make-body-presenter spec :scripts library :body 42))
        (make-body-presenter :seed (make-body-presenter spec :scripts library :seed "0"))
        (make-body-presenter :stream (make-body-presenter spec :scripts library :stream 42))
        (make-body-presenter :blend-time (make-body-presenter spec :scripts library :blend-time -1))
        (simulate spec (simulate 42 :scripts library))
        (simulate :initial (simulate spec :scripts library :initial 'foo))
        (simulate :initial (simulate spec :scripts library :initial '((holding . t) . x)))
        (simulate :events (simulate spec :scripts library :events 'ev-flex))
        (simulate :events (simulate spec :scripts library :events '(42)))
        (simulate :events (simulate spec :scripts library :events (circular-list)))
        (simulate :fps (simulate spec :scripts library :fps 0))
        (simulate :fps (simulate spec :scripts library :fps (nan)))
        (simulate :fps (simulate spec :scripts library :fps 1d9))
        (simulate :seed (simulate spec :scripts library :seed (nan)))
        (:class unknown-event "unknown event ev-nope" (simulate spec :scripts library :events '(ev-flex ev-nope)))
        (simulation-frame-count simulation (simulation-frame-count 42))
        (map-simulation-frames function (map-simulation-frames 42 simulation))
        (map-simulation-frames simulation (map-simulation-frames #'list 42))
        (write-simulation simulation (write-simulation nil))
        (write-simulation :bvh (write-simulation simulation :bvh 42))
        (write-simulation :frames (write-simulation simulation :frames ""))
        (render-simulation simulation (render-simulation 42))
        (render-simulation :out (render-simulation simulation :out 42))
        (render-simulation :fps (render-simulation simulation :fps -1))
        (render-simulation :video (render-simulation simulation :video 42))
        (render-simulation :progress (render-simulation simulation :progress 42))
        (render-simulation :antialias (render-simulation simulation :antialias :super))
        (view-spec spec (view-spec 42))
        (view-spec :initial (view-spec spec :scripts library :initial 'foo))
        (view-spec :frames (view-spec spec :scripts library :frames 0))
        (view-spec :screenshot (view-spec spec :scripts library :screenshot 42))
        (view-spec :keys (view-spec spec :scripts library :keys 'foo))
        (view-spec :keys (view-spec spec :scripts library :keys (list (cons (nan) #\a))))
        (view-spec :seed (view-spec spec :scripts library :seed 1.5)))
      (is (plusp (simulation-frame-count simulation))))))

(test png-rejects-bad-arguments
  (let ((pixels (make-array 4 :element-type '(unsigned-byte 8) :initial-element 0)))
    (rejects
      (write-png path (write-png 42 1 1 pixels))
      (write-png path (write-png "" 1 1 pixels))
      (write-png :filter (write-png "/tmp/player-never-written.png" 1 1 pixels :filter :paeth))
      (png-octets :filter (png-octets 1 1 pixels :filter 42))
      (:class render-error "1x1" (png-octets (nan) 1 pixels))
      (:class render-error "channels" (png-octets 1 1 pixels :channels (circular-list))))
    (is (not (probe-file "/tmp/player-never-written.png")))
    (is (plusp (length (png-octets 1 1 pixels))))))

(test gl-bindings-reject-bad-arguments
  "Checked before any GL call, so no context is needed."
  (rejects
    (make-msaa-target width (make-msaa-target 0 10))
    (make-msaa-target height (make-msaa-target 10 (nan)))
    (make-msaa-target samples (make-msaa-target 10 10 -1))
    (bind-msaa-target target (bind-msaa-target 42))
    (resolve-msaa-target target (resolve-msaa-target nil))
    (delete-msaa-target target (delete-msaa-target "target"))
    (read-frame-pixels width (read-frame-pixels 1.5 10))
    (read-frame-pixels height (read-frame-pixels 10 *big*))
    (read-frame-pixels :channels (read-frame-pixels 10 10 :channels 2))
    (compile-shader-program vertex-source (compile-shader-program 42 ""))
    (compile-shader-program fragment-source (compile-shader-program "" nil))
    (load-gl-functions getter (load-gl-functions 42))
    (osmesa-proc-address name (osmesa-proc-address 'gl-clear))
    (glfw-proc-address name (glfw-proc-address 42))))

;;;# No raw conditions, whatever the value

(defun raw-condition-p (condition)
  "Is CONDITION one the API must never let out: anything but a PLAYER-ERROR?"
  (and condition (not (typep condition 'player-error))))

(defun try-everywhere (name function good-arguments &key snapshot)
  "Call FUNCTION with GOOD-ARGUMENTS, each in turn replaced by each hostile
value; check that every call returns or signals a PLAYER-ERROR whose report
can be printed, and, given SNAPSHOT (a function of no arguments), that what it
returns is the same after each rejected call as before it.  NAME is for messages."
  (loop for position from 0 below (length good-arguments)
        do (dolist (value (hostile-values))
             (let* ((arguments (let ((copy (copy-list good-arguments)))
                                 (setf (nth position copy) value)
                                 copy))
                    (before (and snapshot (funcall snapshot)))
                    (c (condition-of (lambda () (apply function arguments)))))
               (when (and snapshot c)
                 (is (equal before (funcall snapshot)) "~A, argument ~D = ~A: the rejected call changed the state"
                     name position (player.base::bounded-lisp-text value 40)))
               (when (raw-condition-p c)
                 (fail "~A, argument ~D = ~A: a raw ~A: ~A" name position
                       (player.base::bounded-lisp-text value 40) (type-of c)
                       (ignore-errors (player.base::bounded-lisp-text (princ-to-string c) 200))))
               (when (typep c 'player-error)
                 (is (stringp (ignore-errors (report-text c))) "~A: the report of ~A prints" name (type-of c)))))))

(test no-raw-conditions-from-the-controller-api
  (let* ((machine (peedy-machine))
         (c (make-controller machine :presenter (make-trace-presenter) :initial-state '((alert . snore)))))
    (send-event c 'player-user::ev-search)
    (try-everywhere "send-event" (lambda (controller event at) (send-event controller event :at at))
                    (list c 'player-user::ev-nope 0)
                    :snapshot (lambda () (controller-snapshot c)))
    (is (equal (controller-snapshot c) (progn (ignore-errors (send-event c 'player-user::ev-nope))
                                              (controller-snapshot c))))
    (try-everywhere "state-value" #'state-value (list c 'alert))
    (try-everywhere "controller-state" #'controller-state (list c))
    (try-everywhere "event-names" #'event-names (list machine))
    (try-everywhere "find-spec" #'find-spec (list 'peedy))
    (try-everywhere "make-controller"
                    (lambda (machine initial presenter clock)
                      (make-controller machine :initial-state initial :presenter presenter :clock clock))
                    (list machine '((alert . snore)) (make-null-presenter) 0))
    (let ((before (controller-snapshot c)))
      (try-everywhere "recompile" (lambda (spec) (recompile c spec)) (list 'no-such-spec-anywhere)
                      :snapshot (lambda () (controller-snapshot c)))
      (is (eq machine (controller-machine c)) "failed recompiles kept the machine")
      (is (equal before (controller-snapshot c)) "and the state"))))

(test no-raw-conditions-from-the-animation-and-body-api
  (let* ((skeleton (api-humanoid))
         (pose (make-pose skeleton))
         (control (player.body::make-constant-control 1))
         (arbitrator (make-arbitrator))
         (library (elbow-library))
         (performance (elbow-performance)))
    (try-everywhere "control-value" #'control-value (list control 0))
    (try-everywhere "parse-control" #'parse-control (list 1))
    (try-everywhere "make-keys-control" #'make-keys-control (list '((0 . 1))))
    (try-everywhere "qslerp" #'qslerp (list (player::quat) (player::quat) 0.5))
    (try-everywhere "find-joint" #'find-joint (list skeleton 'l_elbow))
    (try-everywhere "dof-index" #'dof-index (list skeleton 'l_elbow :x))
    (try-everywhere "make-pose" #'make-pose (list skeleton))
    (try-everywhere "clamp-pose" #'clamp-pose (list skeleton pose))
    (try-everywhere "pose-within-limits-p" #'pose-within-limits-p (list skeleton pose 0))
    (try-everywhere "request-channels"
                    (lambda (arbitrator driver channels priority time)
                      (request-channels arbitrator driver channels :priority priority :time time))
                    (list arbitrator 'd '(0) 1 0))
    (try-everywhere "channel-blend-weight" #'channel-blend-weight (list arbitrator 0 0))
    (try-everywhere "load-skeleton" #'load-skeleton (list 'parrot))
    (try-everywhere "parse-motor-frame" #'player::parse-motor-frame (list '(:gaze :target (:point 0 1 2))))
    (try-everywhere "make-body" (lambda (name skeleton position)
                                  (make-body name skeleton :position position))
                    (list 'bob 'humanoid (player::vec3)))
    (try-everywhere "find-script" #'find-script (list library 'flex))
    (try-everywhere "perform-script" #'perform-script (list performance 'flex 0))
    (try-everywhere "performance-frame" #'performance-frame (list performance 0.5))))
