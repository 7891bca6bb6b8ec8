;;;; load-system.lisp -- load an ASDF system of this checkout with its
;;;; compiler warnings seen: a full WARNING fails the build (each is printed
;;;; with the file it came from), and STYLE-WARNINGs are counted into one
;;;; summary line.  The Makefile and bin/build-core.lisp load Player through
;;;; LOAD-CHECKED; nothing here belongs to Player's packages.

(require :asdf)

(defpackage #:player-build
  (:use #:cl)
  (:export #:load-checked))

(in-package #:player-build)

(defun component-being-compiled ()
  "The namestring of the file being compiled now, else of the fasl being loaded
(as its file name); warnings SBCL defers to the end of the build (undefined
functions, conflicting derived types) have none."
  (let ((file *compile-file-truename*))
    (cond (file (enough-namestring file (truename "./")))
          (*load-truename* (format nil "loading ~A" (file-namestring *load-truename*)))
          (t "at the end of the build"))))

(defun uninteresting-p (condition)
  "Is CONDITION one SBCL itself never shows (SB-EXT:*MUFFLED-WARNINGS*)?  Loading
a fasl redefines each macro its compilation defined, from the same source, and
SBCL signals that as an uninteresting redefinition: counting those would count
every DEFMACRO of the build."
  (typep condition sb-ext:*muffled-warnings*))

(defun warning-text (condition)
  "CONDITION's report on one line."
  (substitute #\Space #\Newline (princ-to-string condition)))

(defun load-checked (system &key (stream *error-output*))
  "Load SYSTEM (a string) through ASDF. Print each full WARNING with its file;
muffle STYLE-WARNINGs and print their count on one line. Return true when no
full WARNING was signalled, NIL otherwise (the caller fails the build)."
  (let ((style-warnings '()) (warnings '()))
    (handler-bind ((style-warning
                     (lambda (condition)
                       (unless (uninteresting-p condition)
                         (push (format nil "~A: ~A" (component-being-compiled) (warning-text condition))
                               style-warnings))
                       (muffle-warning condition)))
                   (warning
                     (lambda (condition)
                       ;; ASDF's own notes that a file had warnings repeat what was counted.
                       (unless (typep condition '(or asdf:compile-warned-warning
                                                     asdf:compile-failed-warning))
                         (push (format nil "~A: ~A" (component-being-compiled) (warning-text condition))
                               warnings))
                       (muffle-warning condition))))
      (let ((asdf:*compile-file-warnings-behaviour* :ignore)
            (asdf:*compile-file-failure-behaviour* :ignore))
        (asdf:load-system system)))
    (setf style-warnings (remove-duplicates (nreverse style-warnings) :test #'string=))
    (when style-warnings
      (format stream "~&build: ~D style-warning~:P while compiling ~A~%" (length style-warnings) system)
      (when (uiop:getenv "PLAYER_SHOW_STYLE_WARNINGS")
        (format stream "~{  ~A~%~}" style-warnings)))
    (when warnings
      (format stream "~&build: ~D WARNING~:P while compiling ~A:~%~{  ~A~%~}"
              (length warnings) system (remove-duplicates (nreverse warnings) :test #'string=))
      (finish-output stream))
    (null warnings)))
