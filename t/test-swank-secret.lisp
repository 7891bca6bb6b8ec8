;;;; test-swank-secret.lisp -- `--swank` admits only clients that know the
;;;; secret (issue 31, item 1).  A raw Swank client -- a socket speaking Swank's
;;;; wire protocol, six hex digits of length then the message -- is refused
;;;; without the secret and served with it; the secret's file is made with
;;;; mode 0600; the server listens on 127.0.0.1 only.

(in-package #:player-tests)

(in-suite hostile-files)

(defun swank-packet (text)
  "TEXT framed as Swank's wire protocol frames a message: its length in UTF-8
octets as six hex digits, then the octets."
  (let ((octets (sb-ext:string-to-octets text :external-format :utf-8)))
    (concatenate '(vector (unsigned-byte 8))
                 (sb-ext:string-to-octets (format nil "~6,'0X" (length octets)) :external-format :ascii)
                 octets)))

(defun read-swank-packet (stream)
  "The next message on STREAM as a string, or NIL when the connection is closed."
  (let ((header (make-array 6 :element-type '(unsigned-byte 8))))
    (when (= 6 (handler-case (read-sequence header stream) (error () 0)))
      (let ((body (make-array (parse-integer (map 'string #'code-char header) :radix 16)
                              :element-type '(unsigned-byte 8))))
        (read-sequence body stream)
        (sb-ext:octets-to-string body :external-format :utf-8)))))

(defun swank-exchange (port messages &key (seconds 10))
  "Connect to 127.0.0.1:PORT, send MESSAGES (strings, framed), and return the
messages received until one holds :return, the connection closes, or SECONDS
pass.  The second value is true when the server closed the connection."
  (let ((socket (make-instance 'sb-bsd-sockets:inet-socket :type :stream :protocol :tcp))
        (received '()) (closed nil))
    (unwind-protect
         (progn
           (sb-bsd-sockets:socket-connect socket #(127 0 0 1) port)
           (let ((stream (sb-bsd-sockets:socket-make-stream socket :input t :output t
                                                                   :element-type '(unsigned-byte 8)
                                                                   :timeout seconds)))
             (dolist (message messages)
               (write-sequence (swank-packet message) stream))
             (finish-output stream)
             (loop for packet = (handler-case (read-swank-packet stream)
                                  (sb-sys:io-timeout () :timeout))
                   do (cond ((null packet) (setf closed t) (return))
                            ((eq packet :timeout) (return))
                            (t (push packet received)
                               (when (search ":return" packet) (return)))))))
      (ignore-errors (sb-bsd-sockets:socket-close socket)))
    (values (reverse received) closed)))

(defun free-port ()
  "A TCP port nothing listens on at 127.0.0.1."
  (loop for port = (+ 20000 (random 30000 (make-random-state t)))
        unless (port-open-p port) return port))

(test swank-refuses-a-client-without-the-secret
  (let* ((home (scratch-folder "swank-home"))
         (old-home (sb-ext:posix-getenv "HOME"))
         (port (free-port))
         (request "(:emacs-rex (swank:interactive-eval \"(* 6 7)\") \"COMMON-LISP-USER\" t 1)"))
    (unwind-protect
         (progn
           (sb-posix:setenv "HOME" (string-right-trim "/" (namestring home)) 1)
           (multiple-value-bind (started secret-file) (player.render::start-swank port)
             (is (eql port started))
             (is (equal (namestring (merge-pathnames ".slime-secret" home)) (namestring secret-file)))
             (is (= #o600 (logand #o777 (sb-posix:stat-mode (sb-posix:stat (namestring secret-file))))))
             (let ((secret (string-trim " " (with-open-file (in secret-file) (read-line in)))))
               (is (= 32 (length secret)))
               ;; Without the secret: the request is taken for a wrong secret, and the door closes.
               (multiple-value-bind (received closed) (swank-exchange port (list request))
                 (is (null received) "a client without the secret was answered: ~S" received)
                 (is-true closed "the connection stayed open"))
               (multiple-value-bind (received closed) (swank-exchange port (list "not the secret" request))
                 (is (null received) "a client with a wrong secret was answered: ~S" received)
                 (is-true closed))
               ;; With it, the server (still running after two refusals) evaluates.
               (let ((received (swank-exchange port (list secret request))))
                 (is (some (lambda (packet) (and (search ":return" packet) (search "42" packet))) received)
                     "the client with the secret got ~S" received)))))
      (player.render::stop-swank port)
      (sb-posix:setenv "HOME" old-home 1)
      (uiop:delete-directory-tree home :validate t :if-does-not-exist :ignore))))

(test swank-refuses-an-unsafe-secret-file
  (let* ((home (scratch-folder "swank-unsafe"))
         (old-home (sb-ext:posix-getenv "HOME"))
         (secret (merge-pathnames ".slime-secret" home)))
    (unwind-protect
         (progn
           (sb-posix:setenv "HOME" (string-right-trim "/" (namestring home)) 1)
           (with-open-file (out secret :direction :output) (write-line "open to all" out))
           (sb-posix:chmod (namestring secret) #o644)
           (let ((message (handler-case (progn (player.render::ensure-swank-secret) nil)
                            (player-error (e) (princ-to-string e)))))
             (is (search "open to other users" (or message "")) "~S" message))
           (sb-posix:chmod (namestring secret) #o600)
           (is (equal secret (player.render::ensure-swank-secret))))
      (sb-posix:setenv "HOME" old-home 1)
      (uiop:delete-directory-tree home :validate t :if-does-not-exist :ignore))))
