;;;; pronunciation.lisp -- words a grammar uses that pocketsphinx's
;;;; dictionary lacks (an invented artist, an album title), pronounced by
;;;; espeak-ng and written in the dictionary's CMU phones, so a dialogue can
;;;; name anything espeak-ng can say; and every word of a grammar as a
;;;; British voice says it, a variant beside the dictionary's American
;;;; pronunciations, as recognisers do for accents.

(in-package #:player.speech)

(defparameter *espeak-cmu-phones*
  '(("a" "AE") ("aa" "AA") ("A:" "AA") ("A@" "AA R") ("a#" "AH") ("@" "AH") ("@2" "AH") ("@5" "AH")
    ("@L" "AH L") ("3" "ER") ("3:" "ER") ("@r" "ER") ("e" "EH") ("E" "EH") ("e@" "EH R") ("eI" "EY")
    ("i" "IY") ("i:" "IY") ("I" "IH") ("I2" "IH") ("I#" "IH") ("i@" "IH R") ("i@3" "IH R")
    ("0" "AA") ("O" "AO") ("O:" "AO") ("O@" "AO R") ("o@" "AO R") ("oU" "OW") ("OI" "OY")
    ("u:" "UW") ("U" "UH") ("U@" "UH R") ("V" "AH") ("aI" "AY") ("aI@" "AY ER") ("aU" "AW")
    ("aU@" "AW ER") ("p" "P") ("b" "B") ("t" "T") ("t#" "T") ("d" "D") ("d#" "D") ("k" "K")
    ("g" "G") ("m" "M") ("m-" "M") ("n" "N") ("n-" "N") ("N" "NG") ("f" "F") ("v" "V") ("T" "TH")
    ("D" "DH") ("s" "S") ("z" "Z") ("S" "SH") ("Z" "ZH") ("tS" "CH") ("dZ" "JH") ("h" "HH")
    ("l" "L") ("l/" "L") ("r" "R") ("r-" "R") ("w" "W") ("j" "Y") ("?" "T") ("x" "K"))
  "(ESPEAK-PHONEME CMU-PHONES): espeak-ng's English phoneme mnemonics in the
phone set of cmudict-en-us (ARPAbet without stress).")

(defparameter *british-cmu-phones*
  '(("a" "AA") ("oU" "EH UW"))
  "(ESPEAK-PHONEME CMU-PHONES) where espeak-ng's British voice (en) sounds
to the en-us acoustic model unlike *ESPEAK-CMU-PHONES* says: its short a
(\"thank\", \"have\", \"clapton\") is open, nearer AA than AE, and its
o (\"no\", \"hello\", \"wrote\") starts from a central vowel.  Chosen on
the first two thirds of each set of t/fixtures/spoken-sentences.lisp:
\"thank you\" was heard as \"stop the tune\", \"have you got\" as \"can you\".")

(defparameter *accent-voices* '(("en" . *british-cmu-phones*))
  "(VOICE . TABLE): the espeak-ng voices whose accent every grammar word is
also learnt in, TABLE (a symbol) naming the phones that voice's phonemes
sound like where they differ from *ESPEAK-CMU-PHONES*.")

(defun cmu-phones (phoneme &optional overrides)
  "The CMU phones (a string) of the espeak-ng PHONEME, or NIL for a pause or
an unknown one; OVERRIDES, a table like *ESPEAK-CMU-PHONES*, is looked in first."
  (flet ((lookup (name)
           (second (or (assoc name overrides :test #'string=) (assoc name *espeak-cmu-phones* :test #'string=)))))
    (unless (or (zerop (length phoneme)) (char= (char phoneme 0) #\_))
      (or (lookup phoneme) (lookup (string-right-trim "#:-/;0123456789" phoneme))))))

(defun word-pronunciation (word &key (voice *default-voice*) overrides)
  "WORD as espeak-ng's VOICE says it, in CMU phones separated by spaces (see
CMU-PHONES for OVERRIDES); NIL when it says nothing known."
  (let ((phones (remove nil (mapcar (lambda (entry) (cmu-phones (first entry) overrides))
                                    (utterance-phonemes (synthesize-speech word :voice voice))))))
    (and phones (format nil "~{~A~^ ~}" phones))))

(defvar *accent-pronunciations* (make-hash-table :test #'equal)
  "(WORD . VOICE) -> its pronunciation in that accent (see ACCENT-PRONUNCIATIONS),
kept: each word costs a synthesis, about 2 ms.")

(defun accent-pronunciations (word)
  "WORD's pronunciations in the accents of *ACCENT-VOICES*, CMU phones, each once."
  (remove-duplicates
   (remove nil (loop for (voice . table) in *accent-voices*
                     collect (let ((key (cons word voice)))
                               (multiple-value-bind (phones known) (gethash key *accent-pronunciations*)
                                 (if known
                                     phones
                                     (setf (gethash key *accent-pronunciations*)
                                           (word-pronunciation word :voice voice :overrides (symbol-value table))))))))
   :test #'string=))

(defun strip-delimited (text open close)
  "TEXT with every span from OPEN to the next CLOSE (strings) replaced by a space."
  (with-output-to-string (out)
    (loop with start = 0
          for from = (search open text :start2 start)
          for to = (and from (search close text :start2 (+ from (length open))))
          do (write-string text out :start start :end (or from (length text)))
             (if (and from to)
                 (progn (write-char #\Space out) (setf start (+ to (length close))))
                 (return)))))

(defun grammar-words (grammar)
  "The words the JSGF text GRAMMAR can make a sentence of, in lower case, each
once: its text without comments, the header, the grammar's name, rule names,
tags and weights."
  (let* ((text (reduce (lambda (text delimiters) (strip-delimited text (first delimiters) (second delimiters)))
                       '(("/*" "*/") ("//" #.(string #\Newline)) ("#JSGF" ";") ("<" ">") ("{" "}")
                         ("/" "/"))               ; weights
                       :initial-value grammar))
         ;; The grammar's name: the first "grammar NAME;" only.
         (at (search "grammar" text))
         (end (and at (position #\; text :start at)))
         (text (if end (concatenate 'string (subseq text 0 at) " " (subseq text (1+ end))) text))
         (words '()))
    (loop with start = nil
          for i from 0 to (length text)
          for c = (and (< i (length text)) (char text i))
          do (if (and c (or (alpha-char-p c) (char= c #\')))
                 (unless start (setf start i))
                 (when start
                   (pushnew (string-downcase (subseq text start i)) words :test #'string=)
                   (setf start nil))))
    (remove "public" (nreverse words) :test #'string=)))
