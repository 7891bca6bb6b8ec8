;;;; conversation.lisp -- one conversation with one user: the dialogue's
;;;; current state, the context variables, the user's episodic memory, a
;;;; seeded random source, and the Player controller the dialogue animates.
;;;; What happens is told to a DIALOGUE-PRESENTER; every generic function of
;;;; the protocol has a default that does nothing, so a presenter defines only
;;;; what it shows (the chat command prints; a speech module speaks).

(in-package #:player.dialogue)

(defclass dialogue-presenter () ()
  (:documentation "Told what a conversation does; the base class ignores everything."))

(defgeneric present-input (presenter conversation event slots text)
  (:documentation "The input TEXT was understood as EVENT with SLOTS (an alist
of slot name and value strings); EVENT is the not-understood event when nothing matched.")
  (:method ((presenter dialogue-presenter) conversation event slots text)
    (declare (ignore conversation event slots text))))

(defgeneric present-transition (presenter conversation from event to)
  (:documentation "The conversation went from state FROM to state TO on EVENT;
TO is NIL when no rule of the dialogue applied (the state stays FROM).")
  (:method ((presenter dialogue-presenter) conversation from event to)
    (declare (ignore conversation from event to))))

(defgeneric present-utterance (presenter conversation text category)
  (:documentation "Peedy says TEXT, a template of CATEGORY expanded.  Called
before the Player events the transition sends after it.")
  (:method ((presenter dialogue-presenter) conversation text category)
    (declare (ignore conversation text category))))

(defvar *say-function* nil
  "NIL, or a function of TEXT and CONVERSATION called each time Peedy says
something, after the presenter is told: the hook a speech synthesiser plugs
into (the conversation's controller gives the Player clock to sync the beak to).")

(defstruct (conversation (:constructor %make-conversation))
  "A conversation: its DIALOGUE, current STATE, CONTEXT variables (a hash
table by DIALOGUE-KEY), the user's episodic MEMORY, the RANDOM-STATE
templates and selections draw from, the Player CONTROLLER (or NIL), the
PRESENTER, the PLAYER-EVENTS sent so far (newest first), the TURN
being played (a TURN, or NIL) and the OFFER the last turn asked the user
to choose from (an OFFER, or NIL; offers.lisp)."
  dialogue state (context (make-hash-table :test 'equal)) memory random-state
  controller (presenter (make-instance 'dialogue-presenter)) (player-events '()) turn (turns 0) offer)

(defstruct turn
  "One turn: the user's TEXT (or NIL when an event was given directly),
whether a pattern UNDERSTOOD it, the input EVENT and its SLOTS, the states
FROM and TO, the TRANSITION taken (or NIL), the Player EVENTS sent and the
UTTERANCES said, in order."
  text (understood t) event slots from to transition (events '()) (utterances '()))

(defun make-conversation (dialogue &key (seed 0) memory controller presenter (user "user"))
  "Begin a conversation of DIALOGUE (a dialogue or its name) in its initial
state, with templates drawn from a random source seeded with SEED, the
episodic MEMORY (a fresh one of USER by default; a new conversation is
counted in it), the Player CONTROLLER its transitions send events to (NIL:
events are only recorded) and PRESENTER (a DIALOGUE-PRESENTER)."
  (let ((dialogue (find-dialogue dialogue)))
    (check-argument 'make-conversation :seed seed (lambda (x) (typep x '(integer 0))) "a non-negative integer")
    (let ((memory (or memory (make-memory :user user))))
      (begin-conversation memory)
      (%make-conversation :dialogue dialogue :state (dialogue-initial-state dialogue)
                          :memory memory :random-state (sb-ext:seed-random-state seed)
                          :controller controller
                          :presenter (or presenter (make-instance 'dialogue-presenter))))))

(defun context-value (conversation name)
  "The context variable NAME of CONVERSATION (NIL when unset); `mood` is the memory's mood."
  (if (same-name-p name "mood")
      (memory-mood (conversation-memory conversation))
      (values (gethash (dialogue-key name) (conversation-context conversation)))))

(defun (setf context-value) (value conversation name)
  "Set the context variable NAME of CONVERSATION to VALUE."
  (setf (gethash (dialogue-key name) (conversation-context conversation)) value))

(defun conversation-random (conversation limit)
  "A random number below LIMIT from CONVERSATION's seeded source."
  (random limit (conversation-random-state conversation)))

(defun conversation-do (conversation name)
  "Play the animation NAME: send its Player events (or the Player event NAME)
to the conversation's controller, recording them for the turn."
  (let* ((dialogue (conversation-dialogue conversation))
         (animation (gethash (dialogue-key name) (dialogue-animations dialogue))))
    (dolist (event (if animation (animation-events animation) (list name)))
      (push event (conversation-player-events conversation))
      (when (conversation-turn conversation)
        (alexandria:appendf (turn-events (conversation-turn conversation)) (list event)))
      (when (conversation-controller conversation)
        (send-event (conversation-controller conversation) event)))))

(defun conversation-say (conversation category)
  "Say a template of CATEGORY: choose one by the cascade, expand it, remember
it, tell the presenter and *SAY-FUNCTION*; return the text."
  (let* ((template (choose-template conversation category))
         (marked (expand-template-marked template conversation))
         (text (values (gesture-marks marked))))       ; the speaker lands the marks' gestures
    (remember (conversation-memory conversation) :said
              :category (display-name (template-category template)) :template (template-index template) :text text)
    (when (conversation-turn conversation)
      (alexandria:appendf (turn-utterances (conversation-turn conversation)) (list text)))
    (present-utterance (conversation-presenter conversation) conversation text category)
    (when *say-function* (funcall *say-function* marked conversation))
    text))
