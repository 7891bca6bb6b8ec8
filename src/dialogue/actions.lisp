;;;; actions.lisp -- what a transition does (Persona, Figure 7): an action is
;;;; a form (NAME ARGUMENT...) naming a function registered from Lisp with
;;;; DEFINE-DIALOGUE-ACTION.  A dialogue file is data, so it can only name
;;;; actions, never hold code.  The language's own actions are here: (do
;;;; ANIMATION) sends Player events, (say CATEGORY) speaks a template, (set VAR
;;;; EXPRESSION) sets a context variable, (mood NAME) sets the emotional state.
;;;; Application actions (catalogue queries) are in catalogue-actions.lisp.

(in-package #:player.dialogue)

(defstruct (dialogue-action (:constructor %make-dialogue-action))
  "A registered action: its NAME, the FUNCTION called with the conversation
and the form's arguments (unevaluated data), and how many arguments it takes
(MINIMUM, and MAXIMUM or NIL for any)."
  name function (minimum 0) (maximum nil) documentation)

(defvar *dialogue-actions* (make-hash-table :test 'equal)
  "The registered actions, by DIALOGUE-KEY of their names.")

(defun lambda-list-arity (lambda-list)
  "The minimum and maximum (NIL: no limit) argument counts LAMBDA-LIST takes."
  (let ((required (or (position-if (lambda (x) (member x lambda-list-keywords)) lambda-list)
                      (length lambda-list))))
    (values required
            (cond ((intersection '(&rest &key &body) lambda-list) nil)
                  ((member '&optional lambda-list)
                   (+ required (length (ldiff (rest (member '&optional lambda-list))
                                              (member-if (lambda (x) (member x lambda-list-keywords))
                                                         (rest (member '&optional lambda-list)))))))
                  (t required)))))

(defun register-dialogue-action (name function lambda-list &optional documentation)
  "Register FUNCTION, of a conversation and the arguments LAMBDA-LIST takes,
as the dialogue action NAME; return NAME."
  (multiple-value-bind (minimum maximum) (lambda-list-arity lambda-list)
    (setf (gethash (dialogue-key name) *dialogue-actions*)
          (%make-dialogue-action :name name :function function :minimum minimum :maximum maximum
                                 :documentation documentation)))
  name)

(defmacro define-dialogue-action (name (conversation &rest lambda-list) &body body)
  "Define the dialogue action NAME: BODY runs with CONVERSATION bound and the
action form's arguments (data, not evaluated) bound by LAMBDA-LIST.
Dialogues name it in their transitions as (NAME ARGUMENT...)."
  (let ((documentation (and (stringp (first body)) (rest body) (first body))))
    `(register-dialogue-action ',name (lambda (,conversation ,@lambda-list) ,@body)
                               ',lambda-list ,documentation)))

(defun find-dialogue-action (name)
  "The registered action NAME, or NIL."
  (and (symbolp name) (gethash (dialogue-key name) *dialogue-actions*)))

(defun run-action (conversation form)
  "Run the action FORM, (NAME ARGUMENT...), checked when its dialogue was defined."
  (apply (dialogue-action-function (find-dialogue-action (first form))) conversation (rest form)))

;;;# Checking action forms when a dialogue is defined

(defgeneric check-action-arguments (action dialogue arguments form)
  (:documentation "Signal a DIALOGUE-ERROR naming FORM (the transition or input
holding the action) when ARGUMENTS do not suit ACTION, a keyword of the
action's name, in DIALOGUE.  The default accepts any.")
  (:method (action dialogue arguments form)
    (declare (ignore action dialogue arguments form))))

(defun check-action (dialogue action form)
  "Signal a DIALOGUE-ERROR naming FORM unless ACTION is a registered action
called with arguments it takes."
  (unless (and (alexandria:proper-list-p action) action (symbolp (first action)))
    (dialogue-fail form "an action is (NAME ARGUMENT...), not ~A" (bounded-lisp-text action 80)))
  (let ((registered (find-dialogue-action (first action)))
        (count (length (rest action))))
    (unless registered
      (dialogue-fail form "unknown action ~A (known: ~{~A~^, ~})" (display-name (first action))
                     (sort (mapcar (lambda (a) (display-name (dialogue-action-name a)))
                                   (alexandria:hash-table-values *dialogue-actions*))
                           #'string-lessp)))
    (unless (and (>= count (dialogue-action-minimum registered))
                 (or (null (dialogue-action-maximum registered)) (<= count (dialogue-action-maximum registered))))
      (let ((minimum (dialogue-action-minimum registered))
            (maximum (dialogue-action-maximum registered)))
        (dialogue-fail form "action ~A takes ~A argument~:P, not ~D, in ~A"
                       (display-name (first action))
                       (cond ((eql minimum maximum) minimum)
                             ((null maximum) (format nil "~D or more" minimum))
                             (t (format nil "~D to ~D" minimum maximum)))
                       count (bounded-lisp-text action 80))))
    (check-action-arguments (intern (dialogue-key (first action)) :keyword) dialogue (rest action) form)))

;;;# The language's actions

(define-dialogue-action do (conversation animation)
  "Play ANIMATION: an animation of the dialogue, or an event of its Player spec."
  (conversation-do conversation animation))

(defmethod check-action-arguments ((action (eql :do)) dialogue arguments form)
  (let ((name (first arguments)))
    (unless (and (symbolp name) name
                 (or (gethash (dialogue-key name) (dialogue-animations dialogue))
                     (player-event-p dialogue name)))
      (dialogue-fail form "(do ~A): ~A is neither an animation of the dialogue nor an event of Player spec ~A"
                     (display-name name) (display-name name)
                     (if (dialogue-player-spec dialogue) (display-name (spec-name (dialogue-player-spec dialogue))) "(none)")))))

(define-dialogue-action say (conversation category)
  "Say a template of CATEGORY."
  (conversation-say conversation category))

(defmethod check-action-arguments ((action (eql :say)) dialogue arguments form)
  (unless (and (symbolp (first arguments)) (dialogue-category-templates dialogue (first arguments)))
    (dialogue-fail form "(say ~A): the template category ~A has no templates"
                   (display-name (first arguments)) (display-name (first arguments)))))

(define-dialogue-action set (conversation variable expression)
  "Set the context VARIABLE to EXPRESSION's value."
  (setf (context-value conversation variable) (evaluate-expression expression conversation)))

(defmethod check-action-arguments ((action (eql :set)) dialogue arguments form)
  (declare (ignore dialogue))
  (unless (and (symbolp (first arguments)) (first arguments) (not (keywordp (first arguments))))
    (dialogue-fail form "(set VAR EXPRESSION) needs a variable name, not ~A" (lisp-text (first arguments))))
  (check-expression (second arguments) form))

(defvar *mood-function* nil
  "NIL, or a function of (MOOD CONVERSATION) called when a transition sets the
mood (MOOD a keyword): a SPEAKER binds it (speaking.lisp), so the body's
gestures take the mood on (bigger and quicker when happy, smaller and slower
when sad; src/body/mood.lisp).")

(define-dialogue-action mood (conversation mood)
  "Set Peedy's emotional state towards this user to MOOD (happy, sad, neutral...);
with a speaker, his body performs in that mood from now on."
  (let ((mood (intern (dialogue-key mood) :keyword)))
    (setf (memory-mood (conversation-memory conversation)) mood)
    (when *mood-function* (funcall *mood-function* mood conversation))))

(defmethod check-action-arguments ((action (eql :mood)) dialogue arguments form)
  (declare (ignore dialogue))
  (unless (and (symbolp (first arguments)) (first arguments))
    (dialogue-fail form "(mood NAME) needs a name, not ~A" (lisp-text (first arguments)))))
