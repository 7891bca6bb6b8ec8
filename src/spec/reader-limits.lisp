;;;; reader-limits.lisp -- what a data file's text may ask of the Lisp reader,
;;;; measured on the text before the reader sees it.  The reader allocates what
;;;; a short text asks for (#100000000A(), #4000000000*1), spends quadratic
;;;; time on long number tokens, and recurses once per (, prefix, #+ or #N=;
;;;; so these are refused here, at their position, and nothing is allocated.

(in-package #:player.spec)

(defparameter *max-token-length* 4096
  "The longest token (a symbol or number, outside |...| and strings) a data file
may hold: SBCL reads a long number in quadratic time.")

(defparameter *max-reader-count* 1000000
  "The largest count a #N( vector, #N* bit vector or #N= label may give.")

(defparameter *max-array-rank* 8
  "The largest rank a #NA array may give.")

(defparameter *max-reader-chain* 100
  "The most #+, #- and #N= one form may hold: each makes the reader recurse.")

(defun reader-limit-problem (text &key (max-depth *max-form-depth*))
  "NIL when TEXT asks nothing of the Lisp reader beyond Player's limits;
else (VALUES POSITION MESSAGE) for the first place that does: a ( or prefix
(quote, backquote, comma, #', #. and the like) nesting more than MAX-DEPTH
levels, a token longer than *MAX-TOKEN-LENGTH*, a #N count beyond
*MAX-READER-COUNT* (or a rank beyond *MAX-ARRAY-RANK*), or more than
*MAX-READER-CHAIN* #+, #- and #N= in one form.  Strings, |symbols|, comments
and #\\x characters are skipped as the reader skips them."
  (let ((depth 0) (prefixes 0) (chains 0) (token 0) (i 0) (n (length text)))
    (labels ((fail (position control &rest arguments)
               (return-from reader-limit-problem
                 (values position (apply #'format nil control arguments))))
             (prefix (position)
               (when (> (+ depth (incf prefixes)) max-depth)
                 (fail position "the text nests more than ~D levels deep" max-depth)))
             (token-char (position)
               (when (> (incf token) *max-token-length*)
                 (fail (- position (1- token)) "a token is longer than ~:D characters (a number or symbol this long is not Player data)"
                       *max-token-length*)))
             (dispatch (start)
               ;; # at START begins a dispatch: optional digits, then a sub-character.
               (let* ((j (or (position-if-not #'digit-char-p text :start (1+ start)) n))
                      (digits (- j start 1))
                      (count (and (plusp digits)
                                  (if (> digits 9)
                                      (1+ *max-reader-count*)
                                      (parse-integer text :start (1+ start) :end j))))
                      (sub (and (< j n) (char text j))))
                 (when (and count (> count *max-reader-count*))
                   (fail start "#~A...: a reader count larger than ~:D" (subseq text (1+ start) (min j (+ start 12)))
                         *max-reader-count*))
                 (setf i j)
                 (case sub
                   ((nil))
                   (#\\ (setf prefixes 0 token 0) (incf i) (token-char i))
                   (#\| (setf i (block-comment-end text (1+ j))))
                   (#\( (setf token 0) (open-list j))
                   ((#\a #\A)
                    (when (and count (> count *max-array-rank*))
                      (fail start "#~DA: an array of rank ~:D (at most ~D)" count count *max-array-rank*))
                    (prefix start))
                   ((#\+ #\- #\=)
                    (when (> (incf chains) *max-reader-chain*)
                      (fail start "more than ~D #+, #- and #N= in one form" *max-reader-chain*))
                    (prefix start))
                   ((#\' #\. #\c #\C #\p #\P #\s #\S) (prefix start))
                   (t (setf prefixes 0) (token-char j)))))
             (open-list (position)
               (when (> (incf depth) max-depth)
                 (fail position "the text nests more than ~D levels deep" max-depth))
               (setf prefixes 0)))
      (loop while (< i n)
            do (let ((c (char text i)))
                 (case c
                   ((#\Space #\Tab #\Newline #\Return #\Page #\Linefeed) (setf token 0))
                   ((#\' #\` #\,) (setf token 0) (prefix i))
                   (#\@ (if (and (plusp i) (char= (char text (1- i)) #\,)) (prefix i) (token-char i)))
                   (#\( (setf token 0) (open-list i))
                   (#\) (setf token 0 prefixes 0 depth (max 0 (1- depth)))
                    (when (zerop depth) (setf chains 0)))
                   (#\" (setf token 0 prefixes 0 i (delimited-end text i #\")))
                   (#\; (setf token 0 i (or (position #\Newline text :start i) n)))
                   ;; |...| continues a token without adding to its length.
                   (#\| (setf prefixes 0 i (delimited-end text i #\|)))
                   (#\\ (setf prefixes 0) (token-char i) (incf i))
                   (#\# (if (plusp token) (token-char i) (dispatch i)))
                   (t (setf prefixes 0) (token-char i)))
                 (incf i))))
    nil))

(defun delimited-end (text open close)
  "The position in TEXT of the CLOSE character ending the string or |symbol|
whose opening delimiter is at OPEN, honouring backslashes; the end of TEXT
when it is never closed."
  (let ((n (length text)) (i open))
    (loop (incf i)
          (when (>= i n) (return n))
          (let ((c (char text i)))
            (cond ((char= c #\\) (incf i))
                  ((char= c close) (return i)))))))

(defun block-comment-end (text start)
  "The position of the # closing the #| block comment whose text begins at
START in TEXT (block comments nest), or the end of TEXT."
  (let ((depth 1) (i start) (n (length text)))
    (flet ((pair-p (a b) (and (char= (char text i) a) (char= (char text (1+ i)) b))))
      (loop while (< i (1- n))
            do (cond ((pair-p #\# #\|) (incf depth) (incf i 2))
                     ((pair-p #\| #\#) (decf depth) (incf i 2)
                      (when (zerop depth) (return-from block-comment-end (1- i))))
                     (t (incf i)))))
    n))
