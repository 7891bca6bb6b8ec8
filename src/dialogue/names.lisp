;;;; names.lisp -- how a dialogue names things, and how it reads words.
;;;; The paper's names are mixed case (stGotCD, evOK, haveCD), so dialogue
;;;; files are read with the readtable case :INVERT: `stGotCD` stays stGotCD,
;;;; `say` is SAY as ever.  Names are compared by their upper-cased text, so a
;;;; dialogue typed at the REPL (where stGotCD reads as STGOTCD) means the same.

(in-package #:player.dialogue)

(defvar *dialogue-readtable*
  (let ((readtable (copy-readtable *data-readtable*)))
    (setf (readtable-case readtable) :invert)
    readtable)
  "The data readtable with case :INVERT, dialogue files are read with.")

(defun dialogue-key (name)
  "The string NAME (a symbol or string; anything else by its printed text) is
looked up by: its text, upper-cased."
  (string-upcase (typecase name
                   (symbol (symbol-name name))
                   (string name)
                   (t (princ-to-string name)))))

(defun display-name (name)
  "NAME as a dialogue prints it: a symbol as :INVERT would write it (stGotCD
stays mixed, EV-SEARCH becomes ev-search), a string as it is."
  (cond ((stringp name) name)
        ((not (symbolp name)) (lisp-text name))
        (t (let ((text (symbol-name name)))
             (cond ((notany #'lower-case-p text) (string-downcase text))
                   ((notany #'upper-case-p text) (string-upcase text))
                   (t text))))))

(defun name-text (thing)
  "THING as messages show it: a name in the dialogue's spelling, anything else as Lisp text."
  (if (and (symbolp thing) thing) (display-name thing) (bounded-lisp-text thing 60)))

(defun same-name-p (a b)
  "Do A and B (symbols or strings) name the same thing?"
  (string= (dialogue-key a) (dialogue-key b)))

(defun dialogue-form-label (form)
  "How errors name FORM: its kind and first argument, e.g. \"on stGotCD\"."
  (when (and (alexandria:proper-list-p form) (symbolp (first form)) (rest form)
             (or (symbolp (second form)) (stringp (second form))))
    (format nil "~(~A~) ~A" (symbol-name (first form)) (display-name (second form)))))

(defun without-accents (text)
  "TEXT with its accents taken off (\"Débussy\" is \"Debussy\"), so a name
said or typed without them still meets the catalogue's."
  (if (every (lambda (char) (< (char-code char) 128)) text)
      text
      (remove-if (lambda (char) (eq (sb-unicode:general-category char) :mn))
                 (sb-unicode:normalize-string text :nfkd))))

(defun text-words (text)
  "TEXT as a list of lower-case words: letters and digits only, accents
taken off, apostrophes dropped (\"I've\" is \"ive\"), everything else a separator.  Both what the
user says and the dialogue's utterance patterns go through it, so they meet."
  (let ((words '()) (word (make-string-output-stream)) (any nil))
    (flet ((end-word ()
             (when any
               (push (get-output-stream-string word) words)
               (setf any nil))))
      (loop for char across (without-accents text)
            do (cond ((alphanumericp char)
                      (write-char (char-downcase char) word)
                      (setf any t))
                     ((member char '(#\' #\’)))
                     (t (end-word))))
      (end-word))
    (nreverse words)))
