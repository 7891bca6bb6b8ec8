;;;; boot.lisp -- load Player quietly from this checkout and hand over to PLAYER:MAIN.
(require :asdf)
(let ((root (merge-pathnames "../" (make-pathname :name nil :type nil :defaults *load-truename*))))
  (push (truename root) asdf:*central-registry*))
(let ((log (make-string-output-stream)))
  (handler-case
      (let ((*standard-output* log) (*error-output* log))
        (handler-bind ((warning #'muffle-warning))
          (asdf:load-system "player")))
    (error (e)
      (format *error-output* "player: error: cannot load Player: ~A~%~A"
              (substitute #\Space #\Newline (princ-to-string e))
              (get-output-stream-string log))
      (sb-ext:exit :code 1 :abort t))))
;; SBCL leaves only the program name and the arguments after --end-toplevel-options.
(funcall (intern "MAIN" "PLAYER") (rest sb-ext:*posix-argv*))
