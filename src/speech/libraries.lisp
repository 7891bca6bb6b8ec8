;;;; libraries.lisp -- speech's conditions and its two foreign libraries.
;;;; libespeak-ng speaks, libpocketsphinx recognises.  Both are loaded on first
;;;; use, not when Player loads, so a machine without them still plans,
;;;; simulates and renders silently.

(in-package #:player.speech)

(define-condition speech-error (player-error-with-message)
  ()
  (:documentation "Speech failed: a sound file is unreadable or of an unsupported
kind, synthesis or recognition went wrong.  The message names the file or text."))

(define-condition speech-unavailable (speech-error)
  ((package :initarg :package :reader speech-unavailable-package
            :documentation "The Debian package that provides what is missing."))
  (:documentation "A speech library or model is not installed; the message
names the Debian package to install."))

(defun speech-fail (control &rest arguments)
  "Signal a SPEECH-ERROR whose message is CONTROL applied to ARGUMENTS."
  (error 'speech-error :message (apply #'format nil control arguments)))

(defmacro with-speech-traps-masked (&body body)
  "Run BODY with SBCL's floating-point traps masked: espeak-ng and pocketsphinx
compute with infinities (log of zero energy in silence) on purpose."
  `(sb-int:with-float-traps-masked (:invalid :divide-by-zero :overflow :inexact)
     ,@body))

(defvar *espeak-library-names* '("libespeak-ng.so.1")
  "Sonames tried, in order, for espeak-ng (the versioned name: the unversioned
one comes only with the -dev package).")

(defvar *pocketsphinx-library-names* '(("libsphinxbase.so.3") ("libpocketsphinx.so.3"))
  "Sonames tried for pocketsphinx 0.8 (5prealpha): sphinxbase first, which it links.")

(defvar *loaded-speech-libraries* '()
  "Alist from a list of sonames to the CFFI library loaded from one of them.")

(defun load-speech-library (sonames label package)
  "Load the first of SONAMES the dynamic linker finds, once.  Signals
SPEECH-UNAVAILABLE naming LABEL and the Debian PACKAGE when none is found."
  (or (cdr (assoc sonames *loaded-speech-libraries* :test #'equal))
      (let ((library (some (lambda (soname)
                             (handler-case (cffi:load-foreign-library soname)
                               (cffi:load-foreign-library-error () nil)))
                           sonames)))
        (unless library
          (error 'speech-unavailable
                 :package package
                 :message (format nil "~A not found: install the Debian package ~A (tried ~{~A~^, ~})~@[; ~A~]"
                                  label package sonames
                                  (and (string= package "libespeak-ng1")
                                       "or play without sound (--silent)"))))
        (push (cons sonames library) *loaded-speech-libraries*)
        library)))

(defun load-espeak-library ()
  "Make sure libespeak-ng is loaded; SPEECH-UNAVAILABLE names libespeak-ng1 when it is missing."
  (load-speech-library *espeak-library-names* "speaking needs libespeak-ng, which is" "libespeak-ng1"))

(defun load-pocketsphinx-library ()
  "Make sure pocketsphinx is loaded; SPEECH-UNAVAILABLE names the package when it is missing."
  (dolist (names *pocketsphinx-library-names*)
    (load-speech-library names "recognising speech needs pocketsphinx, which is" "pocketsphinx")))
