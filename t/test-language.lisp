;;;; test-language.lisp -- every form of the spec language, parsed and run.

(in-package #:player-tests)

(def-suite* language :in player-tests)

(defun run-events (spec events &key initial-state)
  "Compile SPEC, send EVENTS in order, return (VALUES CONTROLLER RESULTS)."
  (let ((c (make-controller (compile-spec spec) :initial-state initial-state)))
    (values c (mapcar (lambda (e) (send-event c e)) events))))

(defun op-lines (controller)
  "The (:op ...) trace lines of CONTROLLER as (NAME START END)."
  (loop for line in (trace-lines (controller-presenter controller))
        when (eq (first line) :op)
          collect (list (second line) (getf (cddr line) :start) (getf (cddr line) :end))))

(test state-variables-of-every-type
  (with-spec (spec vars
              (state-variable flag boolean true)
              (state-variable mood string happy (happy sad))
              (state-variable level integer 2 (1 2 3))
              (state-variable count integer 5)
              (state-variable speed float 1.5)
              (time-variable heard (ev))
              (event ev))
    (let ((c (make-controller (compile-spec spec))))
      (is (equal '((flag . t) (mood . happy) (level . 2) (count . 5) (speed . 1.5d0) (heard))
                 (mapcar (lambda (pair) (cons (intern (symbol-name (car pair)) :player-tests)
                                              (cdr pair)))
                         (controller-state c))))
      (is (eq t (state-value c 'flag)))
      (is (= 2 (state-value c 'level)))
      (is (null (state-value c 'heard))))))

(test boolean-words-and-quoted-paper-style
  (with-spec (spec words
              (state-variable 'a 'boolean 'false)
              (state-variable b boolean t)
              (state-variable c boolean nil)
              (state-variable 'posture 'string 'stand '(fly stand sit))
              (op 'go :precond '(b and (not c)) :add 'a)
              (event ev :state a))
    (let ((c (make-controller (compile-spec spec))))
      (is (eq t (send-event c 'ev)))
      (is (equalp '((go 0 1)) (op-lines c))))))

(test enumerated-literals-and-infix
  (with-spec (spec enum
              (state-variable posture string sit (fly stand sit))
              (state-variable awake boolean false)
              (op wake :add awake)
              (op standup :precond (awake and posture.sit) :add posture.stand)
              (op takeoff :precond (posture.stand or posture.sit) :add posture.fly)
              (event ev-stand :state posture.stand)
              (event ev-fly :state (and posture.fly awake)))
    (multiple-value-bind (c results) (run-events spec '(ev-stand ev-fly))
      (is (equal '(t t) results))
      (is (equal '(wake standup takeoff) (mapcar #'first (op-lines c))))
      (is (eq 'fly (state-value c 'posture))))))

(test state-class-later-elements-win
  (with-spec (spec classes
              (state-variable posture string stand (stand sit))
              (state-variable awake boolean true)
              (state-class base (awake posture.stand))
              (state-class seated (base posture.sit))
              (op sit :precond base :add posture.sit)
              (op doze :precond seated :sub awake)
              (event ev :op doze))
    (multiple-value-bind (c results) (run-events spec '(ev))
      (is (equal '(t) results))
      ;; seated = awake and sit (posture.sit overrides base's posture.stand)
      (is (equal '(sit doze) (mapcar #'first (op-lines c))))
      (is (equal (list 'sit nil)
                 (list (state-value c 'posture) (state-value c 'awake)))))))

(test class-inheritance-is-deep-and-multiple
  (with-spec (spec deep
              (state-variable a boolean false)
              (state-variable b boolean false)
              (state-variable d boolean false)
              (state-class ca (a))
              (state-class cb (b))
              (state-class cab (ca cb))
              (state-class all (cab d))
              (op set-a :add a) (op set-b :add b) (op set-d :add d)
              (event ev :state all))
    (multiple-value-bind (c results) (run-events spec '(ev))
      (is (equal '(t) results))
      (is (equal '(set-a set-b set-d)
                 (sort (mapcar #'first (op-lines c)) #'string< :key #'symbol-name))))))

(test op-options
  (with-spec (spec opts
              (state-variable x boolean false)
              (state-variable y boolean false)
              (op scripted :script some-script :add x :duration 2.5)
              (op directed :director my-director :precond x :add y :duration 0.5)
              (op coded :code (setf (get 'opts 'ran) t) :duration 0)
              (op asked :must-ask true :c++ "hook();")
              (event ev :state y :op coded :op asked))
    (setf (get 'opts 'ran) nil)
    (multiple-value-bind (c results) (run-events spec '(ev))
      (is (equal '(t) results))
      (is (equalp '((scripted 0 2.5d0) (directed 2.5d0 3.0d0) (coded 3.0d0 3.0d0) (asked 3.0d0 4.0d0))
                 (op-lines c)))
      (is (eq t (get 'opts 'ran)))
      (is (equal '("(:op scripted :script some-script :start 0 :end 2.5)"
                   "(:op directed :director my-director :start 2.5 :end 3)"
                   "(:op coded :code t :start 3 :end 3)")
                 (subseq (remove-if-not (lambda (l) (search "(:op" l)) (trace-of c)) 0 3))))))

(test must-ask-ops-are-not-planned
  (with-spec (spec asked
              (state-variable x boolean false)
              (op secret :must-ask t :add x)
              (event ev-state :state x)
              (event ev-op :op secret))
    (let ((c (make-controller (compile-spec spec))))
      (is (null (send-event c 'ev-state)))
      (is (eq t (send-event c 'ev-op)))
      (is (eq t (state-value c 'x))))))

(test macro-op-runs-sequence-and-applies-declared-effects
  (with-spec (spec macro
              (state-variable alert string snore (snore awake))
              (state-variable fluffed boolean false)
              (op snort :duration 0.5)
              (op exhale :add fluffed)
              (op focus :duration 2)
              (macro-op hard-wake :precond alert.snore :add alert.awake
                        :seq (:op snort :op exhale :label l :time (+ (label l) 1) :op focus))
              (event ev :state alert.awake))
    (multiple-value-bind (c results) (run-events spec '(ev))
      (is (equal '(t) results))
      (is (equalp '((hard-wake 0 4.5d0) (snort 0 0.5d0) (exhale 0.5d0 1.5d0) (focus 2.5d0 4.5d0))
                 (op-lines c)))
      ;; the sub-op's own change is internal; the declared effect is what stays
      (is (equal (list 'awake nil)
                 (list (state-value c 'alert) (state-value c 'fluffed))))
      (is (= 4.5d0 (controller-clock c))))))

(test autoscripts-start-and-stop-with-values
  (with-spec (spec autos
              (state-variable alert string snore (snore awake))
              (state-variable note boolean false)
              (op wake :add alert.awake)
              (op nap :add alert.snore)
              (autoscript alert snore (snore-loop breathe))
              (autoscript alert awake (blink))
              (event ev-wake :state alert.awake)
              (event ev-nap :state alert.snore))
    (multiple-value-bind (c results) (run-events spec '(ev-wake ev-nap))
      (is (equal '(t t) results))
      (is (equal '("(:autoscript-start snore-loop :var alert :value snore :time 0)"
                   "(:autoscript-start breathe :var alert :value snore :time 0)"
                   "(:event ev-wake :time 0)"
                   "(:op wake :script wake :start 0 :end 1)"
                   "(:autoscript-stop snore-loop :var alert :value snore :time 1)"
                   "(:autoscript-stop breathe :var alert :value snore :time 1)"
                   "(:autoscript-start blink :var alert :value awake :time 1)"
                   "(:state (alert . awake) (note . nil))"
                   "(:event ev-nap :time 1)"
                   "(:op nap :script nap :start 1 :end 2)"
                   "(:autoscript-stop blink :var alert :value awake :time 2)"
                   "(:autoscript-start snore-loop :var alert :value snore :time 2)"
                   "(:autoscript-start breathe :var alert :value snore :time 2)"
                   "(:state (alert . snore) (note . nil))")
                 (trace-of c))))))

(test labels-and-times-schedule-ops
  (with-spec (spec timing
              (state-variable x boolean false)
              (op bow :duration 2)
              (op cam)
              (op sit)
              (op late)
              (event ev :op bow :label a :time (+ (label a) 3) :op cam
                        :time (+ (label a) 5) :op sit :time 1 :op late))
    (multiple-value-bind (c results) (run-events spec '(ev ev))
      (is (equal '(t t) results))
      (is (equal '((bow 0 2) (cam 5 6) (sit 7 8) (late 1 2)
                   (bow 8 10) (cam 13 14) (sit 15 16) (late 9 10))
                 (mapcar (lambda (l) (list (first l) (round (second l)) (round (third l))))
                         (op-lines c))))
      (is (= 16 (controller-clock c))))))

(test if-add-sub-and-numbers
  (with-spec (spec numbers
              (state-variable count integer 0)
              (state-variable gain float 0.5)
              (state-variable mood string calm (calm wild))
              (state-variable lit boolean false)
              (time-variable heard (ev-hear))
              (op cheer)
              (event ev-hear :add (count 1) :sub (gain 0.25)
                             :if ((>= count 2) :add mood.wild :add lit :op cheer)
                             :if ((and mood.wild (< gain 0)) :sub lit))
              (event ev-check :if ((> (now) (+ heard 1)) :op cheer)))
    (multiple-value-bind (c results) (run-events spec '(ev-hear ev-hear ev-hear))
      (is (equal '(t t t) results))
      (is (= 3 (state-value c 'count)))
      (is (= -0.25d0 (state-value c 'gain)))
      (is (eq 'wild (state-value c 'mood)))
      (is (null (state-value c 'lit)))
      (is (equal '(cheer cheer) (mapcar #'first (op-lines c))))
      (is (= 1 (state-value c 'heard)))
      (send-event c 'ev-check :at 1.5)
      (is (= 2 (length (op-lines c))))
      (send-event c 'ev-check :at 2.5)
      (is (= 3 (length (op-lines c)))))))

(test unset-time-variable-compares-false
  (with-spec (spec unset
              (time-variable heard (ev-hear))
              (state-variable n integer 0)
              (event ev-hear)
              (event ev-check :if ((< heard 100) :add (n 1)) :if ((/= heard 100) :add (n 10))))
    (let ((c (make-controller (compile-spec spec))))
      (send-event c 'ev-check)
      (is (= 10 (state-value c 'n)))
      (send-event c 'ev-hear)
      (send-event c 'ev-check)
      (is (= 21 (state-value c 'n))))))

(test spec-options-and-docstring
  (with-spec (spec documented "A documented spec." (:max-depth 3)
              (state-variable x boolean false))
    (is (string= "A documented spec." (spec-documentation spec)))
    (is (= 3 (spec-max-depth spec)))))

(test defspec-macro-and-find-spec
  (eval '(defspec player-user::macro-defined (state-variable x boolean false)))
  (unwind-protect
       (progn (is (eq 'player-user::macro-defined (spec-name (find-spec 'macro-defined))))
              (is (eq (find-spec "macro-defined") (find-spec 'macro-defined))))
    (remove-spec 'macro-defined)))
