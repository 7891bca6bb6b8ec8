;;;; cradle-spec.lisp -- specs/newtons-cradle.lisp: the 5-sphere cradle as a
;;;; Player spec, made by GRAPH->SPEC.
;;;;
;;;; The cradle's graph has no edge out of rest: someone has to lift spheres.
;;;; The spec adds one edge per starting configuration (*CRADLE-CONFIGURATIONS*:
;;;; two lifted on the left; the paper's Figure 10, one lifted; its Figure 11,
;;;; one at one end and two at the other) and keeps the states reachable from
;;;; rest. Each configuration's event lifts its spheres, lets go, and plans to
;;;; the first state where the spheres stand still again (for two lifted on
;;;; the left, two standing out on the right): the cradle's swing.

(in-package #:player.compose)

(defun sphere-code (sphere)
  "A sphere state's two letters: position L/C/R (-1/0/1), velocity W/S/E
(moving west, still, moving east)."
  (format nil "~C~C" (char "LCR" (1+ (car sphere))) (char "WSE" (1+ (cdr sphere)))))

(defun cradle-node-name (node)
  "A cradle node's name: its spheres' codes, leftmost first, joined by dashes:
LS-LS-CS-CS-CS is two spheres lifted left, at rest."
  (format nil "~{~A~^-~}" (mapcar #'sphere-code (cradle-spheres node))))

(defparameter *cradle-configurations*
  '((:op "lift-two-left" :event "ev-lift-two-left" :left 2 :right 0)
    ;; Figure 10: "Simple example animation" -- "starting with a single displaced ball".
    (:op "lift-one-left" :event "ev-simple-example-animation" :left 1 :right 0 :figure 10)
    ;; Figure 11: "A more complex example" -- "one displaced ball at one end and two at the other".
    (:op "lift-one-left-two-right" :event "ev-more-complex-example" :left 1 :right 2 :figure 11))
  "The starting configurations specs/newtons-cradle.lisp lifts the spheres
to: the op lifting them, the event playing the swing, how many spheres are
lifted on the LEFT and the RIGHT, and the paper's figure showing it.")

(defun cradle-start (n &key (left 0) (right 0))
  "The cradle node of N spheres with LEFT of them lifted at rest on the left
and RIGHT on the right (the others hanging at rest). An ARGUMENT-ERROR unless
LEFT + RIGHT <= N."
  (check-argument 'cradle-start 'n n (lambda (x) (typep x '(integer 1))) "a number of spheres (an integer >= 1)")
  (check-argument 'cradle-start :left left (lambda (x) (typep x `(integer 0 ,n))) "a number of spheres from 0 to N")
  (check-argument 'cradle-start :right right (lambda (x) (and (typep x '(integer 0)) (<= (+ left x) n)))
                  "a number of spheres, LEFT + RIGHT at most N")
  (apply #'cradle-node (append (make-list left :initial-element '(-1 . 0))
                               (make-list (- n left right) :initial-element '(0 . 0))
                               (make-list right :initial-element '(1 . 0)))))

(defun cradle-run (n &key (left 0) (right 0) steps)
  "The run of the N-sphere cradle let go with LEFT and RIGHT spheres lifted
(see CRADLE-START): its states, start first, from the lazily built
NEWTON-CRADLE, whose states have one successor each. STEPS states after the
start; by default up to the first state where every sphere stands still again
(the swing of the paper's Figures 10 and 11)."
  (let ((graph (lazy-cradle n))
        (run (list (cradle-start n :left left :right right))))
    (loop for k from 0
          for next = (first (lazy-successors graph (first run)))
          while (and next (if steps (< k steps) (< k 1000)))
          do (push next run)
          until (and (null steps) (every (lambda (s) (zerop (cdr s))) (cradle-spheres next))))
    (nreverse run)))

(defun cradle-figure (figure &key (n 5))
  "The run of the paper's FIGURE (10 or 11) with N spheres (see CRADLE-RUN
and *CRADLE-CONFIGURATIONS*). An ARGUMENT-ERROR for another figure."
  (let ((configuration (find figure *cradle-configurations* :key (lambda (c) (getf c :figure)))))
    (check-argument 'cradle-figure 'figure figure (lambda (x) (declare (ignore x)) configuration) "10 or 11")
    (cradle-run n :left (getf configuration :left) :right (getf configuration :right))))

(defun cradle-spec-graph (&key (n 5))
  "The graph specs/newtons-cradle.lisp is made of: G^N with an edge from rest
to each configuration of *CRADLE-CONFIGURATIONS*, the states reachable from
rest, each move timed (TIMED-CRADLE: swings a quarter period, turns and
collisions near-instants, lifts a second). Second value: the node of rest; third, an alist from each
configuration's lifted node to the configuration."
  (let* ((rest (cradle-start n))
         (lifts (loop for c in *cradle-configurations*
                      collect (cons (cradle-start n :left (getf c :left) :right (getf c :right)) c))))
    (values (timed-cradle (graph-reachable (graph-sum (newton-cradle n)
                                                      (make-graph '() (loop for (node) in lifts collect (cons rest node))))
                                           rest)
                          rest)
            rest lifts)))

(defun cradle-op-namer (rest lifts)
  "The op names of the cradle spec: each configuration's op for the edge from
REST to its lifted node (LIFTS, from CRADLE-SPEC-GRAPH), FROM-X-TO-Y for the others."
  (lambda (source target)
    (let ((lift (and (equal source rest) (assoc target lifts :test #'equal))))
      (if lift
          (spec-symbol "~A" (getf (cdr lift) :op))
          (spec-symbol "from-~A-to-~A" (cradle-node-name source) (cradle-node-name target))))))

(defparameter *cradle-spec-options* '((:scripts "newtons-cradle-scripts.lisp") (:body none))
  "The options of specs/newtons-cradle.lisp: its script library (written by
WRITE-CRADLE-SCRIPTS-FILE) and no character, only the cradle's props.")

(defun cradle-spec-forms (&key (n 5))
  "The DEFSPEC body of specs/newtons-cradle.lisp (N spheres): regenerate the file with
  (player.compose:write-cradle-spec-file \"specs/newtons-cradle.lisp\")."
  (multiple-value-bind (graph rest lifts) (cradle-spec-graph :n n)
    (graph->spec-forms
     graph :start rest :variable 'cradle :node-namer #'cradle-node-name
     :options (mapcar (lambda (option) (list (first option)
                                             (if (symbolp (second option))
                                                 (spec-symbol "~A" (second option))
                                                 (second option))))
                      *cradle-spec-options*)
     :documentation (format nil "Newton's cradle with ~D spheres (Clark & Palmer, 1995, section 4), ~
                                 generated by graph->spec from (newton-cradle ~D): the states reachable ~
                                 from rest once spheres are lifted (two on the left; one, the paper's ~
                                 Figure 10; one on the left and two on the right, its Figure 11)." n n)
     :op-namer (cradle-op-namer rest lifts)
     ;; no GO-X event per state: the physics reaches each state only from its own
     ;; configuration (never back to rest), so goals per state would all be
     ;; unreachable from most states; the events are the configurations.
     :go-events nil
     :events (loop for (nil . c) in lifts
                   collect (list (spec-symbol "event") (spec-symbol "~A" (getf c :event))
                                 :op (spec-symbol "~A" (getf c :op))
                                 :state (spec-symbol "cradle.~A"
                                                     (cradle-node-name
                                                      (car (last (cradle-run n :left (getf c :left)
                                                                               :right (getf c :right)))))))))))

(defun write-cradle-spec-file (file)
  "Write specs/newtons-cradle.lisp (to FILE) from CRADLE-SPEC-FORMS."
  (with-atomic-output-file (out file :follow-links t)
    (with-standard-io-syntax
      (let ((*package* (find-package '#:player-user))
            (*print-case* :downcase)
            (*print-readably* nil)
            (*read-default-float-format* 'double-float) ; durations print as 0.05, not 0.05d0
            (*print-pretty* t)
            (*print-right-margin* 100))
        (format out ";;;; newtons-cradle.lisp -- Newton's cradle, 5 spheres, as a Player spec.~%~
;;;; Generated by graph->spec (src/compose/) from (newton-cradle 5), Clark &~%~
;;;; Palmer's transition-system construction; regenerate with~%~
;;;;   (player.compose:write-cradle-spec-file \"specs/newtons-cradle.lisp\")~%~
;;;; A state names each sphere, leftmost first: position L/C/R (lifted left,~%~
;;;; hanging, lifted right), velocity W/S/E (moving west, still, moving east).~%~
;;;; Try: bin/player run specs/newtons-cradle.lisp --events ev-lift-two-left~%~
;;;; The paper's Figures 10 and 11: events ev-simple-example-animation and~%~
;;;; ev-more-complex-example.~%~
;;;; Draw it: make demo-cradle [START=simple-example-animation|more-complex-example]~%~
;;;; (its scripts: newtons-cradle-scripts.lisp)~%~%~
(in-package :player-user)~%~%")
        (let ((forms (cradle-spec-forms)))
          (format out "(defspec newtons-cradle")
          (dolist (form forms)
            (format out "~%  ~S" form))
          (format out ")~%"))))))
