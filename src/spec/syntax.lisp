;;;; syntax.lisp -- small readers of the language's surface syntax.
;;;; Spec words are compared by name, so a spec read in any package works.

(in-package #:player.spec)

(defun word-p (thing &rest names)
  "True when THING is a symbol whose name is one of NAMES (case-insensitive)."
  (and (symbolp thing) thing
       (member (symbol-name thing) names :test #'string-equal)))

(defun name-key (symbol)
  "The string a definition's name is looked up by."
  (string-upcase (symbol-name symbol)))

(defun require-name (thing form what)
  "THING if it is a usable name (a non-keyword, non-NIL symbol); else a syntax error."
  (let ((thing (unquote thing)))
    (unless (and (symbolp thing) thing (not (keywordp thing)) (not (eq thing t)))
      (spec-fail 'spec-syntax-error form "~A must be a name, not ~A" what (lisp-text thing)))
    thing))

(defun proper-list-p (thing)
  "True when THING is a proper list."
  (and (listp thing) (handler-case (list-length thing) (error () nil))))

(defun parse-options (form arguments allowed &key repeatable)
  "Check that ARGUMENTS is a plist of keywords from ALLOWED; return it with values
unquoted. Keys in REPEATABLE may appear more than once."
  (unless (and (proper-list-p arguments) (evenp (length arguments)))
    (spec-fail 'spec-syntax-error form "expected keyword arguments in pairs"))
  (loop with seen = '()
        for (key value) on arguments by #'cddr
        do (unless (member key allowed)
             (spec-fail 'spec-syntax-error form "unknown option ~A (allowed: ~{~A~^ ~})"
                        (lisp-text key) (mapcar #'lisp-text allowed)))
           (when (and (member key seen) (not (member key repeatable)))
             (spec-fail 'duplicate-definition form "option ~A given twice" (lisp-text key)))
           (push key seen)
        append (list key (unquote value))))

(defun split-dotted (symbol)
  "For a symbol like ALERT.SNORE: the candidate (VARIABLE-NAME . VALUE-NAME) splits,
leftmost dot first; NIL when the name has no dot."
  (let ((name (symbol-name symbol)))
    (loop for dot = (position #\. name) then (position #\. name :start (1+ dot))
          while dot
          when (and (plusp dot) (< dot (1- (length name))))
            collect (cons (subseq name 0 dot) (subseq name (1+ dot))))))

(defun boolean-word (thing)
  "For the words true/false/t/nil: (VALUES BOOLEAN T); otherwise (VALUES NIL NIL)."
  (cond ((or (eq thing t) (word-p thing "TRUE")) (values t t))
        ((or (null thing) (word-p thing "FALSE")) (values nil t))
        (t (values nil nil))))
