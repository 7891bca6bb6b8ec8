;;;; test-plan-tapes.lisp -- a timed controller tapes an event's plan the first
;;;; time it plans it from a state and replays the tape after
;;;; (src/control/timeline/tapes.lisp).  A replay must make exactly what the
;;;; closures would: the random specs and streams of the model-based test and
;;;; the random specs of the C++ comparison (macros, :time directives,
;;;; runtime values) are played with tapes off, then twice with them on (the
;;;; first play tapes, the second replays), and the three plays must agree to
;;;; the last line and digit.

(in-package #:player-tests)

(def-suite* plan-tapes :in player-tests)

(defun machine-tape-count (machine)
  "How many plans MACHINE's events have taped."
  (loop for compiled being the hash-values of (player.control::compiled-machine-events machine)
        for table = (player.control::compiled-event-tapes compiled)
        sum (if table (player.control::tape-table-count table) 0)))

(defun plan-tape-problem (seed stream)
  "How playing stream STREAM of random spec SEED with taped plans differs from
playing it without, or NIL.  Returns a second value: the plans taped."
  (call-with-random-stream
   seed stream
   (lambda (machine spec actions initial)
     (flet ((summary (tapes)
              (tm-play-summary-with 'player.control::*replay-plan-tapes* tapes machine spec actions initial)))
       (let* ((closures (summary nil))
              (taping (summary t))
              (replaying (summary t)))
         (values (cond ((not (equal taping closures))
                        "the play that tapes differs from the one without tapes")
                       ((not (equal replaying closures))
                        "the play that replays tapes differs from the one without tapes"))
                 (machine-tape-count machine)))))))

(test timeline-taped-plans-replay-what-the-closures-did
  "On random timed specs and streams (cuts, parallel channels, timers,
triggers, every policy), a timed controller replaying its taped plans plays
exactly what planning with the closures plays."
  (multiple-value-bind (problems taped) (tm-stream-problems #'plan-tape-problem)
    (is (null problems) "~{~A~^~%~}" problems)
    ;; Fewer would mean the streams hardly replayed anything.
    (is (> taped 500) "only ~D plans taped" taped)))

(test timeline-taped-plans-on-the-c++-comparison-specs
  "The random specs of the C++ comparison (macro-ops, :time directives,
runtime values, every policy) play the same with taped plans as without."
  (let ((problems '()) (played 0) (taped 0))
    (dolist (seed (loop for seed from 1 to 20 collect seed))
      (multiple-value-bind (problem count machine)
          ;; Off, taping, replaying.
          (handler-case (c++-spec-variant-problem seed "plan-tapes" 'player.control::*replay-plan-tapes* '(nil t t))
            (error (e) (format nil "error: ~A" e)))
        (incf played (or count 0))
        (incf taped (if machine (machine-tape-count machine) 0))
        (when problem (push (format nil "seed ~D: ~A" seed problem) problems))))
    (is (null problems) "~{~A~^~%~}" (reverse problems))
    (is (>= played 250) "only ~D scenarios" played)
    (is (> taped 100) "only ~D plans taped" taped)))

(defun peedy-compiled-event (machine name)
  "The compiled event NAME (a string) of Peedy's MACHINE."
  (player.control::find-compiled-event (make-controller machine) name))

(test plan-tapes-only-for-events-the-state-alone-decides
  "An event is taped only when the plannable state alone decides its plan: not
one with :if, :time or :label, nor any event of a spec with a :code op."
  (let ((machine (compile-spec (first (load-spec (checkout-file "specs/peedy.lisp"))))))
    (flet ((tapeable (name) (player.control::event-tapeable-p (peedy-compiled-event machine name) machine)))
      (is-true (tapeable "ev-sit"))
      (is-true (tapeable "ev-wake"))            ; a goal whose plan runs a macro-op
      (is-false (tapeable "ev-thanks"))         ; :label and :time
      (is-false (tapeable "ev-idle"))))         ; :if on a runtime value
  (let ((machine (machine-of-forms 'tapes-code-op
                                   '((state-variable up boolean false)
                                     (op lift :add up :duration 1)
                                     (op shout :code (print "hi") :duration 1)
                                     (event ev-lift :op lift))
                                   (find-package '#:player-user))))
    (is-false (player.control::event-tapeable-p (player.control::find-compiled-event (make-controller machine) "ev-lift") machine))))

(test plan-tapes-stop-at-their-limit
  "An event keeps at most *PLAN-TAPES-PER-EVENT* tapes; past that it is planned
by its closures, and plays the same."
  (let* ((machine (compile-spec (first (load-spec (checkout-file "specs/peedy.lisp")))))
         (names (coerce (event-names machine) 'simple-vector))
         (*random-state* (sb-ext:seed-random-state 3))
         (stream (loop repeat 400 collect (svref names (random (length names))))))
    (flet ((play ()
             (let ((controller (make-controller machine :timed t :presenter (make-trace-presenter))))
               (dolist (name stream)
                 (send-event controller name :at (+ (controller-time controller) 0.5d0) :when-busy :preempt))
               (finish-events controller)
               (trace-lines (player.control::controller-presenter* (player.control::controller-timeline controller))))))
      (let ((unlimited (let ((player.control::*replay-plan-tapes* nil)) (play)))
            (limited (let ((player.control::*plan-tapes-per-event* 2)) (play) (play))))
        (is (equal unlimited limited))
        (is (<= (loop for compiled being the hash-values of (player.control::compiled-machine-events machine)
                      maximize (let ((table (player.control::compiled-event-tapes compiled)))
                                 (if table (player.control::tape-table-count table) 0)))
                2))))))

(test plan-tapes-replay-macros-nested-deep
  "Macro-ops nested six deep (deeper than the replay's first span stack) play
the same replayed as planned by the closures."
  (let* ((forms (append '((state-variable lit boolean false)
                          (state-variable blocked boolean false)
                          (op leaf :duration 0.5)
                          (op light :add lit :duration 0.25)
                          (macro-op m1 :precond (not blocked) :seq (:op leaf :op light)))
                        (loop for k from 2 to 6
                              collect `(macro-op ,(intern (format nil "M~D" k)) :precond (not blocked)
                                         :seq (:op leaf :op ,(intern (format nil "M~D" (1- k))) :op leaf)))
                        '((event ev :op m6))))
         (machine (machine-of-forms 'tapes-nested forms (find-package '#:player-user))))
    (flet ((play (tapes)
             (let ((player.control::*replay-plan-tapes* tapes))
               (let* ((presenter (make-trace-presenter))
                      (controller (make-controller machine :timed t :presenter presenter)))
                 ;; Once to its end, then cut by itself and resumed.
                 (send-event controller "ev")
                 (finish-events controller)
                 (send-event controller "ev")
                 (send-event controller "ev" :at (+ (controller-time controller) 3.3d0)
                                             :when-busy :interleave)
                 (finish-events controller)
                 (trace-lines presenter)))))
      (let ((closures (play nil)))
        (play t)                          ; tapes
        (is (equal closures (play t)))
        (is (>= (machine-tape-count machine) 1))
        (is (>= (count-if (lambda (line) (and (symbolp (second line)) (string= (second line) "M6"))) closures) 3))))))
