;;;; spec-files.lisp -- LOAD-SPEC: a spec file is data.  It may hold only
;;;; IN-PACKAGE and DEFSPEC forms; they are read by READ-DATA-FILE and given to
;;;; DEFINE-SPEC, never evaluated, so opening a spec file runs no code.  (:code
;;;; forms inside a spec run only when their event does; ALLOW-CODE NIL
;;;; refuses a spec that has any.)

(in-package #:player.spec)

(defun spec-file-fail (file)
  "A function of a position and a message signalling a SPEC-READER-ERROR in FILE."
  (lambda (position message &optional kind)
    (declare (ignore kind))
    (error 'spec-reader-error :position (and position (cons file position)) :spec nil :form nil
                              :message message)))

(defun defspec-form-p (form)
  "Is FORM a (defspec ...) form?"
  (and (consp form) (eq (first form) 'defspec)))

(defun load-spec (file &key (allow-code t))
  "Load the spec file FILE and return the specs it defines, in order.  The file
is read as data (see READ-DATA-FILE): only IN-PACKAGE and DEFSPEC forms are
accepted, and nothing is evaluated.  Unless ALLOW-CODE, a spec holding :code or
:c++ is refused.  Signals a SPEC-ERROR naming the file and line of the
offending form; the specs defined before it stay defined."
  (multiple-value-bind (entries text) (read-data-file file :what "spec file" :fail (spec-file-fail file))
    (let* ((file (probe-file file))
           (*defined-specs* '()))
      ;; An error about a sub-form (an expression, a directive) names its own line.
      (with-spec-context (:sub-form-places (sub-form-places entries text file))
        (loop for (form position package) in entries
              do (with-spec-context (:source-position (cons file position))
                   (unless (defspec-form-p form)
                     (spec-fail 'spec-syntax-error form
                                "a spec file holds only in-package and defspec forms, not ~A~:[~;; a file with a defscene is a scene file, which run, simulate, render, view and check take~]"
                                (bounded-lisp-text form 60)
                                (and (consp form) (symbolp (first form))
                                     (string= (symbol-name (first form)) "DEFSCENE"))))
                   (let ((rest (rest form)))
                     (define-spec (if (consp rest) (first rest) nil) (if (consp rest) (rest rest) nil)
                                  :source-file file :package package :allow-code allow-code
                                  ;; DEFSPEC and NAME come first.
                                  :form-positions (cddr (list-element-positions text position))))))
        (reverse *defined-specs*)))))
