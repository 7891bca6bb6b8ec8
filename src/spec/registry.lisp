;;;; registry.lisp -- DEFSPEC, the table of defined specs, and loading spec files.

(in-package #:player)

(defvar *specs* (make-hash-table :test 'equal)
  "Defined specs, by name key.")

(defvar *defined-specs* nil
  "While LOAD-SPEC runs: the specs defined so far, most recent first.")

(defun define-spec (name body &key source-file (package *package*))
  "Parse BODY as spec NAME, register it (replacing any older definition) and
return it. Signals a SPEC-ERROR, leaving the old definition in place, when BODY
is malformed."
  (let ((spec (parse-spec name body :source-file source-file :package package)))
    (setf (gethash (name-key name) *specs*) spec)
    (push spec *defined-specs*)
    spec))

(defmacro defspec (name &body body)
  "Define (or, re-evaluated, redefine) the controller spec NAME:
  (defspec NAME [DOCSTRING] [(:max-depth N)] FORM...)
where each FORM is a state-variable, time-variable, state-class, op, macro-op,
autoscript or event form. See the README for the language."
  `(define-spec ',name ',body
                :source-file ,(or (car *source-position*) *compile-file-truename* *load-truename*)
                :package (find-package ,(package-name *package*))))

(defun find-spec (name &optional (errorp t))
  "The spec named NAME (a symbol or string). With ERRORP (the default), an
unknown name is a SPEC-ERROR; otherwise NIL."
  (or (gethash (if (stringp name) (string-upcase name) (name-key name)) *specs*)
      (and errorp
           (error 'unknown-name-error :form name :spec nil :position nil
                  :message (format nil "no spec named ~A is defined~@[ (defined: ~{~A~^, ~})~]"
                                   (lisp-text name) (mapcar #'lisp-text (list-specs)))))))

(defun list-specs ()
  "The names of every defined spec."
  (sort (loop for spec being the hash-values of *specs* collect (spec-name spec))
        #'string< :key #'symbol-name))

(defun remove-spec (name)
  "Forget the spec named NAME."
  (remhash (name-key name) *specs*))

(defun skip-whitespace-and-comments (stream)
  "Advance STREAM past blanks and ; comments; the next character starts a form."
  (loop for char = (peek-char t stream nil nil)
        while (eql char #\;)
        do (read-line stream nil nil)))

(defun read-spec-form (stream file)
  "Read the next form of spec FILE, or :EOF. Reader trouble is a SPEC-READER-ERROR
with the position of the form that could not be read."
  (skip-whitespace-and-comments stream)
  (let ((start (file-position stream)))
    (handler-case (values (read stream nil :eof) start)
      ((or reader-error end-of-file) (condition)
        (error 'spec-reader-error
               :position (cons file start) :spec nil
               :message (format nil "cannot read form: ~A"
                                (remove #\Newline (princ-to-string condition))))))))

(defun load-spec (file)
  "Load the spec file FILE: read it in PLAYER-USER (IN-PACKAGE forms switch),
evaluate its forms, and return the specs it defined, in order. Errors name the
file and line of the offending form."
  (let ((file (or (probe-file file)
                  (error 'spec-reader-error :spec nil :position nil :form nil
                         :message (format nil "cannot open spec file ~A" file))))
        (*package* (find-package '#:player-user))
        (*read-default-float-format* 'double-float)
        (*defined-specs* '()))
    (with-open-file (stream file)
      (loop (multiple-value-bind (form start) (read-spec-form stream file)
              (when (eq form :eof) (return))
              (let ((*source-position* (cons file start)))
                (eval form)))))
    (reverse *defined-specs*)))
