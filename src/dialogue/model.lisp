;;;; model.lisp -- what a parsed dialogue is made of (Persona, "Dialogue
;;;; Management"): conversational states, input events with the utterances
;;;; that say them, transitions (Figures 7 and 8), verbal templates by
;;;; category (Figure 9), animations naming Player events, and a catalogue.

(in-package #:player.dialogue)

(defstruct (dialogue (:constructor %make-dialogue))
  "A conversational state machine.  STATES, INPUTS, TEMPLATES and ANIMATIONS
are hash tables by DIALOGUE-KEY; TRANSITIONS a list in the order written;
UTTERANCES the input patterns in the order written; REWRITES its synonyms
and fillers (vocabulary.lisp), longest first; PHRASES named word
alternatives for patterns; PLAYER-SPEC the Player spec whose events animate
it, with PLAYER-INITIAL its initial state (an alist); CATALOGUE the music."
  (name nil)
  (documentation nil)
  (source-file nil)
  (initial-state nil)
  (states (make-hash-table :test 'equal))
  (state-order '())
  (inputs (make-hash-table :test 'equal))
  (not-understood nil)
  (ambiguous nil)
  (ignore-words '())
  (rewrites '())
  (utterances '())
  (phrases (make-hash-table :test 'equal))
  (transitions '())
  (templates (make-hash-table :test 'equal))
  (animations (make-hash-table :test 'equal))
  (player-spec nil)
  (player-initial '())
  (catalogue nil))

(defstruct (input-def (:conc-name input-))
  "An input event: its NAME, DOCUMENTATION and QUERY, action forms run when
it arrives, before a transition is chosen; FORM as written (Persona's object evaluation:
\"the result is stored in context variables, then the input event is sent\")."
  name documentation (query '()) form)

(defstruct transition
  "A rule: in state FROM (a state name, or :ANY), on input EVENT, when
PREDICATE (an expression, or T) holds, go to TO (NIL: stay) doing ACTIONS
(action forms, in order).  FORM is the rule as written."
  from event (predicate t) to (actions '()) form)

(defstruct template
  "A verbal template of CATEGORY: taken with PROBABILITY when the cascade
reaches it (Figure 9), if its CONDITION holds and its LIMIT (NIL,
:CONVERSATION or :USER: at most once in that span) allows; TEXT with <=Var>
holes.  INDEX is its place in its category, counted from 1."
  category probability text condition limit index form)

(defstruct animation
  "A name of the paper's (pePickTrack) for the Player EVENTS it plays."
  name events form)

(defvar *dialogues* (make-hash-table :test 'equal)
  "The defined dialogues, by DIALOGUE-KEY of their names.")

(defun find-dialogue (name &optional (errorp t))
  "The dialogue called NAME (a symbol or string), or NIL; with ERRORP a
DIALOGUE-ERROR naming the known ones."
  (or (and (dialogue-p name) name)
      (gethash (dialogue-key name) *dialogues*)
      (and errorp
           (dialogue-fail nil "no dialogue ~A is defined (known: ~{~A~^, ~})" (display-name name)
                          (mapcar #'display-name (mapcar #'dialogue-name (alexandria:hash-table-values *dialogues*)))))))

(defun dialogue-state-names (dialogue)
  "DIALOGUE's conversational states, in the order declared."
  (reverse (dialogue-state-order dialogue)))

(defun dialogue-input-names (dialogue)
  "DIALOGUE's input events' names."
  (mapcar #'input-name (alexandria:hash-table-values (dialogue-inputs dialogue))))

(defun dialogue-category-templates (dialogue category)
  "The templates of CATEGORY, in the order written."
  (gethash (dialogue-key category) (dialogue-templates dialogue)))
