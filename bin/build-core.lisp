;;;; build-core.lisp -- build the executable core bin/player starts from:
;;;; load Player quietly from this checkout, then save the image to the path
;;;; given after --end-toplevel-options.  bin/player runs this when the core
;;;; is missing or older than a source file.
(require :asdf)
(let ((root (merge-pathnames "../" (make-pathname :name nil :type nil :defaults *load-truename*))))
  (push (truename root) asdf:*central-registry*))
(let ((log (make-string-output-stream)))
  (handler-case
      (let ((*standard-output* log) (*error-output* log))
        (load (merge-pathnames "load-system.lisp" *load-truename*))
        (unless (uiop:symbol-call '#:player-build '#:load-checked "player" :stream log)
          (error "compiling Player gave full warnings")))
    (error (e)
      (format *error-output* "player: error: cannot build Player: ~A~%~A"
              (substitute #\Space #\Newline (princ-to-string e))
              (get-output-stream-string log))
      (sb-ext:exit :code 1 :abort t))))
;; SBCL leaves only the program name and the arguments after --end-toplevel-options.
(funcall (intern "SAVE-CORE" "PLAYER.CLI") (second sb-ext:*posix-argv*))
