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

(defun write-octets-atomically (path octets)
  "Write OCTETS to the file PATH: first to a new file in PATH's folder, flushed
to disk, which is then renamed over PATH (WRITE-FILE-OCTETS of src/base/).
Whatever fails, the new file is removed and PATH is left as it was.  A
MODEL-WRITE-ERROR with the reason when the folder cannot be written or the
rename fails."
  (handler-case (write-file-octets path octets :follow-links t)
    (io-error (condition)
      (write-fail "writing the file failed: ~A" (io-error-reason condition))))
  path)
