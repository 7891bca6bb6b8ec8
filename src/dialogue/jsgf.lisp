;;;; jsgf.lisp -- the speech recogniser's grammar, made from the dialogue's
;;;; utterance patterns in the spirit of Persona's Figure 3 (STATEMENT play
;;;; something by ARTIST TIMEREF): one rule per input event, one per slot
;;;; (its alternatives the catalogue's names or a phrases set), and the public
;;;; <request> rule, any input event.  JSGF 1.0, as pocketsphinx reads it.

(in-package #:player.dialogue)

(defun jsgf-rule-name (name)
  "NAME as a JSGF rule name: lower case, letters, digits and underscores."
  (map 'string (lambda (c) (if (alphanumericp c) (char-downcase c) #\_)) (display-name name)))

(defun jsgf-element (element)
  "The JSGF text of the pattern ELEMENT."
  (let ((text (if (pattern-words-p element)
                  (format nil "~{~A~^ ~}" (pattern-words-words element))
                  (format nil "<~A>" (jsgf-rule-name (pattern-slot-name element))))))
    (if (pattern-optional-p element) (format nil "[~A]" text) text)))

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
      (format out "public <request> = ~{<~A>~^ | ~};~2%" (mapcar #'jsgf-rule-name events))
      (dolist (event events)
        (format out "<~A> = ~{~A~^~%    | ~};~%" (jsgf-rule-name event)
                (loop for utterance in (dialogue-utterances dialogue)
                      when (same-name-p (utterance-pattern-event utterance) event)
                        collect (format nil "~{~A~^ ~}" (mapcar #'jsgf-element (utterance-pattern-elements utterance))))))
      (terpri out)
      (dolist (slot slots)
        (format out "<~A> = ~{~A~^~%    | ~};~%" (jsgf-rule-name (pattern-slot-name slot))
                (remove-duplicates (mapcar (lambda (alternative) (format nil "~{~A~^ ~}" (car alternative)))
                                           (pattern-slot-alternatives slot))
                                   :test #'string= :from-end t))))))
