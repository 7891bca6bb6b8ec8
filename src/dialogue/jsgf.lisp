;;;; jsgf.lisp -- the speech recogniser's grammar, made from the dialogue's
;;;; utterance patterns in the spirit of Persona's Figure 3 (STATEMENT play
;;;; something by ARTIST TIMEREF): one rule per input event, one per slot
;;;; (its alternatives the catalogue's names, surnames too, or a phrases
;;;; set), the public <request> rule, any input event, perhaps after a
;;;; filler ("could you", "i'd like to"), and each canonical word offered with
;;;; its synonyms.  JSGF 1.0, as pocketsphinx reads it.

(in-package #:player.dialogue)

(defun jsgf-rule-name (name)
  "NAME as a JSGF rule name: lower case, letters, digits and underscores."
  (map 'string (lambda (c) (if (alphanumericp c) (char-downcase c) #\_)) (display-name name)))

(defun jsgf-phrase (phrases)
  "The JSGF text of one of PHRASES (word lists): the phrase, or (A | B ...)."
  (flet ((text (phrase) (format nil "~{~A~^ ~}" phrase)))
    (if (rest phrases)
        (format nil "(~{~A~^ | ~})" (mapcar #'text phrases))
        (text (first phrases)))))

(defun jsgf-words (rewrites words)
  "The JSGF text of the canonical WORDS, each canonical phrase of REWRITES
there offered with its synonyms: play something -> (play | hear | spin ...) (something | anything ...)."
  (let ((canonicals (remove-duplicates (loop for rewrite in rewrites
                                             when (eq (rewrite-kind rewrite) :synonym)
                                               collect (rewrite-replacement rewrite))
                                       :test #'equal))
        (parts '()))
    (loop while words
          do (let ((canonical (first (sort (remove-if-not (lambda (c) (and (<= (length c) (length words))
                                                                            (every #'string= c words)))
                                                          canonicals)
                                           #'> :key #'length))))
               (if canonical
                   (progn (push (jsgf-phrase (synonym-alternatives rewrites canonical)) parts)
                          (setf words (nthcdr (length canonical) words)))
                   (push (pop words) parts))))
    (format nil "~{~A~^ ~}" (nreverse parts))))

(defun jsgf-element (rewrites element)
  "The JSGF text of the pattern ELEMENT, its words offered with their synonyms in REWRITES."
  (let ((text (if (pattern-words-p element)
                  (jsgf-words rewrites (pattern-words-words element))
                  (format nil "<~A>" (jsgf-rule-name (pattern-slot-name element))))))
    (if (pattern-optional-p element) (format nil "[~A]" text) text)))

(defun jsgf-fillers (rewrites)
  "The filler phrases of REWRITES of two words or more (\"could you\", \"i'd
like to\"), as JSGF alternatives, or NIL.  Single filler words (\"um\",
\"please\") are left out: offered anywhere, the recogniser hears them in
every breath (spoken requests in test-persona-loop were heard with a stray \"uh\")."
  (let ((fillers (loop for rewrite in rewrites
                       when (and (eq (rewrite-kind rewrite) :filler) (rest (rewrite-words rewrite)))
                         collect (rewrite-words rewrite))))
    (and fillers (format nil "~{~{~A~^ ~}~^ | ~}" fillers))))

(defun dialogue-jsgf (dialogue)
  "The JSGF 1.0 grammar of what DIALOGUE (a dialogue or its name) understands,
as a string: a public <request> rule, a rule per input event with a pattern,
a rule per slot listing its alternatives.  Every sentence the grammar
generates is matched by MATCH-UTTERANCE."
  (let* ((dialogue (find-dialogue dialogue))
         (events (remove-duplicates (mapcar #'utterance-pattern-event (dialogue-utterances dialogue))
                                    :test #'same-name-p :from-end t))
         (slots (remove-duplicates (loop for utterance in (dialogue-utterances dialogue)
                                         append (remove-if-not #'pattern-slot-p (utterance-pattern-elements utterance)))
                                   :key (lambda (slot) (dialogue-key (pattern-slot-name slot)))
                                   :test #'string= :from-end t)))
    (with-output-to-string (out)
      (format out "#JSGF V1.0;~2%grammar ~A;~2%" (jsgf-rule-name (dialogue-name dialogue)))
      (let ((fillers (jsgf-fillers (dialogue-rewrites dialogue)))
            (events (format nil "~{<~A>~^ | ~}" (mapcar #'jsgf-rule-name events))))
        (if fillers
            (format out "public <request> = [<filler>] (~A);~%<filler> = ~A;~2%" events fillers)
            (format out "public <request> = ~A;~2%" events)))
      (dolist (event events)
        (format out "<~A> = ~{~A~^~%    | ~};~%" (jsgf-rule-name event)
                (loop for utterance in (dialogue-utterances dialogue)
                      when (same-name-p (utterance-pattern-event utterance) event)
                        collect (format nil "~{~A~^ ~}" (mapcar (lambda (element) (jsgf-element (dialogue-rewrites dialogue) element))
                                                                         (utterance-pattern-elements utterance))))))
      (terpri out)
      (dolist (slot slots)
        (format out "<~A> = ~{~A~^~%    | ~};~%" (jsgf-rule-name (pattern-slot-name slot))
                (remove-duplicates (mapcar (lambda (alternative) (format nil "~{~A~^ ~}" (car alternative)))
                                           (pattern-slot-alternatives slot))
                                   :test #'string= :from-end t))))))
