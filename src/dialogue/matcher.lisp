;;;; matcher.lisp -- from a recognised sentence to an input event with slot
;;;; values: Persona's action templates, kept simple.  An utterance pattern,
;;;; (utterance EVENT ELEMENT...), is a sequence of words ("play something
;;;; by"), slots, (:slot NAME), filled by one of NAME's alternatives (the
;;;; catalogue's `artist`, `title` or `album`, or a (phrases NAME "..." ...)
;;;; set), and optional parts, (:optional ELEMENT).  The same patterns give the
;;;; speech recogniser its grammar (jsgf.lisp), so what can be said can be matched.

(in-package #:player.dialogue)

(defstruct utterance-pattern
  "A pattern: the input EVENT it means, its ELEMENTS (PATTERN-WORDS and
PATTERN-SLOT structs) and the FORM as written."
  event elements form)

(defstruct pattern-words
  "Words to say, in order; OPTIONAL when they may be left out."
  words optional)

(defstruct pattern-slot
  "A slot: its NAME, the context variable its value goes to, its ALTERNATIVES
((WORDS . VALUE) pairs, longest first), and whether it is OPTIONAL."
  name alternatives optional)

(defun slot-alternatives (dialogue name form)
  "The (WORDS . VALUE) alternatives of the slot NAME in DIALOGUE, longest first:
a phrases set of the dialogue, or the catalogue's artists, titles or albums."
  (let ((values (or (gethash (dialogue-key name) (dialogue-phrases dialogue))
                    (let ((catalogue (dialogue-catalogue dialogue)))
                      (alexandria:switch ((dialogue-key name) :test #'string=)
                        ("ARTIST" (catalogue-artists catalogue))
                        ("TITLE" (catalogue-titles catalogue))
                        ("ALBUM" (catalogue-albums catalogue))))
                    (dialogue-fail form "unknown slot ~A: not a phrases set of the dialogue, nor artist, title or album of its catalogue"
                                   (display-name name)))))
    (stable-sort (mapcar (lambda (value) (cons (text-words value) value)) values)
          #'> :key (lambda (alternative) (length (car alternative))))))

(defun parse-pattern-element (dialogue element form &optional optional)
  "The pattern element ELEMENT of the utterance FORM describes."
  (cond ((and (stringp element) (text-words element))
         (make-pattern-words :words (text-words element) :optional optional))
        ((and (not optional) (alexandria:proper-list-p element) (= (length element) 2)
              (eq (first element) :optional))
         (let ((inner (second element)))
           (if (and (symbolp inner) inner (not (keywordp inner)))
               (make-pattern-slot :name inner :alternatives (slot-alternatives dialogue inner form) :optional t)
               (parse-pattern-element dialogue inner form t))))
        ((and (alexandria:proper-list-p element) (= (length element) 2) (eq (first element) :slot)
              (symbolp (second element)) (second element))
         (make-pattern-slot :name (second element) :optional optional
                            :alternatives (slot-alternatives dialogue (second element) form)))
        (t (dialogue-fail form "a pattern element is a string of words, (:slot NAME) or (:optional ELEMENT), not ~A"
                          (bounded-lisp-text element 60)))))

(defun match-elements (elements words slots)
  "Match ELEMENTS against WORDS exactly; the slot alist (SLOTS, extended), or :FAIL."
  (cond ((null elements) (if words :fail slots))
        (t (let ((result (match-element (first elements) (rest elements) words slots)))
             ;; An optional element may also be left out.
             (if (and (eq result :fail) (pattern-optional-p (first elements)))
                 (match-elements (rest elements) words slots)
                 result)))))

(defgeneric match-element (element rest words slots)
  (:documentation "Match ELEMENT at the start of WORDS, then the elements
REST against what follows; the slot alist (SLOTS, extended), or :FAIL."))

(defmethod match-element ((element pattern-words) rest words slots)
  (let ((n (length (pattern-words-words element))))
    (if (and (>= (length words) n) (every #'string= (pattern-words-words element) words))
        (match-elements rest (nthcdr n words) slots)
        :fail)))

(defmethod match-element ((element pattern-slot) rest words slots)
  ;; Alternatives are tried longest first; the first that lets the rest match wins.
  (loop for (alternative . value) in (pattern-slot-alternatives element)
        for n = (length alternative)
        for result = (if (and (>= (length words) n) (every #'string= alternative words))
                         (match-elements rest (nthcdr n words)
                                         (acons (dialogue-key (pattern-slot-name element)) value slots))
                         :fail)
        unless (eq result :fail) return result
        finally (return :fail)))

(defun pattern-optional-p (element)
  "May ELEMENT be left out?"
  (if (pattern-words-p element) (pattern-words-optional element) (pattern-slot-optional element)))

(defun match-utterance (dialogue text)
  "The input event TEXT means in DIALOGUE and its slots, as (VALUES EVENT
SLOTS MATCHED); SLOTS an alist from slot keys (upper-case strings) to values.
The first pattern that matches all of TEXT's words (the dialogue's ignored
words, such as \"please\", left out) wins; none matching gives the dialogue's
not-understood event, no slots and MATCHED NIL."
  (let ((words (remove-if (lambda (word) (member word (dialogue-ignore-words dialogue) :test #'string=))
                          (text-words text))))
    (dolist (utterance (dialogue-utterances dialogue) (values (dialogue-not-understood dialogue) '() nil))
      (let ((slots (match-elements (utterance-pattern-elements utterance) words '())))
        (unless (eq slots :fail)
          (return (values (utterance-pattern-event utterance) (reverse slots) t)))))))
