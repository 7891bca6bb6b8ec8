;;;; test-peedy.lisp -- specs/peedy.lisp: the paper-sized Peedy controller, its
;;;; counts, and the papers' scenario (asleep; ev-search twice; ev-bad-speech;
;;;; ev-thanks) traced op by op.

(in-package #:player-tests)

(def-suite* peedy :in player-tests)

(defun peedy-spec ()
  "Load specs/peedy.lisp afresh and return the spec it defines."
  (let ((specs (load-spec (checkout-file "specs/peedy.lisp"))))
    (assert (= 1 (length specs)))
    (first specs)))

(defun peedy-controller (&rest initial-state)
  "A controller of a freshly compiled Peedy; INITIAL-STATE is an alist of overrides."
  (make-controller (compile-spec (peedy-spec)) :initial-state initial-state))

(defun asleep-peedy ()
  "Peedy in the papers' starting state: deep sleep, sitting."
  (peedy-controller '(alert . snore) '(posture . sit)))

(defun peedy-event-lines (controller event &rest args)
  "Send EVENT (with SEND-EVENT's ARGS) and return the trace lines it produced, as text.
Fails the test when the event does not succeed."
  (let ((before (length (trace-of controller))))
    (is (eq t (apply #'send-event controller event args)) "~A failed" event)
    (nthcdr before (trace-of controller))))

(defun peedy-ops (lines)
  "The (:op ...) lines among trace LINES (raw lists) as (NAME START END), names as strings."
  (loop for line in lines
        when (eq (first line) :op)
          collect (list (string-downcase (symbol-name (second line)))
                        (getf (cddr line) :start) (getf (cddr line) :end))))

(defun peedy-raw-lines (controller)
  "CONTROLLER's trace lines as lists."
  (trace-lines (controller-presenter controller)))

(defun peedy-value (controller name)
  "Variable NAME's value in CONTROLLER as lower-case text (\"t\"/\"nil\" for booleans)."
  (player.base::lisp-text (state-value controller name)))

(defun peedy-names (things)
  "THINGS (symbols) as sorted lower-case strings."
  (sort (mapcar (lambda (s) (string-downcase (symbol-name s))) things) #'string<))

;;; The declarations: the paper's sizes and names

(test peedy-has-the-declared-sizes
  (let* ((spec (peedy-spec))
         (vars (player.spec::spec-variables spec))
         (ops (player.spec::spec-ops spec)))
    (is (string= "PEEDY" (symbol-name (spec-name spec))))
    (is (stringp (spec-documentation spec)))
    (is (= 7 (length vars)))
    (is (equal '("last-heard")
               (peedy-names (mapcar #'player.spec::var-name
                              (remove :time vars :key #'player.spec::var-kind :test-not #'eq)))))
    (is (= 5 (length (player.spec::spec-autoscripts spec))))
    (is (= 44 (length ops)))
    (is (equal '("celebrate" "hard-wake" "soft-wake")
               (peedy-names (mapcar #'op-name (remove :macro ops :key #'op-kind :test-not #'eq)))))
    (is (equal '("camgoodbye" "camhello" "camwide" "give-note")
               (peedy-names (mapcar #'op-name (remove-if-not #'player.spec::op-must-ask ops)))))
    (is (= 9 (hash-table-count (player.spec::spec-classes spec))))
    (is (= 38 (length (player.spec::spec-events spec))))
    (is (= 13 (length (machine-goals (compile-spec spec)))))))

(test peedy-uses-the-papers-definitions
  (let* ((spec (peedy-spec))
         (machine (compile-spec spec))
         (vars (player.spec::spec-variables spec))
         (search (find "SEARCH" (player.spec::spec-ops spec) :key (lambda (o) (symbol-name (op-name o)))
                                                        :test #'string=))
         (wake (find "HARD-WAKE" (player.spec::spec-ops spec) :key (lambda (o) (symbol-name (op-name o)))
                                                         :test #'string=)))
    (is (equal '("holding-note" "posture" "alert" "wing-at-ear" "wearing-phones")
               (mapcar (lambda (v) (string-downcase (symbol-name (player.spec::var-name v))))
                       (subseq vars 0 5))))
    (is (equal '(:boolean :enumerated :enumerated :boolean :boolean)
               (mapcar #'player.spec::var-kind (subseq vars 0 5))))
    (is (equal "(fly stand sit)" (player.base::lisp-text (coerce (player.spec::var-domain (second vars)) 'list))))
    (is (equal "(snore sleep awake)" (player.base::lisp-text (coerce (player.spec::var-domain (third vars)) 'list))))
    (is (string= "stream" (player.base::lisp-text (op-script search))))
    (is (string= "stand-noteless" (player.base::lisp-text (player.spec::op-precond-form search))))
    (is (equal '("snort" "exhale" "focus")
               (mapcar (lambda (op) (string-downcase (symbol-name (op-name op))))
                       (player.spec::macro-sub-ops wake))))
    ;; The class hierarchy unfolds to the paper's full precondition of search,
    ;; and the other classes Peedy's ops stand on are goals of their own.
    (let ((goals (mapcar #'player.base::lisp-text (machine-goals machine))))
      (is (member "(and (not holding-note) posture.stand alert.awake (not wing-at-ear) (not wearing-phones))"
                  goals :test #'string=))
      (is (member "(and alert.awake (not wing-at-ear) (not wearing-phones))" goals :test #'string=))
      (is (member "(and posture.stand alert.awake (not wing-at-ear) (not wearing-phones))"
                  goals :test #'string=))
      ;; huh's precondition is not ack-op: it needs the wing at the ear.
      (is (member "(and alert.awake wing-at-ear)" goals :test #'string=))
      (is (member "wing-at-ear" goals :test #'string=)))))

(test peedy-checks-clean
  ;; Every goal is reachable from every state, every op is used, no search is
  ;; cut short; only states a sleeping parrot cannot be in are unreachable.
  (let ((diagnostics (check-spec (peedy-spec))))
    (is (equal '(:unreachable-states) (mapcar #'diagnostic-kind diagnostics))
        "unexpected diagnostics: ~{~A~^; ~}" (mapcar #'diagnostic-message diagnostics))))

;;; The papers' scenario

(test peedy-paper-scenario-trace
  (let ((c (asleep-peedy)))
    (dolist (event '(ev-search ev-search ev-bad-speech ev-thanks))
      (is (eq t (send-event c event))))
    (is (equal '("(:autoscript-start snore-loop :var alert :value snore :time 0)"
                 "(:event ev-search :time 0)"
                 "(:op hard-wake :script hard-wake :start 0 :end 2.5)"
                 "(:op snort :script snort :start 0 :end 1)"
                 "(:op exhale :script exhale :start 1 :end 1.75)"
                 "(:op focus :script focus :start 1.75 :end 2.5)"
                 "(:autoscript-stop snore-loop :var alert :value snore :time 2.5)"
                 "(:op standup :script standup :start 2.5 :end 4)"
                 "(:op search :script stream :start 4 :end 7)"
                 "(:state (holding-note . t) (posture . stand) (alert . awake) (wing-at-ear . nil) (wearing-phones . nil) (music-playing . nil) (last-heard . 0))"
                 "(:event ev-search :time 7)"
                 "(:op drop-note :script drop-note :start 7 :end 7.5)"
                 "(:op search :script stream :start 7.5 :end 10.5)"
                 "(:state (holding-note . t) (posture . stand) (alert . awake) (wing-at-ear . nil) (wearing-phones . nil) (music-playing . nil) (last-heard . 7))"
                 "(:event ev-bad-speech :time 10.5)"
                 "(:op raise-wing :script raise-wing :start 10.5 :end 11.25)"
                 "(:op huh :script huh :start 11.25 :end 12.25)"
                 "(:state (holding-note . t) (posture . stand) (alert . awake) (wing-at-ear . t) (wearing-phones . nil) (music-playing . nil) (last-heard . 10.5))"
                 "(:event ev-thanks :time 12.25)"
                 "(:op lower-wing :script lower-wing :start 12.25 :end 13)"
                 "(:op bow :script bow :start 13 :end 14.25)"
                 "(:op camgoodbye :script camgoodbye :start 17.25 :end 18.75)"
                 "(:op sit :script sit :start 19.25 :end 20.75)"
                 "(:state (holding-note . t) (posture . sit) (alert . awake) (wing-at-ear . nil) (wearing-phones . nil) (music-playing . nil) (last-heard . 12.25))")
               (trace-of c)))
    (is (= 20.75d0 (controller-clock c)))))

(test peedy-first-search-wakes-stands-and-searches
  (let* ((c (asleep-peedy))
         (before (length (peedy-raw-lines c))))
    (is (eq t (send-event c 'ev-search)))
    (let ((ops (peedy-ops (nthcdr before (peedy-raw-lines c)))))
      ;; the macro line, its three sub-ops, then standup and search, back to back
      (is (equal '("hard-wake" "snort" "exhale" "focus" "standup" "search")
                 (mapcar #'first ops)))
      (destructuring-bind (wake snort exhale focus standup search) ops
        (is (= (second wake) (second snort)))
        (is (= (third snort) (second exhale)))
        (is (= (third exhale) (second focus)))
        (is (= (third wake) (third focus)))
        (is (= (third wake) (second standup)))
        (is (= (third standup) (second search)))))
    (is (equal '("t" "stand" "awake" "nil" "nil")
               (mapcar (lambda (v) (peedy-value c v))
                       '(holding-note posture alert wing-at-ear wearing-phones))))))

(test peedy-second-search-skips-waking-and-standing
  (let ((c (asleep-peedy)))
    (send-event c 'ev-search)
    (let* ((end-of-first (controller-clock c))
           (before (length (peedy-raw-lines c))))
      (is (eq t (send-event c 'ev-search)))
      (let ((ops (peedy-ops (nthcdr before (peedy-raw-lines c)))))
        ;; search needs an empty beak, so the first search's note is put down;
        ;; no hard-wake, no standup.
        (is (equal '("drop-note" "search") (mapcar #'first ops)))
        (is (= end-of-first (second (first ops))))
        (is (= (third (first ops)) (second (second ops))))
        (is (= 3 (- (third (second ops)) (second (second ops)))))))
    (is (equal "t" (peedy-value c 'holding-note)))
    (is (equal "stand" (peedy-value c 'posture)))))

(test peedy-bad-speech-raises-the-wing-and-says-huh
  (let ((c (asleep-peedy)))
    (send-event c 'ev-search)
    (let ((lines (peedy-event-lines c 'ev-bad-speech)))
      (is (equal '("(:event ev-bad-speech :time 7)"
                   "(:op raise-wing :script raise-wing :start 7 :end 7.75)"
                   "(:op huh :script huh :start 7.75 :end 8.75)")
                 (subseq lines 0 3))))
    (is (equal "t" (peedy-value c 'wing-at-ear)))
    (is (equal "awake" (peedy-value c 'alert)))
    (is (= 7 (state-value c 'last-heard)))
    ;; huh needs the wing at the ear, not ack-op: a second bad utterance is
    ;; only huh, the wing stays up.
    (is (equal '("(:event ev-bad-speech :time 8.75)"
                 "(:op huh :script huh :start 8.75 :end 9.75)")
               (subseq (peedy-event-lines c 'ev-bad-speech) 0 2)))
    (is (equal "t" (peedy-value c 'wing-at-ear)))
    (is (= 8.75d0 (state-value c 'last-heard)))))

(test peedy-bad-speech-from-deep-sleep-wakes-first
  (let* ((c (asleep-peedy))
         (lines (progn (send-event c 'ev-bad-speech) (peedy-raw-lines c))))
    (is (equal '("hard-wake" "snort" "exhale" "focus" "raise-wing" "huh")
               (mapcar #'first (peedy-ops lines))))
    ;; he stays seated: raising the wing does not need standing
    (is (equal "sit" (peedy-value c 'posture)))
    (is (equal "t" (peedy-value c 'wing-at-ear)))))

(test peedy-thanks-times-camera-and-sit-from-the-end-of-the-bow
  (flet ((check-thanks (c)
           (let* ((before (length (peedy-raw-lines c)))
                  (ok (send-event c 'ev-thanks))
                  (ops (peedy-ops (nthcdr before (peedy-raw-lines c))))
                  (names (mapcar #'first ops))
                  (bow (assoc "bow" ops :test #'string=))
                  (cam (assoc "camgoodbye" ops :test #'string=))
                  (sit (assoc "sit" ops :test #'string=)))
             (is (eq t ok))
             (is (equal '("bow" "camgoodbye" "sit") (last names 3)))
             (when (and bow cam sit)
               ;; label a is the end of the bow, not its start
               (is (= (+ (third bow) 3) (second cam)))
               (is (= (+ (third bow) 5) (second sit)))
               ;; sit is timed from the bow, not queued behind the camera move
               (is (/= (third cam) (second sit))))
             (is (equal "sit" (peedy-value c 'posture)))
             (when sit (is (= (third sit) (controller-clock c))))
             names)))
    ;; standing and ready: just the three ops
    (let ((c (peedy-controller)))
      (is (equal '("bow" "camgoodbye" "sit") (check-thanks c))))
    ;; after ev-bad-speech the wing comes down before the bow
    (let ((c (asleep-peedy)))
      (send-event c 'ev-search)
      (send-event c 'ev-bad-speech)
      (is (equal '("lower-wing" "bow" "camgoodbye" "sit") (check-thanks c)))
      (is (equal "nil" (peedy-value c 'wing-at-ear))))))

(test peedy-snore-loop-runs-only-while-snoring
  (let ((c (asleep-peedy)))
    (is (equal '("(:autoscript-start snore-loop :var alert :value snore :time 0)") (trace-of c)))
    (is (equal '("snore-loop")
               (mapcar (lambda (a) (string-downcase (symbol-name (first a))))
                       (player.control::active-autoscripts c))))
    (send-event c 'ev-search)
    (let ((autos (remove-if-not (lambda (l) (member (first l) '(:autoscript-start :autoscript-stop)))
                                (peedy-raw-lines c))))
      ;; stopped when hard-wake ends, once, and not restarted
      (is (equal '("(:autoscript-start snore-loop :var alert :value snore :time 0)"
                   "(:autoscript-stop snore-loop :var alert :value snore :time 2.5)")
                 (mapcar #'trace-line-string autos))))
    (is (null (player.control::active-autoscripts c))))
  ;; awake and standing (the declared initial state), nothing runs
  (is (null (player.control::active-autoscripts (peedy-controller)))))

(test peedy-autoscripts-follow-their-variables
  (let ((c (peedy-controller)))
    (dolist (event '(ev-dance ev-listen ev-speech ev-fly ev-goodbye ev-nap ev-stop))
      (is (eq t (send-event c event)) "~A failed" event))
    (is (equalp '((:autoscript-start "tap-foot" 5)       ; play-cd before the dance
                 (:autoscript-start "bob-head" 11)      ; headphones on
                 (:autoscript-stop "bob-head" 12.5)     ; off to nod
                 (:autoscript-start "flap-wings" 14.25) ; take-off
                 (:autoscript-stop "flap-wings" 19.25)  ; landed to go to sleep
                 (:autoscript-start "doze-breathe" 22.75)
                 (:autoscript-stop "doze-breathe" 24.25) ; nod-off
                 (:autoscript-start "snore-loop" 24.25)
                 (:autoscript-stop "snore-loop" 26.75)  ; hard-wake to stop the CD
                 (:autoscript-stop "tap-foot" 27.75))
               (loop for line in (peedy-raw-lines c)
                     when (member (first line) '(:autoscript-start :autoscript-stop))
                       collect (list (first line) (string-downcase (symbol-name (second line)))
                                     (getf (cddr line) :time)))))))

;;; The rest of the controller

(test peedy-controller-state-after-each-event
  (let ((c (asleep-peedy))
        (states '()))
    (flet ((snapshot ()
             (mapcar (lambda (v) (peedy-value c v))
                     '(holding-note posture alert wing-at-ear wearing-phones music-playing last-heard))))
      (push (snapshot) states)
      (dolist (event '(ev-search ev-search ev-bad-speech ev-thanks ev-found ev-goodbye))
        (send-event c event)
        (push (snapshot) states)))
    (is (equal '(("nil" "sit" "snore" "nil" "nil" "nil" "nil")
                 ("t" "stand" "awake" "nil" "nil" "nil" "0")
                 ("t" "stand" "awake" "nil" "nil" "nil" "7")
                 ("t" "stand" "awake" "t" "nil" "nil" "10.5")
                 ("t" "sit" "awake" "nil" "nil" "nil" "12.25")
                 ;; ev-found: stand up, put the note's CD on
                 ("nil" "stand" "awake" "nil" "nil" "t" "12.25")
                 ;; ev-goodbye: sit down and doze off
                 ("nil" "sit" "sleep" "nil" "nil" "t" "12.25"))
               (reverse states)))
    (is (equal '("holding-note" "posture" "alert" "wing-at-ear" "wearing-phones"
                 "music-playing" "last-heard")
               (mapcar (lambda (pair) (string-downcase (symbol-name (car pair))))
                       (controller-state c))))))

(test peedy-explicit-requests-reach-must-ask-ops
  ;; give-note is must-ask: no plan uses it, but ev-give asks for it by name,
  ;; and the planner first finds him a note to give.
  (let ((c (asleep-peedy)))
    (send-event c 'ev-give)
    (is (equal '("hard-wake" "snort" "exhale" "focus" "standup" "search" "give-note")
               (mapcar #'first (peedy-ops (peedy-raw-lines c)))))
    (is (equal "nil" (peedy-value c 'holding-note))))
  (let* ((machine (compile-spec (peedy-spec)))
         (planned (loop for goal across (player.planner::machine-goal-table machine)
                        append (loop for plan across (player.planner::goal-plans goal)
                                     append (player.planner::plan-ops plan)))))
    (is (member "DROP-NOTE" planned :key (lambda (op) (symbol-name (op-name op))) :test #'string=))
    (is (null (remove-duplicates (mapcar #'op-name (remove-if-not #'player.spec::op-must-ask planned)))))))

(test peedy-idle-yawns-only-after-half-a-minute-of-silence
  (let ((c (peedy-controller)))
    ;; nobody has spoken yet: last-heard is unset, no yawn
    (send-event c 'ev-idle)
    (send-event c 'ev-speech :at 100)
    (is (= 100 (state-value c 'last-heard)))
    (send-event c 'ev-idle :at 120)
    (send-event c 'ev-idle :at 131)
    (is (equalp '(("nod" 100 100.5d0) ("yawn" 131 132.5d0))
               (peedy-ops (peedy-raw-lines c))))))

(test peedy-goodbye-from-the-air
  ;; Flying with the wing up: the planner lands and sits him before he dozes.
  (let ((c (peedy-controller)))
    (send-event c 'ev-fly)
    (send-event c 'ev-bad-speech)
    (let ((before (length (peedy-raw-lines c))))
      (send-event c 'ev-goodbye)
      (is (equal '("lower-wing" "wave-goodbye" "camwide" "land" "sit" "doze")
                 (mapcar #'first (peedy-ops (nthcdr before (peedy-raw-lines c)))))))
    ;; wave-goodbye is an ack-op: it needed the wing down first
    (is (equal '("nil" "sit" "sleep")
               (mapcar (lambda (v) (peedy-value c v)) '(wing-at-ear posture alert))))))
