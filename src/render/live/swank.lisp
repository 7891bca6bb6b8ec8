;;;; swank.lisp -- a Swank server in the running image, so Emacs/SLIME can
;;;; connect to a viewer and re-evaluate its DEFSPEC there.  Swank is Debian's
;;;; cl-swank, loaded through ASDF only when asked for: Player needs it for
;;;; nothing else.

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

(defun start-swank (port)
  "Start a Swank server on the loopback interface, port PORT (an integer from
1 to 65535), for SLIME's M-x slime-connect; it serves on its own threads and
every connection shares this image, its specs and its viewers.  Returns
PORT.  Signals a PLAYER-ERROR when Swank is missing (naming cl-swank) or
cannot listen on PORT."
  (check-argument 'start-swank 'port port (lambda (x) (typep x '(integer 1 65535)))
                  "a TCP port number from 1 to 65535")
  (load-swank)
  (handler-case (let ((*standard-output* (make-broadcast-stream)))
                  (funcall (swank-function "CREATE-SERVER") :port port :dont-close t))
    (error (e)
      (error 'player-error-with-message
             :message (format nil "cannot start Swank on port ~D: ~A" port (condition-line e)))))
  port)

(defun stop-swank (port)
  "Stop the Swank server on PORT, if one runs."
  (when (find-package "SWANK")
    (handler-bind ((warning #'muffle-warning))
      (ignore-errors (funcall (swank-function "STOP-SERVER") port)))))
