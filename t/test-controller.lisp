;;;; test-controller.lisp -- running controllers: failures, independence,
;;;; the presenter protocol, and redefinition at the REPL.

(in-package #:player-tests)

(def-suite* controller :in player-tests)

(test failure-aborts-rest-of-event-and-keeps-completed-ops
  (with-spec (spec failing
              (state-variable a boolean false)
              (state-variable b boolean false)
              (state-variable locked boolean true)
              (op set-a :add a)
              (op set-b :precond (not locked) :add b)
              (op after)
              (event ev :state a :state b :op after))
    (let ((c (make-controller (compile-spec spec))))
      (multiple-value-bind (ok goal) (send-event c 'ev)
        (is (null ok))
        (is (eq 'b goal)))
      (is (equal '((a . t) (b) (locked . t)) (controller-state c)))
      (is (equal '("(:event ev :time 0)"
                   "(:op set-a :script set-a :start 0 :end 1)"
                   "(:fail ev :goal b :time 1)"
                   "(:state (a . t) (b . nil) (locked . t))")
                 (trace-of c)))
      ;; still usable afterwards
      (is (equal '(nil b) (multiple-value-list (send-event c 'ev))))
      (is (= 1 (controller-clock c))))))

(test failed-op-precondition-reports-precondition-as-written
  (with-spec (spec op-fail
              (state-variable ready boolean false)
              (state-class prepared (ready))
              (op act :precond prepared)
              (event ev :op act))
    (let ((c (make-controller (compile-spec spec))))
      (is (equal '(nil prepared) (multiple-value-list (send-event c 'ev)))))))

(test controllers-of-one-machine-are-independent
  (with-spec (spec twins
              (state-variable up boolean false)
              (state-variable n integer 0)
              (op rise :add up)
              (event ev :state up :add (n 1)))
    (let* ((m (compile-spec spec))
           (one (make-controller m))
           (two (make-controller m :initial-state '((n . 10)))))
      (send-event one 'ev)
      (is (equal '((up . t) (n . 1)) (controller-state one)))
      (is (equal '((up) (n . 10)) (controller-state two)))
      (is (= 1 (controller-clock one)))
      (is (= 0 (controller-clock two))))))

(defclass counting-presenter (null-presenter)
  ((ops :initform '() :accessor counted-ops)))

(defmethod present-op ((p counting-presenter) op start)
  (push (list (op-name op) start) (counted-ops p))
  7)

(test presenter-durations-drive-the-clock
  (with-spec (spec durations
              (state-variable a boolean false)
              (op set-a :add a :duration 1)
              (op other)
              (event ev :state a :op other))
    (let* ((p (make-instance 'counting-presenter))
           (c (make-controller (compile-spec spec) :presenter p)))
      (send-event c 'ev)
      (is (equal '((set-a 0) (other 7)) (reverse (counted-ops p))))
      (is (= 14 (controller-clock c))))))

(test null-presenter-records-nothing
  (with-spec (spec quiet (state-variable a boolean false) (op set-a :add a) (event ev :state a))
    (let ((c (make-controller (compile-spec spec) :presenter (make-null-presenter))))
      (is (eq t (send-event c 'ev)))
      (is (eq t (state-value c 'a))))))

(test code-forms-see-the-running-controller
  (with-spec (spec code-sees
              (state-variable a boolean true)
              (event ev :code (setf (get 'code-sees 'value) (state-value *controller* 'a))))
    (setf (get 'code-sees 'value) :unset)
    (send-event (make-controller (compile-spec spec)) 'ev)
    (is (eq t (get 'code-sees 'value)))))

(test redefinition-and-recompile-keep-state
  (let ((forms-v1 '((state-variable posture string sit (sit stand))
                    (state-variable alert string snore (snore awake))
                    (op wake :add alert.awake)
                    (op standup :precond alert.awake :add posture.stand)
                    (autoscript alert snore (snore-loop))
                    (event ev-stand :state posture.stand)))
        (forms-v2 '((state-variable posture string sit (sit stand fly))
                    (state-variable alert string snore (snore awake))
                    (state-variable mood string calm (calm happy))
                    (op wake :add alert.awake)
                    (op takeoff :precond (alert.awake and posture.stand) :add posture.fly)
                    (op standup :precond alert.awake :add posture.stand)
                    (autoscript alert awake (blink))
                    (event ev-stand :state posture.stand)
                    (event ev-fly :state posture.fly))))
    (define-spec 'redefined forms-v1 :package (find-package '#:player-tests))
    (unwind-protect
         (let ((c (make-controller (compile-spec 'redefined))))
           (send-event c 'ev-stand)
           (is (equal '((posture . stand) (alert . awake)) (controller-state c)))
           (define-spec 'redefined forms-v2 :package (find-package '#:player-tests))
           (recompile c)
           (is (equal '((posture . stand) (alert . awake) (mood . calm)) (controller-state c)))
           (is (search "(:autoscript-start blink :var alert :value awake :time 2)"
                       (car (last (trace-of c)))))
           (is (eq t (send-event c 'ev-fly)))
           (is (eq 'fly (state-value c 'posture)))
           ;; a state the new spec cannot hold is refused, and nothing changes
           (define-spec 'redefined forms-v1 :package (find-package '#:player-tests))
           (signals state-transfer-error (recompile c))
           (is (eq 'fly (state-value c 'posture)))
           (is (eq t (send-event c 'ev-fly))))
      (remove-spec 'redefined))))

(test controller-is-small
  (with-spec (spec small (state-variable a boolean false) (state-variable n integer 0)
                         (op set-a :add a) (event ev :label x :state a))
    (let* ((m (compile-spec spec))
           (p (make-null-presenter))
           (before (sb-ext:get-bytes-consed)))
      (dotimes (i 1000) (make-controller m :presenter p))
      (is (< (/ (- (sb-ext:get-bytes-consed) before) 1000) 1024)))))
