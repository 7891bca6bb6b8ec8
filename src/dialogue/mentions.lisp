;;;; mentions.lisp -- Persona's name substitution (Figure 4): before a
;;;; sentence is matched, find where it names something a slot can hold, and
;;;; how plausibly.  "play before you accuse me by clapton" mentions the
;;;; title "Before You Accuse Me" (exactly) and the artist "Eric Clapton" (by
;;;; surname, less plausibly); the matcher then tries the interpretations, as
;;;; the paper's name substitution presents alternatives to its parser.
;;;; A slot's forms are (WORDS VALUE PLAUSIBILITY HOW): a full name or title
;;;; (1), a surname or the last words of a name (0.8), a title's significant
;;;; words with its function words left out or changed (0.9, matched loosely).

(in-package #:player.dialogue)

(defstruct (mention (:constructor make-mention (slot value start end plausibility how)))
  "Words START below END of a sentence name VALUE, which the slot SLOT (a
DIALOGUE-KEY) can hold, with PLAUSIBILITY (0..1); HOW says why, in words."
  slot value start end plausibility how)

(defun name-forms (value)
  "The forms of the name VALUE (a string): in full, then each of its last
words (\"lloyd webber\", \"webber\")."
  (let ((words (text-words value)))
    (cons (list words value 1.0 "full name")
          (loop for tail on (rest words)
                collect (list tail value 0.8 (format nil "last name~P of ~A" (length tail) value))))))

(defun title-forms (value)
  "The forms of the title VALUE: in full, and, when it differs and has two
or more, its significant words (matched loosely)."
  (let* ((words (text-words value))
         (significant (remove-if (lambda (word) (member word *function-words* :test #'string=)) words)))
    (cons (list words value 1.0 "full title")
          (and (rest significant) (not (equal significant words))
               (list (list significant value 0.9 :significant))))))

(defun slot-forms (dialogue name form)
  "Every form of the slot NAME in DIALOGUE, longest first: a phrases set of
the dialogue, or the catalogue's artists (and composers), titles or albums."
  (let* ((key (dialogue-key name))
         (phrases (gethash key (dialogue-phrases dialogue)))
         (catalogue (dialogue-catalogue dialogue))
         (forms (cond (phrases (mapcar (lambda (value) (list (text-words value) value 1.0 "phrase")) phrases))
                      ((string= key "ARTIST") (mapcan #'name-forms (catalogue-artists catalogue)))
                      ((string= key "TITLE") (mapcan #'title-forms (catalogue-titles catalogue)))
                      ((string= key "ALBUM") (mapcan #'title-forms (catalogue-albums catalogue)))
                      (t (dialogue-fail form "unknown slot ~A: not a phrases set of the dialogue, nor artist, title or album of its catalogue"
                                        (display-name name))))))
    (stable-sort forms #'> :key (lambda (form) (length (first form))))))

(defun loose-form-p (form)
  "Is the slot FORM matched loosely (a title's significant words)?"
  (eq (fourth form) :significant))

(defun exact-span-end (phrase words start)
  "Where PHRASE (a word list) ends when WORDS say it from START, or NIL."
  (let ((end (+ start (length phrase))))
    (and (<= end (length words))
         (every #'string= phrase (nthcdr start words))
         end)))

(defun loose-span-end (phrase words start)
  "Where PHRASE ends when WORDS say it from START with function words
between and around its words changed (\"sunken cathedral\", \"before
accuse\" in \"before you accuse\"), or NIL.  It starts and ends on its own words."
  (let ((position start))
    (dolist (word phrase position)
      (loop while (and (< position (length words)) (/= position start)
                       (string/= word (nth position words))
                       (member (nth position words) *function-words* :test #'string=))
            do (incf position))
      (unless (and (< position (length words)) (string= word (nth position words)))
        (return nil))
      (incf position))))

(defun find-mentions (slots words)
  "The mentions in WORDS of the slots SLOTS, an alist from slot keys to their
forms: every span naming one of them, most plausible first."
  (let ((mentions '()))
    (loop for (key . forms) in slots
          do (dolist (form forms)
               (loop for start below (length words)
                     for end = (if (loose-form-p form)
                                   (loose-span-end (first form) words start)
                                   (exact-span-end (first form) words start))
                     when end
                       do (push (make-mention key (second form) start end (third form)
                                              (if (loose-form-p form) "significant words of the title" (fourth form)))
                                mentions))))
    (stable-sort (nreverse mentions) #'> :key #'mention-plausibility)))

(defun mentions-overlap-p (a b)
  "Do the mentions A and B share a word?"
  (and (< (mention-start a) (mention-end b)) (< (mention-start b) (mention-end a))))
