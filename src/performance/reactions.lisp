;;;; reactions.lisp -- ReActor's reactive directors: a director that names
;;;; what starts it, (:when EXPRESSION), (:on EVENT) or (:after DIRECTOR),
;;;; starts by itself when a state or property expression becomes true, when
;;;; a Player event is processed (a user's input, or one a director's :send
;;;; step sent), or when another director ends.  Its :set steps set
;;;; properties; its :send steps send Player events to the controller the
;;;; body presenter plays for, which plans them as any other event.
;;;;
;;;; One mechanism each: a state expression is read as (:pose-when ...)
;;;; entries and goals are (its cubes in the spec), and fires on a rising
;;;; edge as the spec's triggers do; timing within a director is its steps'
;;;; :at; whatever must be planned goes through a Player event.

(in-package #:player.performance)

(defstruct (reactions (:constructor make-reactions ()))
  "A performance's reactive state.  SEND is NIL or a function of (EVENT TIME)
that sends a Player event (the body presenter's controller); SENT lists
\(TIME EVENT) sent, newest first.  WATCHES holds the property watches, each
\(DIRECTOR . HELD), checked up to HORIZON seconds; STATE-WATCHES the state
ones, each (DIRECTOR CUBES . HELD), BITS the state they were last checked
in.  DEPTH counts directors starting each other in one chain, STARTS every
reactive start so far."
  (send nil) (sent '()) (watches :unset) (horizon nil) (state-watches '()) (depth 0) (bits nil)
  (starts 0))

(defun performance-reactions (performance)
  "PERFORMANCE's REACTIONS, made on first use."
  (or (performance-reaction-state performance)
      (setf (performance-reaction-state performance) (make-reactions))))

(defun reactive-directors (library kind)
  "LIBRARY's directors whose trigger is of KIND (:when, :on or :after), in
file order (so directors fired together start in the order written)."
  (loop for definition in (script-library-definitions library)
        when (and (director-p definition) (eq kind (first (director-trigger definition))))
          collect definition))

;;;# Property expressions

(defparameter *property-operators* '("AND" "OR" "NOT" "<" ">" "<=" ">=" "=" "/=")
  "The operators of a property expression, compared by name.")

(defun property-expression-p (expression)
  "Does EXPRESSION read a scene property, (:property OBJECT PROPERTY [AXIS])?"
  (and (consp expression)
       (or (eq (first expression) :property)
           (and (alexandria:proper-list-p expression)
                (some #'property-expression-p (rest expression))))))

(defun check-property-expression (form expression)
  "Signal a SCRIPT-ERROR about FORM unless EXPRESSION, when it reads a
property, is made of numbers, T, NIL, (:property OBJECT PROPERTY [:x|:y|:z])
and (OPERATOR ARGUMENT...) with the operators of *PROPERTY-OPERATORS*."
  (labels ((check (e)
             (cond ((or (realp e) (member e '(t nil))))
                   ((and (consp e) (eq (first e) :property))
                    (unless (and (alexandria:proper-list-p e) (<= 3 (length e) 4)
                                 (or (eq (second e) :self) (usable-name-p (second e)))
                                 (usable-name-p (third e))
                                 (member (fourth e) '(nil :x :y :z)))
                      (script-fail form "a property is read as (:property OBJECT PROPERTY [:x|:y|:z]), not ~A"
                                   (lisp-text e))))
                   ((and (alexandria:proper-list-p e) (symbolp (first e))
                         (member (symbol-name (first e)) *property-operators* :test #'string=))
                    (mapc #'check (rest e)))
                   (t (script-fail form "~A is not part of a property expression (numbers, T, NIL, ~
                                         (:property OBJECT PROPERTY [AXIS]), ~{~A~^ ~})"
                                   (lisp-text e) (mapcar #'string-downcase *property-operators*))))))
    (when (property-expression-p expression)
      (check expression))))

(defun property-expression-value (expression performance)
  "EXPRESSION's value in PERFORMANCE's current scene (see CHECK-PROPERTY-EXPRESSION);
:self is the first character.  An object the scene lacks reads as NIL."
  (labels ((value (e)
             (cond ((atom e) e)
                   ((eq (first e) :property)
                    (destructuring-bind (object property &optional axis) (rest e)
                      (let* ((name (if (eq object :self) (performance-character performance) object))
                             (found (find-object (performance-scene performance) name nil))
                             (v (and found (property-value found property))))
                        (if (and axis (vec3-p v))
                            (ecase axis (:x (vec3-x v)) (:y (vec3-y v)) (:z (vec3-z v)))
                            v))))
                   (t (let ((arguments (mapcar #'value (rest e)))
                            (operator (symbol-name (first e))))
                        (cond ((string= operator "AND") (every #'identity arguments))
                              ((string= operator "OR") (some #'identity arguments))
                              ((string= operator "NOT") (not (first arguments)))
                              ((notevery #'realp arguments) nil)
                              (t (apply (cdr (assoc operator '(("<" . <) (">" . >) ("<=" . <=) (">=" . >=)
                                                               ("=" . =) ("/=" . /=))
                                                    :test #'string=))
                                        arguments))))))))
    (and (value expression) t)))

;;;# Starting

(defparameter *longest-director-chain* 100
  "How many directors may start each other in one chain (:after, :on with
:send) before the chain is taken for an endless loop.")

(defparameter *most-director-starts* 10000
  "How many times reactive directors may start in one performance: directors
each sending the next one's event twice start 2^N times (issue 31), while
the chain stays short.")

(defun start-reactive-director (performance director time)
  "Start the reactive DIRECTOR at TIME on PERFORMANCE's first character."
  (let ((reactions (performance-reactions performance)))
    (when (>= (reactions-depth reactions) *longest-director-chain*)
      (script-fail (director-form director) "directors start each other without end (over ~D in one chain)"
                   *longest-director-chain*))
    (when (>= (reactions-starts reactions) *most-director-starts*)
      (script-fail (director-form director) "reactive directors started over ~:D times in one performance (directors whose :send or :after start several others multiply)"
                   *most-director-starts*))
    (incf (reactions-starts reactions))
    (incf (reactions-depth reactions))
    (unwind-protect (perform-director performance (director-name director) time :settle t)
      (decf (reactions-depth reactions)))))

(defun director-started (performance director start duration actions)
  "What follows DIRECTOR's start at START on PERFORMANCE: its :set and :send
steps (ACTIONS, as DIRECTOR-SCHEDULE gives them) at their times, and, when it
ends (after DURATION, NIL for never), the directors waiting (:after) for it."
  (dolist (action actions)
    (destructuring-bind (time kind what) action
      (ecase kind
        (:set (let ((script (%make-script :name (make-symbol "SET") :duration 0d0
                                          :items (list what) :form (director-form director))))
                (add-script-run performance (make-script-run script time nil
                                                             (performance-character performance) nil))))
        (:send (send-director-event performance what time)))))
  (when duration
    (dolist (next (reactive-directors (performance-library performance) :after))
      (when (name= (second (director-trigger next)) (director-name director))
        (start-reactive-director performance next (+ start duration))))))

(defun send-director-event (performance event time)
  "Send the Player EVENT at TIME through PERFORMANCE's event sender, and note it."
  (let ((reactions (performance-reactions performance)))
    (push (list time event) (reactions-sent reactions))
    (when (reactions-send reactions)
      (funcall (reactions-send reactions) event time))))

(defun performance-signal (performance event time)
  "Tell PERFORMANCE that the Player EVENT happened at TIME: every director of
its library written (:on EVENT) starts then.  Returns their names."
  (check-argument 'performance-signal 'performance performance #'performance-p "a performance (from make-performance)")
  (check-argument 'performance-signal 'event event #'string-designator-p "an event's name (a symbol or string)")
  (check-seconds 'performance-signal 'time time)
  (loop for director in (reactive-directors (performance-library performance) :on)
        when (name= (second (director-trigger director)) event)
          do (start-reactive-director performance director (float time 1d0))
          and collect (director-name director)))

(defun performance-sent-events (performance)
  "The Player events PERFORMANCE's directors sent, as (TIME EVENT), oldest first."
  (check-argument 'performance-sent-events 'performance performance #'performance-p "a performance (from make-performance)")
  (reverse (reactions-sent (performance-reactions performance))))

;;;# Watching properties (each frame) and the state (each change)

(defun check-property-reactions (performance time)
  "Start each (:when PROPERTY-EXPRESSION) director whose expression has
become true at TIME, a frame later than any checked before (a replay from
the start does not start them twice)."
  (let ((reactions (performance-reactions performance)))
    (when (eq (reactions-watches reactions) :unset)
      (setf (reactions-watches reactions)
            (loop for director in (reactive-directors (performance-library performance) :when)
                  when (property-expression-p (second (director-trigger director)))
                    collect (cons director :unknown))))
    (when (and (reactions-watches reactions)
               (or (null (reactions-horizon reactions)) (> time (reactions-horizon reactions))))
      (setf (reactions-horizon reactions) time)
      (dolist (watch (reactions-watches reactions))
        (let ((holds (property-expression-value (second (director-trigger (car watch))) performance)))
          ;; True from the first frame on is not a rising edge, as for the spec's triggers.
          (when (and holds (eq (cdr watch) nil))
            (start-reactive-director performance (car watch) time))
          (setf (cdr watch) holds))))))

(defun director-state-cubes (director spec)
  "The cubes in SPEC of DIRECTOR's (:when STATE-EXPRESSION); a SCRIPT-ERROR
at the director when it is not a state expression of SPEC."
  (let ((expression (second (director-trigger director))))
    (handler-case
        (with-spec-context (:spec spec :spec-name (spec-name spec) :form-places nil)
          (expression-cubes (parse-expression expression) spec))
      (spec-error (condition)
        (script-fail (director-form director) "director ~A: ~A is not a state expression of spec ~A: ~A"
                     (lisp-text (director-name director)) (lisp-text expression)
                     (lisp-text (spec-name spec)) (spec-error-message condition))))))

(defun state-directors (library)
  "LIBRARY's (:when STATE-EXPRESSION) directors."
  (remove-if (lambda (director) (property-expression-p (second (director-trigger director))))
             (reactive-directors library :when)))

(defun watch-state-reactions (performance spec bits)
  "Make PERFORMANCE watch its (:when STATE-EXPRESSION) directors' expressions
in SPEC, holding or not in the one-hot state BITS; a SCRIPT-ERROR at the
director for an expression that is not one of SPEC's."
  (setf (reactions-bits (performance-reactions performance)) bits)
  (setf (reactions-state-watches (performance-reactions performance))
        (loop for director in (state-directors (performance-library performance))
              collect (let ((cubes (director-state-cubes director spec)))
                        (list* director cubes (cubes-hold-p cubes bits))))))

(defun cubes-hold-p (cubes bits)
  "Does the one-hot state BITS lie in one of CUBES?"
  (and (some (lambda (cube) (state-in-cube-p bits cube)) cubes) t))

(defun check-state-reactions (performance bits time)
  "Start each (:when STATE-EXPRESSION) director whose expression has become
true in the state BITS, reached at TIME."
  (setf (reactions-bits (performance-reactions performance)) bits)
  (dolist (watch (reactions-state-watches (performance-reactions performance)))
    (destructuring-bind (director cubes . held) watch
      (let ((holds (cubes-hold-p cubes bits)))
        (when (and holds (not held))
          (start-reactive-director performance director time))
        (setf (cddr watch) holds)))))

;;;# The body presenter: events, states and sends

(defmethod present-initial-state :after ((presenter body-presenter) controller)
  (let ((performance (presenter-performance presenter)))
    (watch-state-reactions performance (spec-of controller) (controller-bits controller))
    (check-director-events (performance-library performance) (spec-of controller))
    (setf (reactions-send (performance-reactions performance))
          (lambda (event time)
            ;; A timed controller takes events from now on; the untimed one at any time.
            (send-event controller event :at (if (controller-timeline controller)
                                                 (max time (controller-time controller))
                                                 time))))))

(defmethod present-event :after ((presenter body-presenter) event time)
  (performance-signal (presenter-performance presenter) event time))

(defmethod present-state-change :after ((presenter body-presenter) controller time)
  (check-state-reactions (presenter-performance presenter) (controller-bits controller) time))

(defun check-director-events (library spec)
  "Signal a SCRIPT-ERROR for a director of LIBRARY that waits (:on) for, or
sends, an event SPEC does not have."
  (let ((events (mapcar #'event-name (spec-events spec))))
    (loop for director in (remove-if-not #'director-p (script-library-definitions library))
          do (flet ((check (event form)
                      (unless (member event events :test #'name=)
                        (script-fail form "director ~A: spec ~A has no event ~A"
                                     (lisp-text (director-name director)) (lisp-text (spec-name spec))
                                     (lisp-text event)))))
               (when (eq (first (director-trigger director)) :on)
                 (check (second (director-trigger director)) (director-form director)))
               (dolist (step (director-steps director))
                 (when (send-step-p step)
                   (check (send-step-event step) (director-step-form step))))))))

(defun check-reactive-directors (library spec)
  "Signal a SCRIPT-ERROR for the first director of LIBRARY whose trigger or
:send names what SPEC lacks: what CHECK reports, and playing would fail on."
  (check-director-events library spec)
  (dolist (director (state-directors library))
    (director-state-cubes director spec)))

(defun reactive-director-names (library)
  "The names of LIBRARY's directors that start by themselves (a trigger)."
  (loop for definition in (script-library-definitions library)
        when (and (director-p definition) (director-trigger definition))
          collect (director-name definition)))

(defun reactions-library-changed (performance spec)
  "PERFORMANCE plays a new library (live reloading): watch its directors'
expressions from now on, in SPEC, as they hold in the last state seen."
  (let ((reactions (performance-reactions performance)))
    (setf (reactions-watches reactions) :unset)
    (when (reactions-bits reactions)
      (watch-state-reactions performance spec (reactions-bits reactions))
      (check-director-events (performance-library performance) spec))))
