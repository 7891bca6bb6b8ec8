;;;; templates.lisp -- verbal responses by template expansion (Persona,
;;;; Figure 9).  A category's templates are tried in order, each taken with its
;;;; probability: for four equally likely ones, 0.25, then 0.333, 0.5, 1.
;;;; A template whose condition fails, or whose limit (once per conversation
;;;; or per user) is used up, is passed over.  The chosen text's <=Var> holes
;;;; are filled from the context variables.

(in-package #:player.dialogue)

(defun template-allowed-p (template conversation)
  "May TEMPLATE be said now: does its condition hold and its limit allow it?"
  (and (or (null (template-condition template))
           (evaluate-expression (template-condition template) conversation))
       (not (and (template-limit template)
                 (memory-template-used-p (conversation-memory conversation) template
                                         (template-limit template))))))

(defun choose-template (conversation category)
  "A template of CATEGORY chosen by the cascade from CONVERSATION's random
source: the first allowed template with its probability, else the next...
When the draws pass them all, the last allowed one; when none is allowed, the
last whose condition holds.  A DIALOGUE-ERROR when no template fits."
  (let* ((templates (dialogue-category-templates (conversation-dialogue conversation) category))
         (allowed (remove-if-not (lambda (template) (template-allowed-p template conversation)) templates)))
    (or (find-if (lambda (template)
                   (< (random 1d0 (conversation-random-state conversation)) (template-probability template)))
                 allowed)
        (car (last allowed))
        (find-if (lambda (template) (or (null (template-condition template))
                                        (evaluate-expression (template-condition template) conversation)))
                 templates :from-end t)
        (dialogue-fail (and templates (template-form (first templates)))
                       "no template of category ~A fits now (each one's condition fails)"
                       (display-name category)))))

(defun template-value-text (value)
  "VALUE as a template says it: a string as it is, a track or CD by its title,
a list as \"A, B and C\", a number plainly, a name in lower case."
  (typecase value
    (string value)
    (track (track-title value))
    (cd (cd-title value))
    (cons (let ((texts (mapcar #'template-value-text value)))
            (format nil "~{~A~#[~; and ~:;, ~]~}" texts)))
    (real (format-number value))
    (symbol (string-downcase (symbol-name value)))
    (t (princ-to-string value))))

(defun expand-template (template conversation)
  "TEMPLATE's text with each <=Var> replaced by the context variable Var's
value, without its gesture marks; the gestures they ask for are the second
value (see GESTURE-MARKS).  A DIALOGUE-ERROR naming the template when Var is
unset or a mark is unknown."
  (gesture-marks (expand-template-marked template conversation) template))

(defun expand-template-marked (template conversation)
  "As EXPAND-TEMPLATE, but the gesture marks (<!beat>, <!point>) stay in the
text, for the speaker to land (GESTURE-MARKS); an unknown one is a
DIALOGUE-ERROR here."
  (let ((text (template-text template)))
    (gesture-marks text template)
    (with-output-to-string (out)
      (loop with start = 0
            for open = (search "<=" text :start2 start)
            for close = (and open (position #\> text :start (+ open 2)))
            while close
            do (write-string text out :start start :end open)
               (let* ((name (subseq text (+ open 2) close))
                      (value (context-value conversation name)))
                 (when (null value)
                   (dialogue-fail (template-form template)
                                  "template ~D of ~A: the context variable ~A is not set"
                                  (template-index template) (display-name (template-category template)) name))
                 (write-string (template-value-text value) out))
               (setf start (1+ close))
            finally (write-string text out :start start)))))

;;;# Gestures on words: <!beat> and <!point>

(defparameter *gesture-marks* '(("beat" . :beat) ("point" . :point))
  "The marks a template may put before a word, <!NAME>, and the gesture
\(of the performance's *WORD-GESTURES*) each lands on that word.")

(defun count-words (text &key (start 0) (end (length text)))
  "How many words (runs of non-blank characters holding a letter or digit) TEXT has between START and END."
  (let ((count 0) (in-word nil) (alphanumeric nil))
    (loop for i from start below end
          for c = (char text i)
          do (cond ((member c '(#\Space #\Tab #\Newline))
                    (when (and in-word alphanumeric) (incf count))
                    (setf in-word nil alphanumeric nil))
                   (t (setf in-word t)
                      (when (alphanumericp c) (setf alphanumeric t))))
          finally (when (and in-word alphanumeric) (incf count)))
    count))

(defun gesture-marks (text &optional template)
  "TEXT without its gesture marks, and the gestures they ask for as a second
value, ((WORD-NUMBER GESTURE) ...), WORD-NUMBER counting from 1 the word the
mark stands before.  An unknown mark is a DIALOGUE-ERROR naming TEMPLATE."
  (let ((plain (make-array (length text) :element-type 'character :fill-pointer 0))
        (gestures '()))
    (with-output-to-string (out plain)
      (loop with start = 0
            for open = (search "<!" text :start2 start)
            for close = (and open (position #\> text :start (+ open 2)))
            while close
            do (write-string text out :start start :end open)
               (let* ((name (subseq text (+ open 2) close))
                      (gesture (cdr (assoc name *gesture-marks* :test #'string-equal))))
                 (unless gesture
                   (dialogue-fail (and template (template-form template))
                                  "unknown gesture mark <!~A> (known: ~{<!~A>~^ ~})" name
                                  (mapcar #'car *gesture-marks*)))
                 (push (list (1+ (count-words plain)) gesture) gestures))
               (setf start (1+ close))
            finally (write-string text out :start start)))
    (values (coerce plain 'simple-string) (nreverse gestures))))
