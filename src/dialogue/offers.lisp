;;;; offers.lisp -- context that answers a question (Persona's "context
;;;; dependent" reference): when a request names an artist by a surname two
;;;; artists share, Peedy asks which one, and the answer is a fragment that
;;;; resolves against what he offered: "the one by clapton", "joe jackson",
;;;; "the second one", "the last".  An OFFER is the input a choice completes
;;;; (its event and the slots already known) and the slot its values fill.
;;;; A dialogue says what asking is with (:ambiguous EVENT): that input
;;;; arrives with the context variable `choices` set to the values ("Joe
;;;; Jackson or Janet Jackson"), and its rule says the question.

(in-package #:player.dialogue)

(defstruct offer
  "A question Peedy asked: the input EVENT the answer completes, the SLOTS it
already has (an alist), the SLOT (a key) the answer fills and the VALUES
offered, in the order said."
  event slots slot values)

(defparameter *ordinal-words*
  '(("first" . 0) ("second" . 1) ("third" . 2) ("fourth" . 3) ("1st" . 0) ("2nd" . 1) ("3rd" . 2)
    ("one" . 0) ("two" . 1) ("three" . 2) ("last" . :last) ("latter" . :last) ("former" . 0))
  "Words that choose an offered value by its place.  \"one\" only counts
after \"number\" (\"the one by clapton\" names no place).")

(defun ordinal-choice (words count)
  "The index WORDS choose by place among COUNT values, or NIL."
  (loop for previous = nil then word
        for word in words
        for entry = (assoc word *ordinal-words* :test #'string=)
        when (and entry (or (not (member word '("one" "two" "three") :test #'string=))
                            (equal previous "number")))
          do (let ((index (if (eq (cdr entry) :last) (1- count) (cdr entry))))
               (when (< index count) (return index)))))

(defun naming-choice (words values)
  "The index of the one of VALUES whose name WORDS say (all its words, or its
words no other value has), or NIL when they name none or several."
  (let ((named (loop for value in values
                     for index from 0
                     for own = (remove-if (lambda (word)
                                            (some (lambda (other) (and (not (eq other value))
                                                                       (member word (text-words (template-value-text other))
                                                                               :test #'string=)))
                                                  values))
                                          (text-words (template-value-text value)))
                     when (and own (every (lambda (word) (member word words :test #'string=)) own))
                       collect index)))
    (and named (null (rest named)) (first named))))

(defun resolve-fragment (offer text)
  "The input TEXT means as an answer to OFFER, as (VALUES EVENT SLOTS), or NIL
when it chooses none of its values."
  (let* ((words (text-words text))
         (values (offer-values offer))
         (index (or (naming-choice words values) (ordinal-choice words (length values)))))
    (when index
      (values (offer-event offer)
              (append (remove (offer-slot offer) (offer-slots offer) :key #'car :test #'string=)
                      (list (cons (offer-slot offer) (nth index values))))))))

(defun ambiguous-slot (dialogue text slots)
  "The first of SLOTS (the matcher's alist for TEXT) whose value was named by
words that name other values of its slot just as plausibly (a surname two
artists share), as (VALUES KEY VALUES), or NIL."
  (let* ((words (text-words text))
         (mentions (find-mentions (dialogue-slot-forms dialogue) words)))
    (loop for (key . value) in slots
          for mention = (find-if (lambda (m) (and (string= (mention-slot m) key) (equal (mention-value m) value)))
                                 mentions)
          for rivals = (and mention
                            (remove-duplicates
                             (loop for other in mentions
                                   when (and (string= (mention-slot other) key)
                                             (= (mention-start other) (mention-start mention))
                                             (= (mention-end other) (mention-end mention))
                                             (= (mention-plausibility other) (mention-plausibility mention)))
                                     collect (mention-value other))
                             :test #'equal))
          when (rest rivals)
            do (return (values key rivals)))))
