;;;; vocabulary.lisp -- Persona's paraphrase rules that need no parser
;;;; ("Application-Specific Transformations"): synonyms become one abstract
;;;; word ("spin", "put on", "how about" become `play`), and verbal artifacts
;;;; and expressions of desire are dropped ("let's see", "i'd like to", "could
;;;; you"), so "Let's see, I'd like to hear some Madonna" reads "play
;;;; something madonna".  A dialogue declares its own sets:
;;;;   (synonyms "play" "hear" "put on" "spin" ...)   the first is the canonical form
;;;;   (fillers "let's see" "i think" ...)            words that mean nothing here
;;;; Function words (below) cost little when said but absent from a pattern.

(in-package #:player.dialogue)

(defparameter *function-words*
  '("a" "an" "the" "to" "of" "in" "on" "at" "by" "for" "from" "with" "and" "or"
    "me" "my" "i" "you" "your" "it" "its" "this" "that" "is" "are" "be" "just"
    "now" "well" "so" "oh" "um" "uh" "er" "very" "much" "lot" "really" "then"
    "there" "again" "one" "some" "any")
  "Words that carry little meaning on their own: an extra one in a sentence
costs little, and so does one a pattern has and the sentence lacks.  Shared
by every dialogue, since they are English's, not the domain's.")

(defconstant +function-word-weight+ 0.2
  "What a function word weighs against a content word's 1.")

(defun word-weight (word)
  "How much WORD (a lower-case string) counts when it is missing or extra: 1,
or +FUNCTION-WORD-WEIGHT+ for a function word."
  (if (member word *function-words* :test #'string=) +function-word-weight+ 1.0))

(defstruct (rewrite (:constructor make-rewrite (words replacement kind)))
  "One vocabulary rule: the WORDS said, the REPLACEMENT words they become (NIL
drops them) and its KIND, :synonym or :filler."
  words replacement kind)

(defun parse-synonyms-form (form)
  "The rewrites (synonyms \"CANONICAL\" \"PHRASE\"...) declares: each phrase,
and the canonical form itself, become the canonical form's words."
  (unless (and (cddr form) (every (lambda (p) (and (stringp p) (text-words p))) (rest form)))
    (dialogue-fail form "(synonyms \"CANONICAL\" \"PHRASE\" ...) needs strings of words"))
  (let ((canonical (text-words (second form))))
    (mapcar (lambda (phrase) (make-rewrite (text-words phrase) canonical :synonym)) (rest form))))

(defun parse-fillers-form (form)
  "The rewrites (fillers \"PHRASE\"...) declares: each phrase is dropped."
  (unless (and (rest form) (every (lambda (p) (and (stringp p) (text-words p))) (rest form)))
    (dialogue-fail form "(fillers \"PHRASE\" ...) needs strings of words"))
  (mapcar (lambda (phrase) (make-rewrite (text-words phrase) '() :filler)) (rest form)))

(defun sort-rewrites (rewrites)
  "REWRITES, longest phrase first, so \"let's hear\" wins over \"let's\"."
  (stable-sort (copy-list rewrites) #'> :key (lambda (rewrite) (length (rewrite-words rewrite)))))

(defun rewrite-at (rewrites words)
  "The first of REWRITES (longest first) whose words begin WORDS, or NIL."
  (find-if (lambda (rewrite)
             (let ((phrase (rewrite-words rewrite)))
               (and (<= (length phrase) (length words)) (every #'string= phrase words))))
           rewrites))

(defun canonical-words (rewrites words)
  "WORDS rewritten by REWRITES (longest match first, left to right, one
pass), as (VALUES CANONICAL-WORDS NOTES): NOTES say, for explanations, what
became what."
  (let ((out '()) (notes '()))
    (loop while words
          do (let ((rewrite (rewrite-at rewrites words)))
               (cond ((null rewrite) (push (pop words) out))
                     (t (let ((said (subseq words 0 (length (rewrite-words rewrite)))))
                          (unless (equal said (rewrite-replacement rewrite))
                            (push (if (rewrite-replacement rewrite)
                                      (format nil "~S is ~S" (format nil "~{~A~^ ~}" said)
                                              (format nil "~{~A~^ ~}" (rewrite-replacement rewrite)))
                                      (format nil "~S dropped" (format nil "~{~A~^ ~}" said)))
                                  notes))
                          (setf words (nthcdr (length said) words))
                          (dolist (word (rewrite-replacement rewrite)) (push word out)))))))
    (values (nreverse out) (nreverse notes))))

(defun synonym-alternatives (rewrites canonical)
  "The phrases (word lists) REWRITES make into CANONICAL (a word list),
CANONICAL first: the alternatives a grammar offers for it."
  (cons canonical
        (remove canonical
                (mapcar #'rewrite-words
                        (remove-if-not (lambda (rewrite) (and (eq (rewrite-kind rewrite) :synonym)
                                                              (equal (rewrite-replacement rewrite) canonical)))
                                       rewrites))
                :test #'equal)))
