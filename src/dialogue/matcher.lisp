;;;; matcher.lisp -- from what the user said to an input event with slot
;;;; values, scoring every utterance pattern (Persona: "recognize all
;;;; legitimate English paraphrases of a request and reduce them to a single
;;;; canonical structure").  For each pattern the sentence's mentions
;;;; (mentions.lisp) fill its slots, in every way that fits; the words left
;;;; over are put in canonical form (vocabulary.lisp) and aligned with the
;;;; pattern's words in order, a missing or extra word costing its weight.
;;;;   score = 1 - (cost of missing and extra words + doubt about the names) / weight of the pattern
;;;; The best reading at or above *UNDERSTANDING-THRESHOLD* wins; none gives
;;;; the dialogue's not-understood event ("Huh?").

(in-package #:player.dialogue)

(defparameter *understanding-threshold* 0.6
  "The least score a reading needs to be understood.")

(defstruct reading
  "One way of understanding a sentence: the input EVENT, its SLOTS (an alist
from slot keys to values, in the pattern's order), its SCORE (0..1), the
PATTERN read and NOTES (strings) saying why."
  event slots (score 0.0) pattern (notes '()))

;;;# Aligning words

(defun pattern-word-items (pattern)
  "The words of PATTERN as (WORD . OPTIONAL) pairs, in order, its slots left out."
  (loop for element in (utterance-pattern-elements pattern)
        when (pattern-words-p element)
          append (mapcar (lambda (word) (cons word (pattern-words-optional element)))
                         (pattern-words-words element))))

(defun align-words (items words)
  "Align the pattern ITEMS ((WORD . OPTIONAL) pairs) with the sentence WORDS in
order, as an edit distance where a missing required word or an extra word
costs its WORD-WEIGHT; (VALUES COST WEIGHT MISSING EXTRA), WEIGHT the pattern
words' (optional ones counted when said), MISSING and EXTRA the words."
  (let* ((items (coerce items 'vector)) (words (coerce words 'vector))
         (n (length items)) (m (length words))
         (cost (make-array (list (1+ n) (1+ m)) :element-type 'single-float :initial-element 0.0)))
    (flet ((skip-item (i) (let ((item (aref items i))) (if (cdr item) 0.0 (word-weight (car item)))))
           (skip-word (j) (word-weight (aref words j))))
      (loop for i from 1 to n do (setf (aref cost i 0) (+ (aref cost (1- i) 0) (skip-item (1- i)))))
      (loop for j from 1 to m do (setf (aref cost 0 j) (+ (aref cost 0 (1- j)) (skip-word (1- j)))))
      (loop for i from 1 to n
            do (loop for j from 1 to m
                     do (setf (aref cost i j)
                              (min (+ (aref cost (1- i) j) (skip-item (1- i)))
                                   (+ (aref cost i (1- j)) (skip-word (1- j)))
                                   (if (string= (car (aref items (1- i))) (aref words (1- j)))
                                       (aref cost (1- i) (1- j))
                                       most-positive-single-float)))))
      ;; Walk back to name the missing and extra words and weigh what was said.
      (let ((i n) (j m) (weight 0.0) (missing '()) (extra '()))
        (loop while (or (plusp i) (plusp j))
              do (cond ((and (plusp i) (plusp j) (string= (car (aref items (1- i))) (aref words (1- j)))
                             (= (aref cost i j) (aref cost (1- i) (1- j))))
                        (incf weight (word-weight (aref words (1- j))))
                        (decf i) (decf j))
                       ((and (plusp i) (= (aref cost i j) (+ (aref cost (1- i) j) (skip-item (1- i)))))
                        (let ((item (aref items (1- i))))
                          (unless (cdr item)
                            (incf weight (word-weight (car item)))
                            (push (car item) missing)))
                        (decf i))
                       (t (push (aref words (1- j)) extra) (decf j))))
        (values (aref cost n m) weight missing extra)))))

;;;# Filling slots with mentions

(defparameter *max-filling-steps* 2000
  "The most partial fillings SLOT-FILLINGS tries for one pattern: a pattern of
many optional slots has exponentially many fillings, and a sentence is read
in time linear in its length whatever the pattern.")

(defun slot-fillings (slots mentions)
  "Ways to fill the pattern SLOTS (PATTERN-SLOTs, in order) with MENTIONS, no
two sharing a word: a list of lists of (SLOT . MENTION-OR-NIL), an optional
slot also left empty.  Most plausible mentions come first, and the search
stops after *MAX-FILLING-STEPS* partial fillings, so the first ones found
(the likeliest) are all a pattern of very many optional slots gets."
  (let ((fillings '()) (steps 0))
    (labels ((candidates (slot mentions)
               (let ((fitting (remove (dialogue-key (pattern-slot-name slot)) mentions
                                      :key #'mention-slot :test-not #'string=)))
                 (if (pattern-slot-optional slot) (append fitting (list nil)) fitting)))
             (fill-from (slots mentions chosen)
               (when (> (incf steps) *max-filling-steps*)
                 (return-from slot-fillings (nreverse fillings)))
               (if (null slots)
                   (push (reverse chosen) fillings)
                   (dolist (mention (candidates (first slots) mentions))
                     (fill-from (rest slots)
                                (if mention
                                    (remove-if (lambda (other) (mentions-overlap-p mention other)) mentions)
                                    mentions)
                                (cons (cons (first slots) mention) chosen))))))
      (fill-from slots mentions '())
      (nreverse fillings))))

(defun words-outside (words mentions)
  "WORDS in runs (lists) between the MENTIONS' spans, in order."
  (let ((runs '()) (run '()))
    (loop for word in words
          for index from 0
          do (if (find-if (lambda (m) (and m (<= (mention-start m) index) (< index (mention-end m)))) mentions)
                 (when run (push (nreverse run) runs) (setf run '()))
                 (push word run)))
    (when run (push (nreverse run) runs))
    (nreverse runs)))

(defun read-with-filling (dialogue pattern words filling)
  "The READING of the sentence WORDS as PATTERN with its slots filled by FILLING."
  (let* ((mentions (remove nil (mapcar #'cdr filling)))
         (canonical '()) (notes '()))
    ;; Each run between names is rewritten on its own: a synonym never spans a name.
    (dolist (run (words-outside words mentions))
      (multiple-value-bind (run-words run-notes) (canonical-words (dialogue-rewrites dialogue) run)
        (alexandria:appendf canonical run-words)
        (alexandria:appendf notes run-notes)))
    (multiple-value-bind (cost weight missing extra) (align-words (pattern-word-items pattern) canonical)
      (let ((doubt (reduce #'+ mentions :key (lambda (m) (- 1.0 (mention-plausibility m))))))
        (incf weight (length mentions))
        (make-reading
         :event (utterance-pattern-event pattern) :pattern pattern
         :score (if (plusp weight) (max 0.0 (- 1.0 (/ (+ cost doubt) weight))) 0.0)
         :slots (loop for (slot . mention) in filling
                      when mention collect (cons (dialogue-key (pattern-slot-name slot)) (mention-value mention)))
         :notes (append (loop for m in mentions
                              collect (format nil "~(~A~)=~S (~A)" (mention-slot m) (mention-value m) (mention-how m)))
                        notes
                        (and missing (list (format nil "missing ~{~S~^ ~}" missing)))
                        (and extra (list (format nil "extra ~{~S~^ ~}" extra)))))))))

(defun read-as (dialogue pattern words mentions)
  "The best READING of the sentence WORDS as PATTERN, or NIL when its
required slots cannot be filled from MENTIONS."
  (let ((best nil))
    (dolist (filling (slot-fillings (remove-if-not #'pattern-slot-p (utterance-pattern-elements pattern)) mentions)
                     best)
      (let ((reading (read-with-filling dialogue pattern words filling)))
        (when (or (null best) (> (reading-score reading) (reading-score best)))
          (setf best reading))))))

;;;# Reading a sentence

(defun dialogue-slot-forms (dialogue)
  "An alist from the slot keys DIALOGUE's patterns use to their forms."
  (let ((slots '()))
    (dolist (pattern (dialogue-utterances dialogue) (nreverse slots))
      (dolist (element (utterance-pattern-elements pattern))
        (when (and (pattern-slot-p element)
                   (not (assoc (dialogue-key (pattern-slot-name element)) slots :test #'string=)))
          (push (cons (dialogue-key (pattern-slot-name element)) (pattern-slot-forms element)) slots))))))

(defun utterance-readings (dialogue text)
  "Every reading of TEXT (a string) in DIALOGUE, the best for each pattern,
best first (ties in the order the patterns are written)."
  (let* ((words (text-words text))
         (mentions (find-mentions (dialogue-slot-forms dialogue) words)))
    (stable-sort (loop for pattern in (dialogue-utterances dialogue)
                       for reading = (read-as dialogue pattern words mentions)
                       when reading collect reading)
                 #'> :key #'reading-score)))

(defun match-utterance (dialogue text)
  "The input event TEXT means in DIALOGUE and its slots, as (VALUES EVENT
SLOTS MATCHED SCORE); SLOTS an alist from slot keys (upper-case strings) to
values.  The best-scoring reading (UTTERANCE-READINGS) wins when it scores
*UNDERSTANDING-THRESHOLD* or more; otherwise the dialogue's not-understood
event, no slots and MATCHED NIL."
  (let ((best (first (utterance-readings dialogue text))))
    (if (and best (>= (reading-score best) *understanding-threshold*))
        (values (reading-event best) (reading-slots best) t (reading-score best))
        (values (dialogue-not-understood dialogue) '() nil (if best (reading-score best) 0.0)))))

;;;# Explaining

(defun reading-line (reading)
  "READING as `explain:` shows it: score, event, slots, and why."
  (format nil "explain: ~,2F ~A~:{ ~(~A~)=~S~} (~{~A~^; ~})"
          (reading-score reading) (display-name (reading-event reading))
          (mapcar (lambda (pair) (list (car pair) (template-value-text (cdr pair)))) (reading-slots reading))
          (or (reading-notes reading) '("word for word"))))

(defun explain-utterance (dialogue text &key (stream *standard-output*) (count 3))
  "Print on STREAM the best COUNT readings of TEXT in DIALOGUE, one event
each, best first, as `explain: SCORE EVENT slot=\"value\"... (WHY)` lines,
then the threshold the best must reach.  Returns the readings printed."
  (let ((shown (loop with seen = '()
                     for reading in (utterance-readings dialogue text)
                     unless (member (reading-event reading) seen :test #'same-name-p)
                       collect reading and do (push (reading-event reading) seen)
                     until (= (length seen) count))))
    (dolist (reading shown) (write-line (reading-line reading) stream))
    (format stream "explain: understood at ~,2F or more~:[; nothing is: ~A~;~*~]~%"
            *understanding-threshold*
            (and shown (>= (reading-score (first shown)) *understanding-threshold*))
            (display-name (dialogue-not-understood dialogue)))
    shown))
