;;;; directors.lisp -- ReActor's directors as data: steps that start and stop
;;;; scripts in sequence or in synchrony (start B at A's critical time), set
;;;; properties and send Player events, and their expansion into a schedule
;;;; of timed script starts and actions for the evaluator.  A director may
;;;; name what starts it (:when, :on, :after: reactions.lisp plays those).
;;;; The language is described at the top of scripts.lisp.

(in-package #:player.performance)

;;; ---------------------------------------------------------------------------
;;; Data

(defstruct (director (:constructor %make-director))
  "A director: STEPS (START-STEPs, STOP-STEPs, SET-STEPs, SEND-STEPs) taken in
order.  TRIGGER is NIL (ops and other directors start it) or what starts it
by itself: (:when EXPRESSION), (:on EVENT) or (:after DIRECTOR).  SOURCE is
\(FILE . POSITION) or NIL, FORM the DEFDIRECTOR form."
  (name nil :type symbol :read-only t)
  (trigger nil :read-only t)
  (documentation nil :type (or null string) :read-only t)
  (steps '() :type list :read-only t)
  (source nil :read-only t)
  (form nil :read-only t))

(defmethod print-object ((director director) stream)
  (print-unreadable-object (director stream :type t)
    (format stream "~A, ~D steps" (lisp-text (director-name director))
            (length (director-steps director)))))

(defstruct (director-step (:constructor nil))
  "A step of a director about the script started as TAG, happening at WHEN: NIL
(when the last script started before it ends), seconds after the director's
start, or (:start TAG OFFSET), (:critical TAG NAME OFFSET), (:end TAG OFFSET).
FORM is the step as written."
  (tag nil :type symbol :read-only t)
  (when nil :read-only t)
  (form nil :read-only t))

(defstruct (start-step (:include director-step)
                       (:constructor make-start-step (script tag when form)))
  "Start the script named SCRIPT."
  (script nil :type symbol :read-only t))

(defstruct (stop-step (:include director-step)
                      (:constructor make-stop-step (tag when form)))
  "Stop the script started as TAG.")

(defstruct (set-step (:include director-step)
                     (:constructor make-set-step (item when form)))
  "Set a property once: ITEM is the SET-ITEM (:at 0 :set (OBJECT PROPERTY) VALUE) would be."
  (item nil :read-only t))

(defstruct (send-step (:include director-step)
                      (:constructor make-send-step (event when form)))
  "Send the Player event EVENT (a symbol) to the controller the performance plays for."
  (event nil :type symbol :read-only t))

;;; ---------------------------------------------------------------------------
;;; Parsing DEFDIRECTOR

(defun parse-defdirector (form &optional source)
  "The DIRECTOR that FORM, (defdirector NAME [DOCSTRING] STEP...), defines;
SOURCE is its (FILE . POSITION).  Scripts stay names until the library checks
them.  Signals SCRIPT-ERROR naming the bad step."
  (unless (and (alexandria:proper-list-p form) (usable-name-p (second form)))
    (script-fail form "a director is written (defdirector NAME [DOCSTRING] STEP...)"))
  (let* ((name (second form))
         (*script-context* (format nil "director ~A" (lisp-text name)))
         (documentation (and (stringp (third form)) (third form)))
         (step-forms (if documentation (cdddr form) (cddr form)))
         (trigger (and (consp (first step-forms)) (member (first (first step-forms)) '(:when :on :after))
                       (parse-director-trigger (pop step-forms))))
         (tags '()))
    (when (null step-forms)
      (script-fail form "a director needs at least one step"))
    (%make-director
     :name name :documentation documentation :source source :form form :trigger trigger
     :steps (loop for step-form in step-forms
                  for step = (parse-director-step step-form tags)
                  when (start-step-p step) do (push (director-step-tag step) tags)
                  collect step))))

(defun parse-director-trigger (form)
  "What starts a director, FORM: (:when EXPRESSION), (:on EVENT) or (:after
DIRECTOR), checked for shape (the expression against the spec when played)."
  (unless (and (alexandria:proper-list-p form) (= 2 (length form)))
    (script-fail form "a director's trigger is (:when EXPRESSION), (:on EVENT) or (:after DIRECTOR)"))
  (destructuring-bind (kind what) form
    (ecase kind
      (:when (when (or (null what) (keywordp what) (stringp what) (numberp what))
               (script-fail form ":when takes a state or property expression, not ~A" (lisp-text what)))
             (check-property-expression form what))
      ((:on :after) (unless (usable-name-p what)
                      (script-fail form "~A takes the name of ~:[a Player event~;a director~], not ~A"
                                   (lisp-text kind) (eq kind :after) (lisp-text what)))))
    (list kind what)))

(defun parse-director-step (form tags)
  "The DIRECTOR-STEP FORM denotes, given the TAGS started by earlier steps."
  (unless (and (alexandria:proper-list-p form) (>= (length form) 2)
               (member (first form) '(:start :stop :set :send)))
    (script-fail form "a director step is (:start SCRIPT [:as TAG] [:at WHEN]), (:stop TAG [:at WHEN]), ~
                       (:set (OBJECT PROPERTY) VALUE [:at WHEN]) or (:send EVENT [:at WHEN])"))
  (case (first form)
    (:set (parse-set-step form tags))
    (:send (parse-send-step form tags))
    (t (parse-script-step form tags))))

(defun parse-set-step (form tags)
  "(:set (OBJECT PROPERTY) VALUE [:at WHEN]): checked as a :set item is."
  (unless (>= (length form) 3)
    (script-fail form "a :set step is (:set (OBJECT PROPERTY) VALUE [:at WHEN])"))
  (destructuring-bind (target value &rest options) (rest form)
    (check-options form options '(:at) "a :set step")
    (make-set-step (parse-set-item (list :at 0 :set target value) 0d0 (list target value))
                   (parse-when form (getf options :at) tags) form)))

(defun parse-send-step (form tags)
  "(:send EVENT [:at WHEN]): the event is checked against the spec when played."
  (destructuring-bind (event &rest options) (rest form)
    (check-options form options '(:at) "a :send step")
    (unless (usable-name-p event)
      (script-fail form ":send takes the name of a Player event, not ~A" (lisp-text event)))
    (make-send-step event (parse-when form (getf options :at) tags) form)))

(defun parse-script-step (form tags)
  "(:start SCRIPT [:as TAG] [:at WHEN]) or (:stop TAG [:at WHEN])."
  (destructuring-bind (kind name &rest options) form
    (check-options form options (if (eq kind :start) '(:as :at) '(:at))
                   (format nil "a ~A step" (lisp-text kind)))
    (unless (usable-name-p name)
      (script-fail form "~A takes the name of a ~:[tag~;script~], not ~A"
                   (lisp-text kind) (eq kind :start) (lisp-text name)))
    (let ((when (parse-when form (getf options :at) tags)))
      (if (eq kind :start)
          (let ((tag (getf options :as name)))
            (unless (usable-name-p tag)
              (script-fail form ":as takes a name, not ~A" (lisp-text tag)))
            (when (member tag tags :test #'name=)
              (script-fail form "an earlier step already starts a script as ~A; give this one another :as"
                           (lisp-text tag)))
            (make-start-step name tag when form))
          (make-stop-step (known-tag form name tags) when form)))))

(defun known-tag (form tag tags)
  "TAG if an earlier step started a script as TAG; else a SCRIPT-ERROR about FORM."
  (unless (member tag tags :test #'name=)
    (script-fail form "no earlier step starts a script as ~A (started: ~:[none~;~:*~{~A~^ ~}~])"
                 (lisp-text tag) (mapcar #'lisp-text (reverse tags))))
  tag)

(defun parse-when (form when tags)
  "The WHEN (see DIRECTOR-STEP) the :at value WHEN of the step FORM denotes."
  (flet ((offset (value)
           (unless (seconds-p value)
             (script-fail form "an offset must be a finite number of seconds, not ~A"
                          (argument-value-text value)))
           (float value 1d0)))
    (cond ((null when) nil)
          ((realp when) (parse-seconds when form ":at"))
          ((and (alexandria:proper-list-p when) (member (first when) '(:start :end))
                (<= 2 (length when) 3))
           (list (first when) (known-tag form (second when) tags) (offset (or (third when) 0))))
          ((and (alexandria:proper-list-p when) (eq (first when) :critical)
                (<= 3 (length when) 4) (usable-name-p (third when)))
           (list :critical (known-tag form (second when) tags) (third when)
                 (offset (or (fourth when) 0))))
          (t (script-fail form ":at takes seconds, (:start TAG [OFFSET]), ~
                                (:critical TAG NAME [OFFSET]) or (:end TAG [OFFSET]), not ~A"
                          (lisp-text when))))))

;;; ---------------------------------------------------------------------------
;;; Schedules

(defstruct (director-run (:constructor make-director-run (tag script start natural-end)))
  "A script a director starts, while its schedule is worked out: times are
seconds after the director's start; NATURAL-END is NIL for a looping script.
WAITS lists (TIME . WHAT), the moments of it that later steps wait for."
  (tag nil :read-only t)
  (script nil :read-only t)
  (start 0d0 :read-only t)
  (natural-end nil :read-only t)
  (stop nil)
  (waits '()))

(defun director-run-end (run)
  "When RUN ends: stopped, or at its natural end; NIL for never."
  (let ((stop (director-run-stop run)) (end (director-run-natural-end run)))
    (if (and stop end) (min stop end) (or stop end))))

(defun director-schedule (director library &optional (start 0))
  "The scripts DIRECTOR of LIBRARY plays when it starts at absolute time START:
a list of (SCRIPT-NAME START-TIME STOP-TIME-OR-NIL), in step order, STOP-TIME
set when a :stop cuts the script short (NIL: it runs to its end, or for ever if
it loops).  The second value is the director's duration, NIL when a script it
starts loops unstopped.  The third lists its other steps in order, as (TIME
:set SET-ITEM) and (TIME :send EVENT).  Signals SCRIPT-ERROR for an unknown script or critical
time, a wait for a looping script's end, or inconsistent stops; ARGUMENT-ERROR
for arguments of the wrong kind."
  (check-argument 'director-schedule 'director director #'director-p "a director (from find-director)")
  (check-argument 'director-schedule 'library library
                  (lambda (x)
                    (declare (notinline script-library-p)) ; defined in script-library.lisp, later
                    (script-library-p x))
                  "a script library (from load-script-library)")
  (check-seconds 'director-schedule 'start start)
  (let ((*script-context* (format nil "director ~A" (lisp-text (director-name director))))
        (runs '())
        (actions '())
        (last nil))
    (with-spec-context (:source-position (director-source director))
      (dolist (step (director-steps director))
        (let ((time (director-step-time step last runs)))
          (etypecase step
            (start-step
             (let ((script (director-script step library)))
               (setf last (make-director-run (director-step-tag step) script time
                                    (and (not (script-loop script))
                                         (+ time (script-duration script)))))
               (push last runs)))
            (stop-step
             (stop-director-run (find-tagged-run step (director-step-tag step) runs) time step))
            (set-step (push (list (+ start time) :set (set-step-item step)) actions))
            (send-step (push (list (+ start time) :send (send-step-event step)) actions)))))
      (setf runs (reverse runs))
      (values (mapcar (lambda (run)
                        (let ((stop (director-run-stop run)) (end (director-run-natural-end run)))
                          (list (script-name (director-run-script run)) (+ start (director-run-start run))
                                (and stop (or (null end) (< stop end)) (+ start stop)))))
                      runs)
              (and (every #'director-run-end runs)
                   (reduce #'max runs :key #'director-run-end
                                      :initial-value (reduce #'max actions :key (lambda (a) (- (first a) start))
                                                                           :initial-value 0d0)))
              (reverse actions)))))

(defun director-script (step library)
  "The script STEP starts; a SCRIPT-ERROR when LIBRARY has none of that name."
  (let ((name (start-step-script step)))
    (or (find-script library name)
        (script-fail (director-step-form step) "~A is ~:[not a script of the library~;a director; directors start scripts~]"
                     (lisp-text name) (find-director library name)))))

(defun find-tagged-run (step tag runs)
  "The run an earlier step started as TAG (PARSE-DIRECTOR-STEP made sure there is one)."
  (or (find tag runs :key #'director-run-tag :test #'name=)
      (script-fail (director-step-form step) "no earlier step starts ~A" (lisp-text tag))))

(defun director-step-time (step last runs)
  "Seconds after the director's start at which STEP happens, LAST being the run
of the last :start before it, RUNS every run so far."
  (let* ((form (director-step-form step))
         (when (director-step-when step))
         (time (cond ((realp when) when)
                     ((null when) (if last (wait-for-run-end last form) 0d0))
                     (t (let ((run (find-tagged-run step (second when) runs)))
                          (+ (car (last when))
                             (ecase (first when)
                               (:start (director-run-start run))
                               (:end (wait-for-run-end run form))
                               (:critical (wait-for-run-critical run (third when) form)))))))))
    (when (minusp time)
      (script-fail form "the step comes ~A s before the director starts" (format-number (- time))))
    time))

(defun wait-for-run-end (run form)
  "RUN's end, which the step FORM waits for; a SCRIPT-ERROR when it never ends."
  (let ((end (or (director-run-end run)
                 (script-fail form "script ~A loops and never ends by itself, so nothing can wait for its end; stop ~A first"
                              (lisp-text (script-name (director-run-script run))) (lisp-text (director-run-tag run))))))
    (push (cons end "end") (director-run-waits run))
    end))

(defun wait-for-run-critical (run name form)
  "When RUN reaches its critical time NAME, which the step FORM waits for."
  (let* ((script (director-run-script run))
         (time (+ (director-run-start run)
                  (or (script-critical-time script name nil)
                      (script-fail form "script ~A has no critical time ~A (known: ~:[none~;~:*~{~A~^ ~}~])"
                                   (lisp-text (script-name script)) (lisp-text name)
                                   (mapcar (lambda (entry) (lisp-text (car entry)))
                                           (script-critical script)))))))
    (when (and (director-run-stop run) (> time (director-run-stop run)))
      (script-fail form "~A is stopped at ~A, before its critical time ~A (~A)"
                   (lisp-text (director-run-tag run)) (format-number (director-run-stop run)) (lisp-text name)
                   (format-number time)))
    (push (cons time (format nil "critical time ~A" (lisp-text name))) (director-run-waits run))
    time))

(defun stop-director-run (run time step)
  "Stop RUN at TIME, checking it against RUN's start and what earlier steps wait for."
  (let ((form (director-step-form step))
        (tag (lisp-text (director-run-tag run))))
    (when (director-run-stop run)
      (script-fail form "~A is stopped twice" tag))
    (when (< time (director-run-start run))
      (script-fail form "~A is stopped at ~A, before it starts at ~A" tag
                   (format-number time) (format-number (director-run-start run))))
    (loop for (wait . what) in (director-run-waits run)
          when (> wait time)
            do (script-fail form "~A is stopped at ~A, before its ~A (~A) that an earlier step ~
                                  waits for; put the stop before that step"
                            tag (format-number time) what (format-number wait)))
    (setf (director-run-stop run) time)))
