;;;; conditions.lisp -- the model layer's conditions and the limits on what it
;;;; imports.  Every way an import can fail (a missing file, a file Assimp
;;;; refuses, data that is not finite, a model past a limit) is one MODEL-ERROR
;;;; naming the file, so the CLI prints it as one line; every way a write can
;;;; fail is one MODEL-WRITE-ERROR, a MODEL-ERROR naming the file written.

(in-package #:player.model)

(define-condition model-error (player-error)
  ((file :initarg :file :reader model-error-file
         :documentation "The model file, as given.")
   (message :initarg :message :reader model-error-message
            :documentation "What is wrong with it, a clause without a capital."))
  (:report (lambda (condition stream)
             (format stream "cannot import the model ~A: ~A"
                     (model-error-file condition) (model-error-message condition))))
  (:documentation "A model file could not be imported: it is missing or
unreadable, Assimp refused it, or what it holds is not finite or past a limit.
(MODEL-WRITE-ERROR, its subclass, is a model that could not be written.)"))

(define-condition model-library-missing (model-error)
  ((package :initarg :package :reader model-library-missing-package
            :documentation "The Debian package that provides the library."))
  (:documentation "libassimp is not installed; the message names the Debian package."))

(defun model-fail (file control &rest arguments)
  "Signal a MODEL-ERROR about FILE whose message is CONTROL applied to ARGUMENTS."
  (error 'model-error :file file :message (apply #'format nil control arguments)))

(define-condition model-write-error (model-error)
  ()
  (:report (lambda (condition stream)
             (format stream "cannot write the model ~A: ~A"
                     (model-error-file condition) (model-error-message condition))))
  (:documentation "A model could not be written to FILE: what it holds cannot
be put in the file's format (a number that is not finite, a skin past the
format's limits, a texture that is missing or of a kind the format cannot
hold), or the file cannot be created where it was asked for."))

(defvar *model-output* nil
  "While a model is written: the file as given, which every MODEL-WRITE-ERROR names.")

(defun write-fail (control &rest arguments)
  "Signal a MODEL-WRITE-ERROR about the file being written (*MODEL-OUTPUT*)
whose message is CONTROL applied to ARGUMENTS."
  (error 'model-write-error :file *model-output* :message (apply #'format nil control arguments)))
;;;# Messages from C

(defun c-message (pointer &optional (limit 300))
  "The NUL-terminated message a C library left at POINTER as one line: at most
LIMIT bytes, decoded as UTF-8 with any invalid byte replaced, line breaks and
other control characters made spaces; NIL for a NULL POINTER.  C libraries'
messages quote the input they choke on, which is not always UTF-8 or one line,
and a Player error is one line."
  (unless (cffi:null-pointer-p pointer)
    (let* ((length (loop for i below limit until (zerop (cffi:mem-aref pointer :uint8 i)) count t))
           (octets (make-array length :element-type '(unsigned-byte 8))))
      (dotimes (i length) (setf (aref octets i) (cffi:mem-aref pointer :uint8 i)))
      (substitute-if #\Space (lambda (char) (< (char-code char) 32))
                     (sb-ext:octets-to-string octets :external-format '(:utf-8 :replacement #\?))))))

;;;# Limits
;;; Bounds on what one import may hold, so a hostile or broken file is a
;;; clear error instead of an exhausted heap or a skeleton no body can drive.

(defparameter *model-vertex-limit* 2000000
  "The most vertices (summed over meshes) a model may have.")

(defparameter *model-triangle-limit* 4000000
  "The most triangles (summed over meshes) a model may have.")

(defparameter *model-joint-limit* 300
  "The most joints a model's skeleton may have.")

(defparameter *model-key-limit* 5000000
  "The most animation keys (positions, rotations and scales, over all clips) a model may have.")

(defparameter *model-node-limit* 100000
  "The most nodes a scene's node tree may have (joints are a subset of them).")
