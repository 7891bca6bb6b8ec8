;;;; visemes.lisp -- espeak-ng's phonemes as the mouth shapes of the :lips
;;;; motor function (*VISEMES* in lips.lisp), and an utterance's phoneme
;;;; timeline as the timed viseme list :lips plays.  This table is the one
;;;; place phonemes meet visemes; Pantomime's lipshape maps the same way
;;;; (CLOSED for m b p, F, TH, R, E, A, O, OO ...).

(in-package #:player.speech)

(defparameter *phoneme-visemes*
  '((:rest "_" "_:" "_!" "_^_" "_|" "||" "_;_")
    (:mm "m" "b" "p" "m-")
    (:ff "f" "v")
    (:ss "s" "z")
    (:th "T" "D")
    (:ch "S" "Z" "tS" "dZ")
    (:dd "t" "d" "n" "t#" "d#" "n-" "?")
    (:rr "r" "r-" "3" "3:" "@r")
    (:oo "w" "u:" "U" "u" "W" "U@")
    (:ee "i" "i:" "I" "I2" "I#" "j" "i@" "i@3")
    (:kk "k" "g" "N" "x" "h" "k#")
    (:ll "l" "@L" "l/" "L")
    (:ih "e" "E" "eI" "@" "@2" "@5" "a#" "I@" "e@")
    (:oh "0" "O" "O:" "O@" "oU" "OI" "o" "o@" "V")
    (:aa "a" "aa" "A" "A:" "A@" "aI" "aI@" "aU" "aU@" "A#"))
  "(VISEME PHONEME...): the espeak-ng (en) phoneme mnemonics each viseme of
*VISEMES* shows.  Names not listed are looked up without their trailing
marks, then by their first character; unknown ones show :ih.")

(defun phoneme-viseme (name)
  "The viseme (a keyword of *VISEMES*) that shows the espeak-ng phoneme NAME."
  (flet ((lookup (phoneme)
           (car (find phoneme *phoneme-visemes* :key #'rest :test (lambda (p names) (member p names :test #'string=))))))
    (cond ((or (zerop (length name)) (char= (char name 0) #\_)) :rest)
          ((lookup name))
          ((lookup (string-right-trim "#:-/;0123456789" name)))
          ((lookup (subseq name 0 1)))
          (t :ih))))

(defparameter *shortest-viseme* 0.02d0
  "Seconds a phoneme must last to get its own viseme: shorter ones are
coarticulated away (the jaw cannot show them).")

(defun utterance-visemes (utterance &key (lead 0.35d0))
  "The timed visemes that say UTTERANCE, ((SECONDS VISEME) ...) for :lips:
each phoneme's viseme formed LEAD (a fraction) into the phoneme, repeats and
too-short phonemes merged, ending with :rest at the end of the sound."
  (let ((visemes '()) (last nil))
    (loop for (name start end) in (utterance-phonemes utterance)
          for viseme = (phoneme-viseme name)
          for at = (+ start (* lead (- end start)))
          when (and (or (>= (- end start) *shortest-viseme*) (eq viseme :rest))
                    (not (eq viseme last))
                    (or (null visemes) (> at (+ (first (first visemes)) 1d-3))))
            do (push (list at viseme) visemes)
               (setf last viseme))
    (let ((end (utterance-duration utterance)))
      (unless (and visemes (eq last :rest))
        (push (list (max end (+ (if visemes (first (first visemes)) 0d0) 1d-3)) :rest) visemes)))
    (nreverse visemes)))
