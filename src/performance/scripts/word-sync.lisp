;;;; word-sync.lisp -- a :say item's words as sync points (BML's
;;;; <sync id="w3"/>): an item written (:at (:word "raitt") ...) or
;;;; (:at (:word 3 OFFSET) ...) starts when the nearest :say item written
;;;; before it in its script says that word.  espeak-ng's word events time
;;;; the words, so the sentence is synthesised when the library is read:
;;;; its length is known before it plays, and counts for the script's
;;;; inferred duration.

(in-package #:player.performance)

(defun say-item-utterance (item)
  "The utterance of the :say ITEM, synthesised (once per text, voice and rate)."
  (synthesize-speech (say-item-text item)
                     :voice (or (say-item-voice item) *default-voice*)
                     :rate (or (say-item-rate item) *default-speech-rate*)))

(defun say-item-length (item)
  "How long the :say ITEM speaks, in seconds, or NIL when no speech library is
here to say (then its script's inferred duration counts only its start)."
  (handler-case (utterance-duration (say-item-utterance item))
    (speech-unavailable () nil)))

(defun word-sync-form-p (time)
  "Is the item time TIME a word sync point, (:word ...)?"
  (and (consp time) (eq (first time) :word)))

(defun word-sync-time (item time)
  "Seconds into its script at which ITEM, whose time TIME is (:word WORD
[OFFSET]), starts: when the last :say item before it says WORD (a string, or
the word's number from 1), plus OFFSET seconds.  A SCRIPT-ERROR about ITEM
when there is no such :say item or word, or no speech library to time it."
  (unless (and (alexandria:proper-list-p time) (<= 2 (length time) 3)
               (or (and (stringp (second time)) (plusp (length (second time))))
                   (and (integerp (second time)) (plusp (second time))))
               (or (null (cddr time)) (and (realp (third time)) (seconds-p (abs (third time))))))
    (script-fail item "a word sync point is (:word \"WORD\" [OFFSET]) or (:word N [OFFSET]), N from 1, not ~A"
                 (lisp-text time)))
  (let ((say *last-say-item*))
    (unless say
      (script-fail item "~A names a word, but no :say item comes before it in the script"
                   (lisp-text time)))
    (let ((utterance (handler-case (say-item-utterance say)
                       (speech-error (error)
                         (script-fail item "~A needs the words' times: ~A" (lisp-text time) error)))))
      (multiple-value-bind (start) (utterance-word-time utterance (second time))
        (unless start
          (script-fail item "~S has no word ~A (its words: ~{~A~^ ~})" (say-item-text say)
                       (lisp-text (second time)) (mapcar #'first (utterance-words utterance))))
        (let ((at (+ (script-item-at say) start (or (third time) 0))))
          (when (minusp at)
            (script-fail item "~A comes ~A s before the script starts" (lisp-text time) (format-number (- at))))
          (float at 1d0))))))
