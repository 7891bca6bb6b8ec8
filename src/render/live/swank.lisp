;;;; swank.lisp -- a Swank server in the running image, so Emacs/SLIME can
;;;; connect to a viewer and re-evaluate its DEFSPEC there.  Swank is Debian's
;;;; cl-swank, loaded through ASDF only when asked for: Player needs it for
;;;; nothing else.  Trust: the server listens on 127.0.0.1 only and every
;;;; connection must first send Swank's secret, the first line of
;;;; ~/.slime-secret (made here, mode 0600, when missing); SLIME sends it by
;;;; itself.  A connection without it is closed, and the viewer runs on.

(in-package #:player.render)

(defun swank-function (name)
  "The function NAME of the loaded SWANK package."
  (symbol-function (find-symbol name "SWANK")))

(defvar *contrib-directory*
  (ignore-errors (merge-pathnames "contrib/" (sb-int:sbcl-homedir-pathname)))
  "Where SBCL's contribs (sb-bsd-sockets, sb-introspect...) were when Player
was loaded: bin/player's saved core runs without SBCL_HOME, so REQUIRE alone
cannot find them.")

(defun require-contrib (name)
  "A module provider: load contrib NAME's fasl from *CONTRIB-DIRECTORY*; true when it did."
  (let ((fasl (and *contrib-directory*
                   (probe-file (merge-pathnames (make-pathname :name (string-downcase (string name))
                                                               :type "fasl")
                                                *contrib-directory*)))))
    (when fasl
      (load fasl)
      t)))

(defun load-swank ()
  "Load Swank through ASDF unless it is loaded.  Signals a PLAYER-ERROR naming
the package cl-swank when ASDF cannot find it or it does not load."
  (unless (find-package "SWANK")
    (flet ((fail (why)
             (error 'player-error-with-message
                    :message (format nil "cannot start Swank: ~A (install Debian's cl-swank: apt-get install cl-swank)"
                                     why))))
      (pushnew 'require-contrib sb-ext:*module-provider-functions*)
      (unless (ignore-errors (asdf:find-system "swank" nil))
        (fail "ASDF finds no system \"swank\""))
      ;; Compiling Swank the first time prints pages of notes: keep them out of the trace.
      (handler-case (let ((*standard-output* (make-broadcast-stream))
                          (*error-output* (make-broadcast-stream)))
                      (handler-bind ((warning #'muffle-warning))
                        (asdf:load-system "swank")))
        (error (e) (fail (condition-line e)))))))

(defun swank-secret-file ()
  "Where Swank looks for its secret: ~/.slime-secret."
  (merge-pathnames ".slime-secret" (user-homedir-pathname)))

(defun swank-fail (control &rest arguments)
  "Signal a PLAYER-ERROR: Swank cannot start, for the reason CONTROL and ARGUMENTS give."
  (error 'player-error-with-message
         :message (format nil "cannot start Swank: ~?" control arguments)))

(defun ensure-swank-secret ()
  "The file holding Swank's secret, made when missing: 32 random hex digits,
created exclusively with mode 0600 (never through a link).  An existing one
must be a regular file of this user's, unreadable by others, its first line
not empty; else a PLAYER-ERROR saying what to fix."
  (let* ((file (swank-secret-file))
         (name (sb-ext:native-namestring file)))
    (unless (file-kind file :follow nil)
      (let ((secret (with-open-file (random "/dev/urandom" :element-type '(unsigned-byte 8))
                      (format nil "~{~(~2,'0X~)~}" (loop repeat 16 collect (read-byte random))))))
        (handler-case
            (let ((fd (sb-posix:open name (logior sb-posix:o-wronly sb-posix:o-creat sb-posix:o-excl
                                                  sb-posix:o-nofollow)
                                     #o600)))
              (with-open-stream (out (sb-sys:make-fd-stream fd :output t :external-format :utf-8))
                (write-line secret out)))
          (sb-posix:syscall-error (e) (io-fail file e :action "create")))))
    (let ((stat (sb-posix:lstat name)))
      (cond ((not (eq (file-kind file :follow nil) :regular))
             (swank-fail "~A is not a regular file" name))
            ((/= (sb-posix:stat-uid stat) (sb-posix:getuid))
             (swank-fail "~A belongs to another user" name))
            ((plusp (logand (sb-posix:stat-mode stat) #o077))
             (swank-fail "~A is open to other users; chmod 600 it" name))
            ((string= "" (with-input-file (in file) (string-trim " " (read-line in nil ""))))
             (swank-fail "~A is empty: its first line is the secret" name))))
    file))

(defun guard-swank-connections ()
  "Make a connection that fails Swank's secret be closed and forgotten: Swank
signals an error in its accepting thread, which would otherwise end the
whole viewer (the debugger is off)."
  (let* ((accept (find-symbol "ACCEPT-CONNECTIONS" "SWANK"))
         (original (fdefinition accept)))
    (unless (get accept 'player-guarded)
      (setf (get accept 'player-guarded) t
            (fdefinition accept)
            (lambda (socket style dont-close)
              (handler-case (funcall original socket style dont-close)
                (error ()
                  (ignore-errors
                   (write-live-line *standard-output* "; Swank closed a connection that did not send the secret~%"))
                  (sleep 0.05)          ; never a busy loop, whatever failed
                  nil)))))
    (let* ((authenticate (find-symbol "AUTHENTICATE-CLIENT" "SWANK"))
           (original (fdefinition authenticate)))
      (unless (get authenticate 'player-guarded)
        (setf (get authenticate 'player-guarded) t
              (fdefinition authenticate)
              (lambda (stream)
                (handler-bind ((error (lambda (e) (declare (ignore e)) (ignore-errors (close stream :abort t)))))
                  (funcall original stream))))))))

(defun start-swank (port)
  "Start a Swank server on the loopback interface (127.0.0.1), port PORT (an
integer from 1 to 65535), for SLIME's M-x slime-connect; it serves on its
own threads and every connection shares this image, its specs and its
viewers.  A connection must first send the secret in ~/.slime-secret (made,
mode 0600, when missing; see ENSURE-SWANK-SECRET).  Returns PORT and the
secret's file.  Signals a PLAYER-ERROR when Swank is missing (naming
cl-swank), the secret's file is unsafe, or Swank cannot listen on PORT."
  (check-argument 'start-swank 'port port (lambda (x) (typep x '(integer 1 65535)))
                  "a TCP port number from 1 to 65535")
  (load-swank)
  (ensure-swank-secret)
  (guard-swank-connections)
  (handler-case (let ((*standard-output* (make-broadcast-stream)))
                  (funcall (swank-function "CREATE-SERVER") :port port :dont-close t
                                                            :interface "127.0.0.1"))
    (error (e)
      (error 'player-error-with-message
             :message (format nil "cannot start Swank on port ~D: ~A" port (condition-line e)))))
  (values port (swank-secret-file)))

(defun stop-swank (port)
  "Stop the Swank server on PORT, if one runs."
  (when (find-package "SWANK")
    (handler-bind ((warning #'muffle-warning))
      (ignore-errors (funcall (swank-function "STOP-SERVER") port)))))
