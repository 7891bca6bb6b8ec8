;;;; patterns.lisp -- what a user may say for an input event: an utterance
;;;; pattern, (utterance EVENT ELEMENT...), is a sequence of words ("play
;;;; something by"), slots, (:slot NAME), filled by one of NAME's forms (the
;;;; catalogue's `artist`, `title` or `album`, or a (phrases NAME "..." ...)
;;;; set; mentions.lisp), and optional parts, (:optional ELEMENT).  Pattern
;;;; words are kept in the dialogue's canonical vocabulary (vocabulary.lisp).
;;;; The matcher scores sentences against them (matcher.lisp); the same
;;;; patterns give the speech recogniser its grammar (jsgf.lisp).

(in-package #:player.dialogue)

(defstruct utterance-pattern
  "A pattern: the input EVENT it means, its ELEMENTS (PATTERN-WORDS and
PATTERN-SLOT structs) and the FORM as written."
  event elements form)

(defstruct pattern-words
  "Words to say, in order; OPTIONAL when they may be left out."
  words optional)

(defstruct pattern-slot
  "A slot: its NAME, the context variable its value goes to, its FORMS (see
SLOT-FORMS), the ALTERNATIVES a grammar offers ((WORDS . VALUE) pairs,
longest first), and whether it is OPTIONAL."
  name forms alternatives optional)

(defun slot-alternatives (forms)
  "The (WORDS . VALUE) alternatives a grammar offers for a slot of FORMS
(SLOT-FORMS): all but the loose ones, longest first."
  (loop for form in forms
        unless (loose-form-p form) collect (cons (first form) (second form))))

(defun make-slot-element (dialogue name form optional)
  "The PATTERN-SLOT for the slot NAME of the utterance FORM."
  (let ((forms (slot-forms dialogue name form)))
    (make-pattern-slot :name name :optional optional :forms forms :alternatives (slot-alternatives forms))))

(defun parse-pattern-element (dialogue element form &optional optional)
  "The pattern element ELEMENT of the utterance FORM describes."
  (cond ((and (stringp element) (text-words element))
         ;; Pattern words are kept in canonical form, as sentences are matched.
         (make-pattern-words :words (values (canonical-words (dialogue-rewrites dialogue) (text-words element)))
                             :optional optional))
        ((and (not optional) (alexandria:proper-list-p element) (= (length element) 2)
              (eq (first element) :optional))
         (let ((inner (second element)))
           (if (and (symbolp inner) inner (not (keywordp inner)))
               (make-slot-element dialogue inner form t)
               (parse-pattern-element dialogue inner form t))))
        ((and (alexandria:proper-list-p element) (= (length element) 2) (eq (first element) :slot)
              (symbolp (second element)) (second element))
         (make-slot-element dialogue (second element) form optional))
        (t (dialogue-fail form "a pattern element is a string of words, (:slot NAME) or (:optional ELEMENT), not ~A"
                          (bounded-lisp-text element 60)))))

(defun pattern-optional-p (element)
  "May ELEMENT be left out?"
  (if (pattern-words-p element) (pattern-words-optional element) (pattern-slot-optional element)))
