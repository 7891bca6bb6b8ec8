;;;; files.lisp -- how Player opens files: outputs written whole or not at all,
;;;; inputs that are regular files, and one IO-ERROR naming the file and why.
;;;; Every output goes to a new temporary file beside it (created exclusively,
;;;; never through a link), is flushed to the disk, then renamed over the old
;;;; one, so a full disk or an interrupt leaves the old file as it was.
;;;; Every input is opened without blocking and checked to be a regular file
;;;; before a byte is read, so a FIFO or a device cannot hang a command.

(in-package #:player.base)

;;;# The error

(define-condition io-error (player-error)
  ((file :initarg :file :reader io-error-file
         :documentation "The file, as the user named it.")
   (action :initarg :action :initform "write" :reader io-error-action
           :documentation "What was being done: \"read\", \"write\", \"create\".")
   (reason :initarg :reason :reader io-error-reason
           :documentation "Why it failed, as a phrase: \"no space left on device\"."))
  (:report (lambda (condition stream)
             (format stream "cannot ~A ~A: ~A" (io-error-action condition)
                     (shown-file-name (io-error-file condition)) (io-error-reason condition))))
  (:documentation "Reading or writing FILE failed for REASON (the operating system's, in words)."))

(defun shown-file-name (file)
  "FILE as an error shows it: as the user named it, in the system's spelling."
  (if (pathnamep file) (sb-ext:native-namestring file) (princ-to-string file)))

(defun os-file-name (file)
  "FILE (a pathname or a Lisp namestring) as the operating system names it,
merged with *DEFAULT-PATHNAME-DEFAULTS* as OPEN would merge it."
  (sb-ext:native-namestring (merge-pathnames file)))

(defun sentence-case (text)
  "TEXT with its first letter lower case, as a reason inside a sentence reads."
  (if (and (plusp (length text)) (upper-case-p (char text 0))
           (or (= (length text) 1) (not (upper-case-p (char text 1)))))
      (concatenate 'string (string (char-downcase (char text 0))) (subseq text 1))
      text))

(defun errno-reason (errno)
  "The operating system's words for ERRNO: \"no space left on device\"."
  (sentence-case (sb-int:strerror errno)))

(defun condition-reason (condition)
  "Why CONDITION (a file, stream or system-call error) happened, as a phrase
without any Lisp object in it."
  (typecase condition
    (io-error (io-error-reason condition))
    (sb-posix:syscall-error (errno-reason (sb-posix:syscall-errno condition)))
    (simple-condition
     ;; SBCL's file and stream errors carry strerror's text as their last argument.
     (let ((last (car (last (simple-condition-format-arguments condition)))))
       (if (stringp last) (sentence-case last) (generic-reason condition))))
    (t (generic-reason condition))))

(defun generic-reason (condition)
  "A phrase for CONDITION when the system gave no reason of its own."
  (typecase condition
    (sb-int:stream-decoding-error "it is not valid UTF-8 text")
    (sb-int:stream-encoding-error "a character cannot be encoded")
    (end-of-file "it ends early")
    (t "input/output error")))

(defun io-fail (file reason &key (action "write"))
  "Signal an IO-ERROR about FILE.  REASON is a phrase or the condition that failed."
  (error 'io-error :file (final-file-name file) :action action
                   :reason (if (stringp reason) reason (condition-reason reason))))

;;;# What kind of file a path names

(defun file-kind (path &key (follow t))
  "What PATH names: :REGULAR, :DIRECTORY, :FIFO, :DEVICE, :SOCKET, :LINK (only
when FOLLOW is NIL), or NIL when nothing is there.  Nothing is opened."
  (let ((stat (handler-case (if follow
                                (sb-posix:stat (os-file-name path))
                                (sb-posix:lstat (os-file-name path)))
                (sb-posix:syscall-error () nil))))
    (and stat (mode-kind (sb-posix:stat-mode stat)))))

(defun mode-kind (mode)
  "The kind of file a stat MODE says."
  (let ((type (logand mode sb-posix:s-ifmt)))
    (cond ((= type sb-posix:s-ifreg) :regular)
          ((= type sb-posix:s-ifdir) :directory)
          ((= type sb-posix:s-ififo) :fifo)
          ((= type sb-posix:s-iflnk) :link)
          ((= type sb-posix:s-ifsock) :socket)
          (t :device))))

(defun kind-reason (kind)
  "Why a file of KIND is refused as data."
  (case kind
    ((nil) "no such file")
    (:directory "it is a directory, not a file")
    (:fifo "it is a FIFO, not a regular file")
    (:socket "it is a socket, not a regular file")
    (:link "it is a symbolic link")
    (t "it is a device, not a regular file")))

(defun check-regular-file (path &key (action "read"))
  "PATH when it names (through links) a regular file; else an IO-ERROR saying what it is.
Stat only: a FIFO or a device is never opened."
  (let ((kind (file-kind path)))
    (unless (eq kind :regular)
      (io-fail path (kind-reason kind) :action action))
    path))

(defun regular-file-or-nil (path)
  "PATH when it names a regular file, NIL when nothing or something else is there."
  (and (eq (file-kind path) :regular) path))

;;;# Reading

(defun open-input-file (path &key (element-type 'character) (external-format :utf-8))
  "A stream reading the regular file PATH.  The file is opened without blocking
\(a FIFO's open returns at once) and checked with fstat before it is read;
anything but a regular file is an IO-ERROR, as is a file that cannot be opened."
  (let ((fd (handler-case (sb-posix:open (os-file-name path) (logior sb-posix:o-rdonly sb-posix:o-nonblock))
              (sb-posix:syscall-error (e) (io-fail path e :action "read")))))
    (handler-bind ((error (lambda (e) (declare (ignore e)) (sb-posix:close fd))))
      (let ((kind (mode-kind (sb-posix:stat-mode (sb-posix:fstat fd)))))
        (unless (eq kind :regular) (io-fail path (kind-reason kind) :action "read")))
      (sb-posix:fcntl fd sb-posix:f-setfl
                      (logandc2 (sb-posix:fcntl fd sb-posix:f-getfl) sb-posix:o-nonblock)))
    (sb-sys:make-fd-stream fd :input t :element-type element-type :external-format external-format
                              :buffering :full :auto-close t
                              ;; FILE-LENGTH needs the stream to know its file.
                              :file (os-file-name path) :pathname (pathname path))))

(defun call-with-input-file (path function &rest options)
  "Call FUNCTION with a stream reading the regular file PATH (OPTIONS as for
OPEN-INPUT-FILE); close it after.  A failed read is an IO-ERROR naming PATH."
  (let ((stream (apply #'open-input-file path options)))
    (unwind-protect
         (handler-bind ((stream-error
                          (lambda (e)
                            (when (and (eq (stream-error-stream e) stream)
                                       (not (typep e '(or end-of-file reader-error))))
                              (io-fail path e :action "read")))))
           (funcall function stream))
      (close stream))))

(defmacro with-input-file ((stream path &rest options) &body body)
  "Run BODY with STREAM reading the regular file PATH (see CALL-WITH-INPUT-FILE)."
  `(call-with-input-file ,path (lambda (,stream) ,@body) ,@options))

(defun file-octets (path &key (limit most-positive-fixnum))
  "The bytes of the regular file PATH; an IO-ERROR when it is longer than LIMIT."
  (with-input-file (in path :element-type '(unsigned-byte 8))
    (let ((length (file-length in)))
      (when (> length limit)
        (io-fail path (format nil "it is larger than ~:D bytes" limit) :action "read"))
      (let* ((octets (make-array length :element-type '(unsigned-byte 8)))
             (end (read-sequence octets in)))
        (if (= end length) octets (subseq octets 0 end))))))
