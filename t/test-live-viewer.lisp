;;;; test-live-viewer.lisp -- live authoring with a window: `view --watch`
;;;; follows edits of the spec file and script library while it plays (errors
;;;; printed, the window playing on), (player:view ...) returns at once with a
;;;; session the REPL drives and redefines, and `view --swank PORT` listens.
;;;; Like test-viewer.lisp, the window runs under xvfb-run; where it is
;;;; missing the tests say so and pass.

(in-package #:player-tests)

(eval-when (:compile-toplevel :load-toplevel :execute)
  (require :sb-bsd-sockets))

(def-suite* live-viewer :in player-tests)

(defun wait-until (predicate &key (timeout 20))
  "Call PREDICATE every 50 ms until it returns true (return that) or TIMEOUT seconds pass (NIL)."
  (loop with deadline = (+ (get-internal-real-time) (* timeout internal-time-units-per-second))
        do (let ((value (funcall predicate)))
             (when value (return value)))
           (when (> (get-internal-real-time) deadline) (return nil))
           (sleep 0.05)))

(defun start-windowed (program arguments directory)
  "Start PROGRAM with ARGUMENTS under `xvfb-run -a` in DIRECTORY, its standard
output and error going to out.txt and err.txt there; returns the process."
  (sb-ext:run-program "xvfb-run" (list* "-a" program arguments)
                      :search t :wait nil :input nil :directory (namestring directory)
                      :output (namestring (merge-pathnames "out.txt" directory)) :if-output-exists :supersede
                      :error (namestring (merge-pathnames "err.txt" directory)) :if-error-exists :supersede))

(defun finish-windowed (process &key (timeout 60))
  "Wait (at most TIMEOUT seconds) for PROCESS to end; its exit code, or NIL."
  (when (wait-until (lambda () (not (sb-ext:process-alive-p process))) :timeout timeout)
    (sb-ext:process-exit-code process)))

(test view-watch-follows-edits-and-survives-errors
  (with-window-programs ()
    (ensure-player-core)
    (let* ((directory (live-scratch-directory "watch"))
           (spec (merge-pathnames "anim.lisp" directory))
           (library (merge-pathnames "anim-scripts.lisp" directory))
           (spec-text (file-text (fixture "anim.lisp")))
           (library-text (file-text (fixture "anim-scripts.lisp")))
           (out (merge-pathnames "out.txt" directory))
           (err (merge-pathnames "err.txt" directory)))
      (edit-file spec spec-text)
      (edit-file library library-text)
      (unwind-protect
           (let ((process (start-windowed (namestring (checkout-file "bin/player"))
                                          (list "view" "anim.lisp" "--watch" "--size" "160x120"
                                                "--frames" "100000" "--keys" "1@0,escape@6")
                                          directory)))
             (flet ((printed (text file) (wait-until (lambda () (search text (file-text file))))))
               (is-true (printed "; watching anim.lisp anim-scripts.lisp humanoid.lisp for changes" out) "~A" (file-text out))
               ;; A new event: the character switches, keeping its state, and the key map grows.
               (edit-file spec (concatenate 'string (string-right-trim '(#\Newline #\)) spec-text)
                                            (format nil ")~%  (event ev-again :op wave))~%")))
               (is-true (printed "5 ev-again" out) "~A" (file-text out))
               ;; A broken spec: one error line, the old definition plays on.
               (edit-file spec (format nil "(in-package :player-user)~%(defspec anim (op pick-up :typo 3))~%"))
               (is-true (printed "player: error: anim.lisp:2:" err) "~A" (file-text err))
               ;; The script library: read again; broken, refused.
               (edit-file library (format nil "~A~%; edited~%" library-text))
               (is-true (printed "; read the script library anim-scripts.lisp again" out))
               (edit-file library (format nil "~A~%(script~%" library-text))
               (is-true (printed "anim-scripts.lisp" err) "~A" (file-text err))
               (let ((code (finish-windowed process)))
                 (is (eql 0 code) "exit ~A, stderr: ~A" code (file-text err)))
               (let ((lines (lines (file-text out))))
                 (is (member "; now playing the new definition of anim" lines
                             :test (lambda (a b) (eql 0 (search a b)))))
                 ;; The state was kept across the switch: holding since key 1, no new pick-up.
                 (is (= 1 (count-if (lambda (line) (search "(:autoscript-start sway" line)) lines)))
                 (is (find-if (lambda (line) (search " frames in " line)) lines) "the window did not play on")
                 (is (= 2 (length (lines (file-text err)))) "~A" (file-text err)))))
        (uiop:delete-directory-tree directory :validate t :if-does-not-exist :ignore)))))

(defparameter *view-session-script*
  '((in-package :player)
    ;; Its own file, not standard output: the viewer's thread writes there too,
    ;; and SBCL's fd-streams are not safe to share between threads.
    (defun check (name value)
      (with-open-file (stream :checks-file :direction :output :if-exists :append :if-does-not-exist :create)
        (format stream "CHECK ~A ~S~%" name value)))
    (load-spec (second sb-ext:*posix-argv*))
    (defparameter *v* (view 'player-user::anim :size '(160 120)))
    (check "returned-running" (view-running-p *v*))
    (check "send" (send-event *v* 'player-user::ev-pick))
    (sleep 1.2)
    (check "state" (call-in-view *v* (lambda (c) (state-value c 'player-user::holding))))
    (define-spec 'player-user::anim
        '((:scripts "anim-scripts.lisp") (state-variable holding boolean false)
          (state-variable happy boolean false)
          (op pick-up :add holding :duration 1) (op wave :add happy :duration 1.5)
          (autoscript holding true (sway))
          (event ev-pick :op pick-up) (event ev-cheer :op wave))
        :package (find-package :player-user) :source-file (pathname (second sb-ext:*posix-argv*)))
    (sleep 0.3)
    (check "kept" (call-in-view *v* (lambda (c) (list (state-value c 'player-user::holding)
                                                      (state-value c 'player-user::happy)))))
    (check "new-event" (send-event *v* 'player-user::ev-cheer))
    (check "unknown" (handler-case (send-event *v* 'player-user::ev-drop) (unknown-event () :unknown-event)))
    (check "scripts" (reload-view-scripts *v*))
    (check "bad-scripts" (handler-case (reload-view-scripts *v* "/nonexistent/scripts.lisp")
                           (script-error () :script-error)))
    (check "stop" (stop-view *v*))
    (check "stopped" (view-running-p *v*))
    (check "after" (handler-case (send-event *v* 'player-user::ev-pick) (player-error () :player-error))))
  "Forms a Lisp under xvfb-run evaluates: VIEW at the REPL, redefinition, STOP-VIEW.")

(test view-from-the-repl-returns-a-session
  (with-window-programs ()
    (let* ((directory (live-scratch-directory "session"))
           (script (merge-pathnames "session.lisp" directory)))
      (with-open-file (stream script :direction :output)
        (with-standard-io-syntax
          (let ((*package* (find-package :player-tests)))
            (dolist (form (subst (namestring (merge-pathnames "checks.txt" directory)) :checks-file
                                 *view-session-script*))
              (print form stream)))))
      (unwind-protect
           (let* ((process (start-windowed
                            "sbcl" (list "--noinform" "--non-interactive" "--no-userinit"
                                         "--eval" "(require :asdf)"
                                         "--eval" (format nil "(push ~S asdf:*central-registry*)" (namestring *root*))
                                         "--eval" "(handler-bind ((warning #'muffle-warning)) (asdf:load-system \"player\"))"
                                         "--load" (namestring script) "--end-toplevel-options"
                                         (fixture "anim.lisp"))
                            directory))
                  (code (finish-windowed process :timeout 120))
                  (checks (loop for line in (lines (file-text (merge-pathnames "checks.txt" directory)))
                                when (eql 0 (search "CHECK " line))
                                  collect (let ((space (position #\Space line :start 6)))
                                            (cons (subseq line 6 space) (subseq line (1+ space)))))))
             (is (eql 0 code) "exit ~A: ~A" code (file-text (merge-pathnames "err.txt" directory)))
             (is (equal '(("returned-running" . "T") ("send" . "T") ("state" . "T") ("kept" . "(T NIL)")
                          ("new-event" . "T") ("unknown" . ":UNKNOWN-EVENT") ("scripts" . "T")
                          ("bad-scripts" . ":SCRIPT-ERROR") ("stop" . "T")
                          ("stopped" . "NIL") ("after" . ":PLAYER-ERROR"))
                        checks)
                 "~S~%stderr: ~A" checks (file-text (merge-pathnames "err.txt" directory))))
        (uiop:delete-directory-tree directory :validate t :if-does-not-exist :ignore)))))

(defun port-open-p (port)
  "Does something accept TCP connections on 127.0.0.1:PORT?"
  (let ((socket (make-instance 'sb-bsd-sockets:inet-socket :type :stream :protocol :tcp)))
    (unwind-protect
         (handler-case (progn (sb-bsd-sockets:socket-connect socket #(127 0 0 1) port) t)
           (error () nil))
      (sb-bsd-sockets:socket-close socket))))

(test view-swank-listens-while-the-viewer-plays
  (with-window-programs ()
    (ensure-player-core)
    (let* ((directory (live-scratch-directory "swank"))
           (port (loop for port = (+ 20000 (random 30000 (make-random-state t)))
                       unless (port-open-p port) return port)))
      (unwind-protect
           (let* ((process (start-windowed (namestring (checkout-file "bin/player"))
                                           (list "view" (fixture "anim.lisp") "--size" "160x120" "--frames" "90"
                                                 "--swank" (princ-to-string port))
                                           directory))
                  ;; The first run compiles Swank (cl-swank) into ~/.cache: allow for it.
                  (connected (wait-until (lambda () (cond ((port-open-p port) :open)
                                                          ((not (sb-ext:process-alive-p process)) :exited)))
                                         :timeout 120))
                  (code (finish-windowed process)))
             (is (eq :open connected) "no connection to port ~D: ~A" port connected)
             (is (eql 0 code) "exit ~A: ~A" code (file-text (merge-pathnames "err.txt" directory)))
             (is (search (format nil "; Swank listens on port ~D" port)
                         (file-text (merge-pathnames "out.txt" directory))))
             (is (not (port-open-p port)) "Swank still listens after the viewer closed"))
        (uiop:delete-directory-tree directory :validate t :if-does-not-exist :ignore)))))
