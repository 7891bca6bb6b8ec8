;;;; data-files.lisp -- reading Player's files (specs, script libraries, pose
;;;; libraries, skeletons) as data.  Opening one never runs code: *READ-EVAL*
;;;; is off, #S is refused, symbols go to PLAYER-USER (or a package that uses
;;;; PLAYER, by IN-PACKAGE), and only regular UTF-8 files are read.  Nesting,
;;;; tokens and #N counts are measured on the text before the reader sees it
;;;; (reader-limits.lisp), and every form is checked
;;;; for circular structure, so no file can exhaust the stack or loop.

(in-package #:player.spec)

(defparameter *max-data-file-bytes* (* 64 1024 1024)
  "The largest file Player reads as data.")

(defun regular-file-p (path)
  "Is PATH (following links) a regular file?  Directories, FIFOs and devices are not."
  (let ((stat (handler-case (sb-posix:stat (native-namestring path))
                (sb-posix:syscall-error () nil))))
    (and stat (= (logand (sb-posix:stat-mode stat) sb-posix:s-ifmt) sb-posix:s-ifreg))))

(defun native-namestring (path)
  "PATH as the operating system's file name."
  (if (pathnamep path) (sb-ext:native-namestring path) path))

(defun find-data-file (path what fail)
  "PATH's truename when it is a readable regular file; else FAIL is called with
NIL, a message naming WHAT (\"spec file\", ...) and :MISSING or :NOT-REGULAR."
  (let ((found (ignore-errors (probe-file path))))
    (cond ((null found)
           (funcall fail nil (format nil "cannot open ~A ~A: no such file" what path) :missing))
          ((not (regular-file-p found))
           (funcall fail nil (format nil "cannot open ~A ~A: not a regular file" what path) :not-regular))
          (t found))))

(defun line-of (text position)
  "The 1-based line of character POSITION in TEXT."
  (1+ (count #\Newline text :end (min position (length text)))))

(defun file-text (file fail)
  "FILE's contents decoded as UTF-8.  FAIL is called with the character position
of the first byte that is not UTF-8, or of NIL when FILE cannot be read."
  (let ((octets (handler-case
                    (with-input-file (in file :element-type '(unsigned-byte 8))
                      (let ((length (file-length in)))
                        (when (> length *max-data-file-bytes*)
                          (funcall fail nil (format nil "~A is larger than ~:D bytes" (file-namestring file)
                                                    *max-data-file-bytes*) :read))
                        (let* ((octets (make-array length :element-type '(unsigned-byte 8)))
                               (end (read-sequence octets in)))
                          (subseq octets 0 end))))
                  ((or io-error file-error stream-error) (e)
                    (funcall fail nil (format nil "cannot read ~A: ~A" (file-namestring file) (condition-reason e))
                             :read)))))
    (handler-case (sb-ext:octets-to-string octets :external-format :utf-8)
      (error ()
        (let ((lenient (sb-ext:octets-to-string
                        octets :external-format '(:utf-8 :replacement #\Replacement_Character))))
          (funcall fail (or (position #\Replacement_Character lenient) 0)
                   "the file is not valid UTF-8 text" :read))))))

;;;# Reading

(defvar *data-readtable*
  (let ((readtable (copy-readtable nil)))
    (set-dispatch-macro-character
     #\# #\S (lambda (stream char arg)
               (declare (ignore char arg))
               (error 'sb-int:simple-reader-error :stream stream
                                                   :format-control "#S(...) structures are not data Player reads"
                                                   :format-arguments '()))
     readtable)
    readtable)
  "The standard syntax without #S, which would call a structure's constructor.")

(defun reader-message (condition)
  "CONDITION, a reader problem, as a sentence without Lisp stream objects, nor
the package name a token asked for (the file may be no Player data at all, a
secret's first word being that name)."
  (typecase condition
    (end-of-file "the form is not finished (a parenthesis or string is not closed)")
    (sb-int:simple-reader-package-error "a symbol names a package that does not exist (write names without a package: prefix)")
    (t (let ((text (handler-case (princ-to-string condition)
                     (error () "the Lisp reader failed"))))
         ;; SBCL's reader errors end with the stream they were reading.
         (string-trim '(#\Space #\Newline #\.)
                      (substitute #\Space #\Newline
                                  (subseq text 0 (or (search "Stream:" text)
                                                     (search " on #<" text)
                                                     (length text)))))))))

(defun player-package-p (package)
  "May a data file be read in PACKAGE?  Only in PLAYER-USER and packages that
use PLAYER, so that spec words mean what Player means by them."
  (and package (member (find-package '#:player) (package-use-list package))))

(defun switch-package (form position fail)
  "Make (in-package NAME) FORM current for the rest of the file, or FAIL."
  (let ((package (and (proper-list-p form) (= (length form) 2)
                      (typep (second form) '(or string symbol))
                      (find-package (second form)))))
    (unless (player-package-p package)
      (funcall fail position
               (format nil "~A: a data file may only switch to player-user or a package that uses player"
                       (bounded-lisp-text form 80))
               :read))
    (setf *package* package)))

(defun read-data-file (file &key (what "file") fail (allow-in-package t) (readtable *data-readtable*))
  "Every top-level form of FILE, read as data, as a list of (FORM POSITION
PACKAGE): the form's character position and the package it was read in; with
ALLOW-IN-PACKAGE, IN-PACKAGE forms are obeyed and left out.  The second
value is FILE's text.  FAIL, a function
of a position (or NIL), a message and a kind (:missing, :not-regular, :read
or :structure), is called for every problem and must not return: the file
missing or not regular, not UTF-8, nested more than *MAX-FORM-DEPTH* deep,
unreadable, or holding a circular form.  WHAT names the file in messages.
READTABLE (by default *DATA-READTABLE*) must be a copy of it, differing at
most in its case (dialogue files keep the paper's mixed-case names)."
  (let* ((file (find-data-file file what fail))
         (text (file-text file fail)))
    (multiple-value-bind (position message) (reader-limit-problem text)
      (when position
        (funcall fail position message :structure)))
    (let ((start (first-form-start text)))
      ;; A list, or reader syntax (#.) the reader refuses in its own words.
      (when (and start (not (member (char text start) '(#\( #\#))))
        ;; Quote nothing: the file may be a secret named by mistake.
        (funcall fail start (format nil "~A is not Player data: Player's files hold lists such as (defspec ...), and it does not begin with one"
                                    (file-namestring file))
                 :read)))
    (with-standard-io-syntax
      (let ((*readtable* readtable)
            (*read-eval* nil)
            (*read-default-float-format* 'double-float)
            (*package* (find-package '#:player-user)))
        (with-input-from-string (in text)
          (loop for start = (progn (skip-whitespace-and-comments in) (file-position in))
                for form = (handler-case (read in nil in)
                             ;; #p42 and #+0 fail as TYPE-ERROR and SIMPLE-ERROR: any
                             ;; error while reading is a form that cannot be read.
                             (error (condition)
                               (funcall fail start (format nil "cannot read form: ~A" (reader-message condition))
                                        :read)))
                until (eq form in)
                do (handler-case (check-form-structure form)
                     (spec-error (condition) (funcall fail start (spec-error-message condition) :structure)))
                if (and allow-in-package (consp form) (eq (first form) 'in-package))
                  do (switch-package form start fail)
                else collect (list form start *package*) into entries
                finally (return (values entries text))))))))

(defun first-form-start (text)
  "The position of the first character of TEXT that is neither blank nor in a
; or #| |# comment, or NIL when there is none."
  (let ((i 0) (n (length text)))
    (loop (cond ((>= i n) (return nil))
                ((member (char text i) '(#\Space #\Tab #\Newline #\Return #\Page)) (incf i))
                ((char= (char text i) #\;) (setf i (or (position #\Newline text :start i) n)))
                ((and (char= (char text i) #\#) (< (1+ i) n) (char= (char text (1+ i)) #\|))
                 (setf i (1+ (block-comment-end text (+ i 2)))))
                (t (return i))))))

(defun skip-whitespace-and-comments (stream)
  "Advance STREAM past blanks and ; comments; the next character starts a form."
  (loop for char = (peek-char t stream nil nil)
        while (eql char #\;)
        do (read-line stream nil nil)))

;;;# Where a list's elements start

(defun list-element-positions (text start)
  "The character positions in TEXT where the elements of the list whose ( is
at START begin, in order (an element is an atom or a form, with any quote,
backquote or comma prefixes).  Strings, |symbols|, comments and #\\(
characters are skipped as the reader does; used to point an error at the
sub-form it is about."
  (let ((positions '()) (depth 0) (i (1+ start)) (n (length text)) (in-element nil))
    (flet ((skip-delimited (close) (setf i (delimited-end text i close)))
           (begin ()
             (when (and (zerop depth) (not in-element))
               (push i positions)
               (setf in-element t))))
      (loop while (< i n)
            do (let ((c (char text i)))
                 (case c
                   ((#\Space #\Tab #\Newline #\Return #\Page)
                    (when (zerop depth) (setf in-element nil)))
                   (#\; (setf i (or (position #\Newline text :start i) n))
                    (when (zerop depth) (setf in-element nil)))
                   (#\( (begin) (incf depth))
                   (#\) (if (zerop depth)
                            (return)
                            (progn (decf depth)
                                   (when (zerop depth) (setf in-element nil)))))
                   (#\" (begin) (skip-delimited #\")
                    (when (zerop depth) (setf in-element nil)))
                   (#\| (begin) (skip-delimited #\|))
                   ((#\' #\` #\,) (begin))
                   (#\# (if (and (< (1+ i) n) (char= (char text (1+ i)) #\|))
                            (setf i (block-comment-end text (+ i 2)))
                            (progn (begin)
                                   (when (and (< (1+ i) n) (char= (char text (1+ i)) #\\))
                                     (incf i 2)))))
                   (#\\ (begin) (incf i))
                   (t (begin)))
                 (incf i))))
    (nreverse positions)))

;;;# Where every list of a form starts

(defun list-openings (text start)
  "The openings, in text order, of the lists of the form whose ( is at START
in TEXT, as (POSITION . KIND): KIND :PAREN for a ( (but not the () of NIL),
:QUOTE for ' and :FUNCTION for #', which the reader also turns into lists.  NIL when the text
holds what cannot be matched with the form's lists this way (backquote,
comma, #+ and #-), or when START is not a (."
  (let ((openings '()) (depth 0) (i start) (n (length text)))
    (unless (and (< start n) (char= (char text start) #\())
      (return-from list-openings nil))
    (loop while (< i n)
          do (let ((c (char text i)))
               (case c
                 (#\; (setf i (or (position #\Newline text :start i) n)))
                 (#\" (setf i (delimited-end text i #\")))
                 (#\| (setf i (delimited-end text i #\|)))
                 (#\\ (incf i))
                 ((#\` #\,) (return-from list-openings nil))
                 (#\' (push (cons i :quote) openings))
                 (#\( (let ((close (position-if-not (lambda (c) (member c '(#\Space #\Tab #\Newline #\Return)))
                                                     text :start (1+ i))))
                        (if (and close (char= (char text close) #\)) (plusp depth))
                            (setf i close)  ; () is NIL, not a list
                            (progn (push (cons i :paren) openings) (incf depth)))))
                 (#\) (when (zerop (decf depth)) (return)))
                 (#\# (let ((next (and (< (1+ i) n) (char text (1+ i)))))
                        (case next
                          (#\| (setf i (block-comment-end text (+ i 2))))
                          (#\\ (incf i 2))  ; #\( is a character, not a list
                          (#\( (incf depth) (incf i))  ; a vector: its ) closes it
                          (#\' (push (cons i :function) openings) (incf i))
                          ((#\+ #\-) (return-from list-openings nil))))))
               (incf i)))
    (nreverse openings)))

(defun form-lists (form)
  "The lists of FORM in the order the reader met their openings: each list's
first cons, then the lists among its elements (and in vectors), depth first.
NIL when a list occurs twice (shared structure, #1#), which text cannot match."
  (let ((seen (make-hash-table :test 'eq)) (lists '()))
    (labels ((walk (x)
               (cond ((consp x)
                      (when (gethash x seen) (return-from form-lists nil))
                      (setf (gethash x seen) t)
                      (push x lists)
                      (loop for tail = x then (cdr tail)
                            while (consp tail)
                            do (walk (car tail))))
                     ((and (vectorp x) (not (stringp x)) (not (bit-vector-p x)))
                      (map nil #'walk x)))))
      (walk form))
    (nreverse lists)))

(defun sub-form-places (entries text file &optional (table (make-hash-table :test 'eq)))
  "TABLE (a new EQ hash table by default) filled with every list inside the
forms of ENTRIES ((FORM POSITION ...) ..., as READ-DATA-FILE returns them from
FILE's TEXT) mapped to its (FILE . POSITION), for *SUB-FORM-PLACES*.  A form
whose lists cannot be matched with its text one to one is left out: its
errors keep naming the top-level form's line."
  (loop for (form start) in entries
        for openings = (and (consp form) (list-openings text start))
        for lists = (and openings (form-lists form))
        when (and lists (= (length lists) (length openings))
                  (every (lambda (list opening)
                           (case (cdr opening)
                             (:quote (eq (car list) 'quote))
                             (:function (eq (car list) 'function))
                             (t t)))
                         lists openings))
          do (loop for list in lists
                   for (position) in openings
                   do (setf (gethash list table) (cons file position))))
  table)
