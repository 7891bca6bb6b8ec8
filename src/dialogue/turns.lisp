;;;; turns.lisp -- one turn of a conversation, Persona's loop: the sentence is
;;;; matched to an input event with slot values; the slots become context
;;;; variables, the input is remembered and its query runs; the first rule for
;;;; the current state and the event whose predicate holds is taken (rules for
;;;; the state before rules for any state, each in the order written); its
;;;; actions send Player events and say templates.

(in-package #:player.dialogue)

(defun dialogue-slot-names (dialogue)
  "The keys of every slot DIALOGUE's utterance patterns fill."
  (remove-duplicates (loop for utterance in (dialogue-utterances dialogue)
                           append (loop for element in (utterance-pattern-elements utterance)
                                        when (pattern-slot-p element)
                                          collect (dialogue-key (pattern-slot-name element))))
                     :test #'string=))

(defun find-transition (conversation event)
  "The transition CONVERSATION takes on EVENT from its state, or NIL."
  (let ((transitions (dialogue-transitions (conversation-dialogue conversation)))
        (state (conversation-state conversation)))
    (flet ((applies-p (transition from)
             (and (if (eq from :any) (eq (transition-from transition) :any)
                      (and (not (eq (transition-from transition) :any))
                           (same-name-p (transition-from transition) from)))
                  (same-name-p (transition-event transition) event)
                  (or (eq (transition-predicate transition) t)
                      (evaluate-expression (transition-predicate transition) conversation)))))
      (or (find-if (lambda (transition) (applies-p transition state)) transitions)
          (find-if (lambda (transition) (applies-p transition :any)) transitions)))))

(defun conversation-input (conversation event &key slots text (understood t))
  "Play one turn of CONVERSATION on the input EVENT (a name of its dialogue's
inputs) with SLOTS (an alist from slot names to values) heard as TEXT
(UNDERSTOOD NIL when no pattern matched it); return the TURN.  An unknown
EVENT is a DIALOGUE-ERROR."
  (let* ((dialogue (conversation-dialogue conversation))
         (input (check-input dialogue event nil))
         (event (input-name input))
         (slots (mapcar (lambda (pair) (cons (dialogue-key (car pair)) (cdr pair))) slots))
         (from (conversation-state conversation))
         (turn (make-turn :text text :event event :slots slots :from from :understood understood))
         (presenter (conversation-presenter conversation)))
    (setf (conversation-turn conversation) turn)
    (incf (conversation-turns conversation))
    ;; This turn's slots replace the last turn's: a stale title must not answer "who wrote that?".
    (dolist (key (dialogue-slot-names dialogue))
      (setf (context-value conversation key) (cdr (assoc key slots :test #'string=))))
    (loop for (key . value) in slots do (setf (context-value conversation key) value))
    (remember (conversation-memory conversation) :heard :event (display-name event) :text text :slots slots)
    (present-input presenter conversation event slots text)
    (dolist (action (input-query input)) (run-action conversation action))
    (let* ((transition (find-transition conversation event))
           (to (and transition (or (transition-to transition) from))))
      (setf (turn-transition turn) transition
            (turn-to turn) (or to from))
      (present-transition presenter conversation from event to)
      (when transition
        (setf (conversation-state conversation) to)
        (dolist (action (transition-actions transition)) (run-action conversation action))))
    (setf (conversation-turn conversation) nil)
    turn))

(defun conversation-hear (conversation text)
  "Play one turn of CONVERSATION on the sentence TEXT: an answer to the
question the last turn asked (\"the second one\", \"the one by clapton\";
offers.lisp) completes the input that asked it; otherwise TEXT is matched to
an input event and slots (MATCH-UTTERANCE), and a name two values of a slot
share (a surname) becomes the dialogue's :ambiguous input, with `choices`
set, when it declares one; then CONVERSATION-INPUT.  TEXT NIL (a recogniser
that heard nothing it knows) is the dialogue's not-understood event.  Return
the TURN."
  (check-argument 'conversation-hear :text text (lambda (x) (or (null x) (stringp x))) "a string or NIL")
  (let ((dialogue (conversation-dialogue conversation))
        (offer (shiftf (conversation-offer conversation) nil)))
    (multiple-value-bind (answer answer-slots) (and offer text (resolve-fragment offer text))
      (when answer
        (return-from conversation-hear (conversation-input conversation answer :slots answer-slots :text text))))
    (multiple-value-bind (event slots understood) (match-utterance dialogue (or text ""))
      (unless event
        (dialogue-fail nil "~S matches no utterance, and the dialogue names no :not-understood event" text))
      (multiple-value-bind (key values) (and understood (dialogue-ambiguous dialogue) (ambiguous-slot dialogue text slots))
        (if key
            (progn
              (setf (context-value conversation "choices")
                    (format nil "~{~A~#[~; or ~:;, ~]~}" (mapcar #'template-value-text values)))
              (prog1 (conversation-input conversation (dialogue-ambiguous dialogue) :text text)
                (setf (conversation-offer conversation) (make-offer :event event :slots slots :slot key :values values))))
            (conversation-input conversation event :slots slots :text text :understood understood))))))

;;;# Printing a conversation

(defclass text-presenter (dialogue-presenter)
  ((stream :initarg :stream :initform *standard-output* :reader presenter-stream))
  (:documentation "Prints each turn on STREAM, one line a step, as `chat` shows it:
  input: evHaveYouGot artist=\"Bonnie Raitt\"
  transition: stAttending --evHaveYouGot--> stGotCD
  peedy: \"i have The Bonnie Raitt Collection from 1990\""))

(defun make-text-presenter (&key (stream *standard-output*))
  "A TEXT-PRESENTER printing to STREAM."
  (make-instance 'text-presenter :stream stream))

(defmethod present-input ((presenter text-presenter) conversation event slots text)
  (declare (ignore text))
  (format (presenter-stream presenter) "input: ~A~:{ ~(~A~)=~S~}~:[ (not understood)~;~]~%"
          (display-name event) (mapcar (lambda (pair) (list (car pair) (template-value-text (cdr pair)))) slots)
          (turn-understood (conversation-turn conversation))))

(defmethod present-transition ((presenter text-presenter) conversation from event to)
  (declare (ignore conversation))
  (format (presenter-stream presenter) "transition: ~A --~A--> ~A~:[ (no rule)~;~]~%"
          (display-name from) (display-name event) (display-name (or to from)) to))

(defmethod present-utterance ((presenter text-presenter) conversation text category)
  (declare (ignore conversation category))
  (format (presenter-stream presenter) "peedy: ~S~%" text))
