;;;; timers.lisp -- the spec forms that send events by themselves: timers
;;;; (ReActor's directors triggered by time; Persona's Peedy who "after a
;;;; period of inaction will sit down ... and eventually fall asleep") and
;;;; triggers (fired when a state expression becomes true).

(in-package #:player.spec)

(defun find-timer-named (name)
  "The timer or trigger of *SPEC* named NAME, or NIL."
  (find-if (lambda (def) (string= (name-key (if (timer-def-p def) (timer-name def) (trigger-name def)))
                                  (name-key name)))
           (append (spec-timers *spec*) (spec-triggers *spec*))))

(defun declare-timer-name (form)
  "The name of timer or trigger FORM, checked to be new."
  (unless (cdr form)
    (spec-fail 'spec-syntax-error form "expected (~A NAME ...)" (lisp-text (first form))))
  (let ((name (require-name (second form) form "a timer or trigger name")))
    (when (find-timer-named name)
      (spec-fail 'duplicate-definition form "~A is defined twice" (lisp-text name)))
    name))

(defun required-event (options form)
  "The event OPTIONS' :EVENT names; an error about FORM when absent or unknown."
  (unless (member :event options)
    (spec-fail 'spec-syntax-error form "a ~A needs :event EVENT, the event it sends"
               (lisp-text (first form))))
  (let ((name (require-name (getf options :event) form "the :event")))
    (or (find-event-named name)
        (spec-fail 'unknown-name-error form "unknown event ~A" (lisp-text name)))))

(defun define-timer (form)
  "Parse (timer NAME :after SECONDS :event EV [:repeat t] [:restart-on (EV...)])."
  (let* ((name (declare-timer-name form))
         (options (parse-options form (cddr form) '(:after :event :repeat :restart-on))))
    (unless (member :after options)
      (spec-fail 'spec-syntax-error form "a timer needs :after SECONDS"))
    (let ((after (getf options :after)))
      (unless (and (finite-real-p after) (>= after *shortest-period*))
        (spec-fail 'type-error-in-spec form ":after must be a positive number of seconds, at least ~A (a faster clock sends more events than can be played), not ~A"
                   (format-number *shortest-period*)
                   (if (finite-real-p after)
                       (let ((*read-default-float-format* 'double-float)) (prin1-to-string (to-double after)))
                       (bounded-lisp-text after 40))))
      (setf (spec-timers *spec*)
            (append (spec-timers *spec*)
                    (list (make-timer-def
                           :name name :form form
                           :after (spec-seconds after form ":after" :minimum 0)
                           :event (required-event options form)
                           :repeat (parse-flag (getf options :repeat) form)
                           :restart-on (parse-restart-on (getf options :restart-on) form))))))))

(defun parse-restart-on (value form)
  "A timer's :RESTART-ON: a list of event names, or :ANY (every event sent from outside)."
  (cond ((word-p value "ANY") :any)
        ((proper-list-p value)
         (mapcar (lambda (name)
                   (let ((name (require-name name form "an event in :restart-on")))
                     (or (find-event-named name)
                         (spec-fail 'unknown-name-error form "unknown event ~A in :restart-on"
                                    (lisp-text name)))))
                 value))
        (t (spec-fail 'spec-syntax-error form ":restart-on takes (EVENT...) or :any, not ~A"
                      (bounded-lisp-text value 40)))))

(defun define-trigger (form)
  "Parse (trigger NAME :when EXPRESSION :event EV)."
  (let* ((name (declare-timer-name form))
         (options (parse-options form (cddr form) '(:when :event))))
    (unless (member :when options)
      (spec-fail 'spec-syntax-error form "a trigger needs :when EXPRESSION"))
    (let ((event (required-event options form)))
      (setf (spec-triggers *spec*)
            (append (spec-triggers *spec*)
                    (list (make-trigger-def
                           :name name :form form :event event
                           :condition (parse-trigger-condition (getf options :when) form))))))))

(defun parse-trigger-condition (expression form)
  "A trigger's :WHEN as a parsed expression (comparisons of numbers allowed);
an error about FORM when it is not an expression."
  (when (or (null expression) (keywordp expression) (numberp expression) (stringp expression))
    (spec-fail 'spec-syntax-error form ":when takes a state expression, not ~A"
               (bounded-lisp-text expression 40)))
  (parse-expression expression :runtime t))
