;;;; word-sync.lisp -- a :say item's words as sync points (BML's
;;;; <sync id="w3"/>): an item written (:at (:word "raitt") ...) or
;;;; (:at (:word 3 OFFSET) ...) starts when the nearest :say item written
;;;; before it in its script says that word; (:at (:word offer "raitt") ...)
;;;; names the :say written with :as offer.  espeak-ng's word events time
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
here to say (then its script's inferred duration counts only its start).
A SCRIPT-ERROR about ITEM when espeak-ng refuses it (an unknown voice)."
  (handler-case (utterance-duration (say-item-utterance item))
    (speech-unavailable () nil)
    (speech-error (error) (script-fail (script-item-form item) "~A" error))))

(defun word-sync-form-p (time)
  "Is the item time TIME a word sync point, (:word ...)?"
  (and (consp time) (eq (first time) :word)))

(defun word-sync-time (item time)
  "Seconds into its script at which ITEM, whose time TIME is (:word [NAME]
WORD [OFFSET]), starts: when the :say item called NAME (default: the last
before it) says WORD (a string, or the word's number from 1), plus OFFSET
seconds.  A SCRIPT-ERROR about ITEM when there is no such :say item or
word, or no speech library to time it."
  (let* ((named (and (consp (rest time)) (usable-name-p (second time))))
         (spec (if named (cddr time) (rest time))))
    (unless (and (alexandria:proper-list-p time) (<= 1 (length spec) 2)
                 (or (and (stringp (first spec)) (plusp (length (first spec))))
                     (and (integerp (first spec)) (plusp (first spec))))
                 (or (null (rest spec)) (and (realp (second spec)) (seconds-p (abs (second spec))))))
      (script-fail item "a word sync point is (:word [SAY-NAME] \"WORD\" [OFFSET]) or (:word [SAY-NAME] N [OFFSET]), N from 1, not ~A"
                   (lisp-text time)))
    (let ((say (if named
                   (or (find (second time) *say-items* :key #'say-item-name :test #'name=)
                       (script-fail item "~A names no :say item written before it with :as ~A"
                                    (lisp-text time) (lisp-text (second time))))
                   (or (first *say-items*)
                       (script-fail item "~A names a word, but no :say item comes before it in the script"
                                    (lisp-text time))))))
      (let ((utterance (handler-case (say-item-utterance say)
                         (speech-error (error)
                           (script-fail item "~A needs the words' times: ~A" (lisp-text time) error)))))
        (multiple-value-bind (start) (utterance-word-time utterance (first spec))
          (unless start
            (script-fail item "~S has no word ~A (its words: ~{~A~^ ~})" (say-item-text say)
                         (lisp-text (first spec)) (mapcar #'first (utterance-words utterance))))
          (let ((at (+ (script-item-at say) start (or (second spec) 0))))
            (when (minusp at)
              (script-fail item "~A comes ~A s before the script starts" (lisp-text time) (format-number (- at))))
            (float at 1d0)))))))
