;;;; gltf-files.lisp -- the two files a glTF document and its buffer can be:
;;;; .glb, the binary container (a 12-byte header, then a JSON chunk padded
;;;; with spaces and a BIN chunk padded with zeros, each to 4 bytes), and
;;;; .gltf, JSON text whose one buffer is a base64 data: URI, so it too is one
;;;; file.  Then the write itself, atomic: the octets go to a new file beside
;;;; the target, which is renamed over it only once complete, so a failure
;;;; never leaves a half-written file or destroys the one that was there.

(in-package #:player.model)

;;;# base64 (RFC 4648), for the data: URI

(defparameter *base64-digits*
  "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/"
  "The 64 digits of base64, in order.")

(defun base64-text (octets)
  "OCTETS (a vector of bytes) in base64, padded with = to a multiple of 4."
  (declare (type octets octets))
  (let* ((length (length octets))
         (text (make-string (* 4 (ceiling length 3)) :element-type 'base-char :initial-element #\=))
         (digits (coerce *base64-digits* 'simple-base-string)))
    (loop for from of-type fixnum from 0 below length by 3
          for to of-type fixnum from 0 by 4
          do (let* ((left (- length from))
                    (group (logior (ash (aref octets from) 16)
                                   (if (> left 1) (ash (aref octets (+ from 1)) 8) 0)
                                   (if (> left 2) (aref octets (+ from 2)) 0))))
               ;; 3 bytes make 4 digits; a last group of 1 or 2 bytes makes 2 or 3, then =.
               (dotimes (k (1+ (min left 3)))
                 (setf (char text (+ to k)) (char digits (ldb (byte 6 (- 18 (* 6 k))) group))))))
    text))

;;;# The two containers

(defconstant +glb-magic+ #x46546C67 "A .glb file's first 4 bytes, \"glTF\" read little-endian.")
(defconstant +glb-json-chunk+ #x4E4F534A "The type of a .glb's JSON chunk, \"JSON\".")
(defconstant +glb-bin-chunk+ #x004E4942 "The type of a .glb's BIN chunk, \"BIN\" and a zero.")

(defun utf-8-octets (text)
  "TEXT encoded as UTF-8."
  (sb-ext:string-to-octets text :external-format :utf-8))

(defun glb-octets (json binary)
  "A .glb file of the document JSON (a string) and the buffer BINARY (its
octets, a multiple of 4 long, or empty for no BIN chunk): the header
(magic, version 2, total length), the JSON chunk padded with spaces to 4
bytes, then the BIN chunk.  A MODEL-WRITE-ERROR when it would pass the
format's 4 GiB."
  (let* ((text (utf-8-octets json))
         (json-length (* 4 (ceiling (length text) 4)))
         (bin-length (length binary))
         (total (+ 12 8 json-length (if (plusp bin-length) (+ 8 bin-length) 0))))
    (when (>= total (expt 2 32))
      (write-fail "it needs ~:D bytes, more than a .glb file can hold (4 GiB)" total))
    (let ((octets (make-array total :element-type '(unsigned-byte 8) :initial-element 0)))
      (store-u32 octets 0 +glb-magic+)
      (store-u32 octets 4 2)
      (store-u32 octets 8 total)
      (store-u32 octets 12 json-length)
      (store-u32 octets 16 +glb-json-chunk+)
      (replace octets text :start1 20)
      (fill octets (char-code #\Space) :start (+ 20 (length text)) :end (+ 20 json-length))
      (when (plusp bin-length)
        (let ((start (+ 20 json-length)))
          (store-u32 octets start bin-length)
          (store-u32 octets (+ start 4) +glb-bin-chunk+)
          (replace octets binary :start1 (+ start 8))))
      octets)))

(defun data-uri (octets)
  "The data: URI holding OCTETS, as a .gltf file's embedded buffer."
  (concatenate 'string "data:application/octet-stream;base64," (base64-text octets)))

;;;# Writing a file atomically

(defun errno-text (condition)
  "The system's words for the errno of CONDITION, an SB-POSIX:SYSCALL-ERROR."
  (sb-int:strerror (sb-posix:syscall-errno condition)))

(defun temporary-sibling (target)
  "A name for a new file beside TARGET (a native namestring), hidden and unlikely to exist."
  (let ((slash (position #\/ target :from-end t)))
    (format nil "~A.~A.~D-~36R.part"
            (subseq target 0 (if slash (1+ slash) 0))
            (subseq target (if slash (1+ slash) 0))
            (sb-posix:getpid) (random (expt 36 6)))))

(defun create-temporary (target)
  "A new file beside TARGET, opened for writing: its name and its descriptor.
A MODEL-WRITE-ERROR naming the folder when it cannot be created there."
  (let ((name (temporary-sibling target)))
    (handler-case
        (values name (sb-posix:open name (logior sb-posix:o-wronly sb-posix:o-creat sb-posix:o-excl) #o666))
      (sb-posix:syscall-error (condition)
        (write-fail "cannot create a file in the folder ~A: ~A"
                    (subseq name 0 (1+ (or (position #\/ name :from-end t) -1))) (errno-text condition))))))

(defun write-octets-atomically (path octets)
  "Write OCTETS to the file PATH: first to a new file in PATH's folder, flushed
to disk, which is then renamed over PATH (rename(2) replaces it in one step).
Whatever fails, the new file is removed and PATH is left as it was.  A
MODEL-WRITE-ERROR when the folder cannot be written or the rename fails."
  (let ((target (sb-ext:native-namestring (merge-pathnames path))))
    (multiple-value-bind (name descriptor) (create-temporary target)
      (let ((done nil))
        (unwind-protect
             (handler-case
                 (let ((stream (sb-sys:make-fd-stream descriptor :output t :element-type '(unsigned-byte 8)
                                                                 :buffering :full :file name)))
                   (unwind-protect (progn (write-sequence octets stream)
                                          (finish-output stream)
                                          (sb-posix:fsync descriptor))
                     (close stream))
                   (handler-case (sb-posix:rename name target)
                     (sb-posix:syscall-error (condition)
                       (write-fail "the written file cannot replace it: ~A" (errno-text condition))))
                   (setf done t))
               (sb-posix:syscall-error (condition)
                 (write-fail "writing the file failed: ~A" (errno-text condition)))
               (stream-error (condition)
                 (write-fail "writing the file failed: ~A" condition)))
          (unless done
            (ignore-errors (sb-posix:unlink name))))))
    path))
