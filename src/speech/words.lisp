;;;; words.lisp -- an utterance's words as a timeline: espeak-ng's word
;;;; events (where in the text a word starts, how long it is, and when it is
;;;; heard) made into (WORD START END), and the sync points a script or a
;;;; dialogue template names by a word or its number (BML's <sync id="w3"/>).

(in-package #:player.speech)

(defun word-text (text position length)
  "The word LENGTH characters long at the 1-based POSITION of TEXT, without
the punctuation around it; NIL when the event points outside TEXT."
  (let ((start (1- position)))
    (when (and (<= 0 start) (plusp length) (<= (+ start length) (length text)))
      (string-trim "\"'.,;:!?()[]{}-" (subseq text start (+ start length))))))

(defun spoken-end (phonemes)
  "Where the last sounding (not pause) phoneme of PHONEMES ends, or NIL."
  (loop for (name nil end) in (reverse phonemes)
        unless (or (zerop (length name)) (char= (char name 0) #\_))
          return end))

(defun first-sound-from (phonemes time)
  "The start of the first sounding phoneme of PHONEMES that starts at TIME or
later, or TIME when none does."
  (loop for (name start) in phonemes
        when (and (>= start (- time 1d-3)) (plusp (length name)) (char/= (char name 0) #\_))
          return start
        finally (return time)))

(defun word-timeline (text events phonemes)
  "The words of TEXT as (WORD START END) from espeak-ng's word EVENTS,
\(:word POSITION LENGTH MILLISECONDS) in order: each word starts with its
first sounding phoneme (espeak-ng reports a word a frame or a pause early)
and lasts until the next begins, the last until the last sounding phoneme
of PHONEMES ends.  Events naming no word of TEXT (espeak-ng's own
insertions) are passed over."
  (let* ((starts (loop with last = 0d0
                       for (nil position length ms) in events
                       for word = (word-text text position length)
                       for start = (max last (first-sound-from phonemes (/ ms 1000d0)))
                       when (and word (plusp (length word)))
                         collect (cons word start)
                         and do (setf last start)))
         (end (or (spoken-end phonemes) (and starts (cdr (car (last starts)))) 0d0)))
    (loop for ((word . start) next) on starts
          collect (list word start (max start (if next (cdr next) end))))))

(defun word-key (word)
  "WORD compared as a sync point: lower case, without accents' case games or punctuation."
  (string-downcase (string-trim "\"'.,;:!?()[]{}-" word)))

(defun utterance-word (utterance word)
  "The (WORD START END) of UTTERANCE that WORD names: a string (the first
word spelt so, ignoring case and punctuation) or an integer N >= 1 (the Nth
word).  NIL when there is none such."
  (let ((words (utterance-words utterance)))
    (etypecase word
      (integer (and (plusp word) (nth (1- word) words)))
      (string (find (word-key word) words :key (lambda (entry) (word-key (first entry)))
                                          :test #'string=)))))

(defun utterance-word-time (utterance word)
  "When UTTERANCE says WORD (see UTTERANCE-WORD), in seconds from its start,
and the word's end as a second value; NIL when it has no such word."
  (let ((entry (utterance-word utterance word)))
    (and entry (values (second entry) (third entry)))))
