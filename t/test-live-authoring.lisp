;;;; test-live-authoring.lisp -- live authoring that keeps up (issue 27, item
;;;; 3): the viewer follows every file a character is made of, one save gives
;;;; one line, a signal closes it at once with the shell's exit status, every
;;;; event can be typed by name, and a macro-op's trace line carries its real
;;;; end.  The window tests run under xvfb-run (see test-viewer.lisp); the
;;;; others drive a viewer with no window, frame by frame.

(in-package #:player-tests)

(def-suite* live-authoring :in player-tests)

;;;# A viewer without a window

(defun windowless-viewer (spec &key initial)
  "A viewer of SPEC (a spec) playing a timed controller on a body presenter
of placeholder scripts, from INITIAL, with no window: tests set its NOW."
  (let* ((presenter (make-body-presenter spec :silent t))
         (controller (make-controller (compile-spec spec) :initial-state initial :presenter presenter
                                                          :timed t)))
    (player.render::%make-viewer :controller controller :performance (presenter-performance presenter)
                                 :name (string-downcase (spec-name spec)) :spec spec
                                 :keys (player.render:view-event-keys spec))))

(defun play-windowless (viewer until &key (step 0.25d0))
  "Play VIEWER frame by frame (STEP seconds apart) up to UNTIL, then to the
end; the lines its trace printed, as strings."
  (lines (with-output-to-string (*standard-output*)
           (loop for now from 0d0 to until by step
                 do (setf (player.render:viewer-now viewer) now)
                    (player.render:advance-viewer viewer)
                    (player.render:print-due-trace viewer))
           (player.render:print-due-trace viewer t))))

(defun many-events-spec (count)
  "A spec of COUNT events, ev-1 ... ev-COUNT, each playing an op of its own."
  (define-spec 'player-user::many-events
      (append (loop for k from 1 to count
                    collect `(player-user::op ,(intern (format nil "O~D" k) :player-user) :duration 0.1))
              (loop for k from 1 to count
                    collect `(player-user::event ,(intern (format nil "EV-~D" k) :player-user)
                                                 :op ,(intern (format nil "O~D" k) :player-user))))
    :package (find-package :player-user)))

(test viewer-takes-every-event-by-name
  ;; 40 events, 35 keys: the last five are listed and can be typed.
  (let* ((spec (many-events-spec 40))
         (viewer (windowless-viewer spec))
         (key-map (with-output-to-string (*standard-output*)
                    (player.render::print-key-map (player.render::viewer-keys viewer)))))
    (is (= 40 (length (player.render::viewer-keys viewer))))
    (dolist (name '("ev-1" "ev-35" "ev-36" "ev-40"))
      (is (find-if (lambda (line) (equal name (string-trim " " (subseq line (min 2 (length line))))))
                   (lines key-map))
          "~A missing from the key map:~%~A" name key-map))
    (let ((*standard-input* (make-string-input-stream (format nil "ev-40~%"))))
      (player.render::read-terminal viewer))
    (let ((printed (play-windowless viewer 1)))
      (is (find "(:event ev-40 :time 0)" printed :test #'string=) "~S" printed))))

(test viewer-trace-shows-macro-ends
  ;; Woken from a snore, ev-search plays the macro-op hard-wake first: its
  ;; line must say when it really ends, before its sub-ops' lines, as `run` has it.
  (let* ((spec (load-spec-file-quietly (fixture "mini.lisp")))
         (viewer (windowless-viewer spec :initial '((alert . snore)))))
    (setf (player.render:viewer-now viewer) 0d0)
    (player.render:view-send-event viewer 'player-user::ev-search)
    (let* ((printed (play-windowless viewer 12))
           (lines (mapcar (lambda (text) (let ((*package* (find-package :player-user))) (read-from-string text)))
                          (remove-if-not (lambda (text) (search "(:op " text)) printed)))
           (macro (find 'player-user::hard-wake lines :key #'second))
           (subs (remove-if-not (lambda (line) (member (second line) '(player-user::snort player-user::exhale
                                                                          player-user::focus)))
                                lines)))
      (is (= 3 (length subs)) "~S" printed)
      (is (eq macro (first lines)) "~S" printed)
      (when (and macro subs)
        (is (= (getf (cddr macro) :start) (getf (cddr (first subs)) :start)))
        (is (> (getf (cddr macro) :end) (getf (cddr macro) :start)) "~S" macro)
        (is (= (getf (cddr macro) :end) (reduce #'max subs :key (lambda (line) (getf (cddr line) :end))))
            "~S" printed)))))

(defun load-spec-file-quietly (path)
  "The first spec PATH defines."
  (first (load-spec path)))

;;;# Watching files

(test watcher-reports-a-two-step-save-once
  ;; An editor that empties the file, then fills it, between two looks: one change.
  (let* ((directory (live-scratch-directory "watcher"))
         (path (namestring (merge-pathnames "spec.lisp" directory)))
         (player.render::*watch-interval* 1d0))
    (unwind-protect
         (progn
           (edit-file path "(a)")
           (let ((watcher (player.render::make-file-watcher (list path) 0d0))
                 (reports '()))
             (flet ((look (now) (dolist (p (player.render::watcher-changes watcher now)) (push (cons now p) reports))))
               (edit-file path "")
               (look 1d0)
               (edit-file path "(a b)")
               (look 2d0)
               (look 3d0)
               (look 4d0)
               (is (= 1 (length reports)) "~S" reports)
               (edit-file path "(a b c)")
               (look 5d0) (look 6d0) (look 7d0)
               (is (= 2 (length reports)) "~S" reports))))
      (uiop:delete-directory-tree directory :validate t :if-does-not-exist :ignore))))

;;;# A window on a display of its own

(defun call-with-xvfb-display (function)
  "Start an Xvfb server on a free display (it prints the number it took:
-displayfd 1) and call FUNCTION with DISPLAY's value, \":N\"; stop it after.
The viewer runs as a direct child of this Lisp, so its own exit status and
pid are the test's to see (xvfb-run would stand between them)."
  (let ((server (sb-ext:run-program "Xvfb" (list "-displayfd" "1" "-nolisten" "tcp" "-screen" "0" "320x240x24")
                                    :search t :wait nil :input nil :output :stream :error nil)))
    (unwind-protect
         (let ((number (read-line (sb-ext:process-output server) nil)))
           (if number
               (funcall function (format nil ":~A" (string-trim " " number)))
               (fail "Xvfb did not start")))
      (when (sb-ext:process-alive-p server)
        (sb-ext:process-kill server 15)
        (sb-ext:process-wait server)))))

(defun start-viewer-on (display directory &rest arguments)
  "Start `bin/player view ARGUMENTS` (default: the anim fixture) in DIRECTORY
on DISPLAY, its output in DIRECTORY's out.txt and err.txt."
  (sb-ext:run-program (namestring (checkout-file "bin/player"))
                      (list* "view" (or arguments (list (fixture "anim.lisp") "--size" "160x120" "--silent")))
                      :wait nil :input nil :directory (namestring directory)
                      :environment (cons (format nil "DISPLAY=~A" display)
                                         (remove-if (lambda (entry) (eql 0 (search "DISPLAY=" entry)))
                                                    (sb-ext:posix-environ)))
                      :output (namestring (merge-pathnames "out.txt" directory)) :if-output-exists :supersede
                      :error (namestring (merge-pathnames "err.txt" directory)) :if-error-exists :supersede))

(defun humanoid-skeleton-text ()
  "The text of the humanoid skeleton shipped with Player."
  (file-text (merge-pathnames "humanoid.lisp" player.body::*shipped-skeletons-directory*)))

(test view-watch-follows-poses-and-skeleton
  (with-window-programs ()
    (ensure-player-core)
    (let* ((directory (live-scratch-directory "watch-all"))
           (spec (merge-pathnames "anim.lisp" directory))
           (library (merge-pathnames "anim-scripts.lisp" directory))
           (poses (merge-pathnames "anim-poses.lisp" directory))
           (skeleton (merge-pathnames "figure.lisp" directory))
           (spec-text (file-text (fixture "anim.lisp")))
           (out (merge-pathnames "out.txt" directory))
           (err (merge-pathnames "err.txt" directory)))
      (edit-file spec (let ((at (search "(:body humanoid)" spec-text)))
                            (concatenate 'string (subseq spec-text 0 at) "(:body \"figure.lisp\")"
                                         (subseq spec-text (+ at (length "(:body humanoid)"))))))
      (edit-file library (format nil "(poses \"anim-poses.lisp\")~%~A" (file-text (fixture "anim-scripts.lisp"))))
      (edit-file poses (format nil ";;;; no poses of its own~%"))
      (edit-file skeleton (humanoid-skeleton-text))
      (unwind-protect
           (call-with-xvfb-display
            (lambda (display)
              (let ((process (start-viewer-on display directory "anim.lisp" "--watch" "--size" "160x120" "--silent")))
                (flet ((printed (text) (wait-until (lambda () (search text (file-text out))))))
                  (unwind-protect
                       (progn
                         (is-true (printed "; watching anim.lisp anim-scripts.lisp anim-poses.lisp figure.lisp for changes")
                                  "~A" (file-text out))
                         (edit-file poses (format nil ";;;; no poses of its own~%;;;; still none~%"))
                         (is-true (printed "; read the pose library anim-poses.lisp again") "~A" (file-text out))
                         (edit-file skeleton (format nil "~A~%;;; edited~%" (humanoid-skeleton-text)))
                         (is-true (printed "; read the skeleton figure.lisp again") "~A~A" (file-text out) (file-text err))
                         (edit-file skeleton "(skeleton")
                         (is-true (wait-until (lambda () (search "figure.lisp" (file-text err)))) "~A" (file-text err))
                         ;; One save of the spec, one line.
                         (edit-file spec (concatenate 'string (string-right-trim '(#\Newline #\)) (file-text spec))
                                                      (format nil ")~%  (event ev-again :op wave))~%")))
                         (is-true (printed "5 ev-again") "~A" (file-text out))
                         (sleep 1)
                         (sb-ext:process-kill process 15)
                         (is-true (wait-until (lambda () (not (sb-ext:process-alive-p process)))))
                         (is (eql 143 (sb-ext:process-exit-code process)) "exit ~A, stderr: ~A"
                             (sb-ext:process-exit-code process) (file-text err))
                         (let ((lines (lines (file-text out))))
                           (is (= 1 (count-if (lambda (line)
                                                (and (search "anim.lisp" line) (not (search "; watching" line))))
                                              lines))
                               "~A" (file-text out))
                           (is (find "; now playing the new definition of anim" lines
                                     :test (lambda (a b) (and (eql 0 (search a b)) (search "anim.lisp read again" b))))
                               "~A" (file-text out))))
                    (when (sb-ext:process-alive-p process)
                      (sb-ext:process-kill process 9)
                      (sb-ext:process-wait process)))))))
        (uiop:delete-directory-tree directory :validate t :if-does-not-exist :ignore)))))

;;;# Signals

(test view-stops-on-signals-within-a-second
  (with-window-programs ()
    (ensure-player-core)
    (loop for (signal . status) in '((15 . 143) (2 . 130) (1 . 129))
          do (let ((directory (live-scratch-directory "signal")))
               (unwind-protect
                    (call-with-xvfb-display
                     (lambda (display)
                       (let ((process (start-viewer-on display directory))
                             (out (merge-pathnames "out.txt" directory)))
                         (unwind-protect
                              (progn
                                (is-true (wait-until (lambda () (search "; space pauses" (file-text out))) :timeout 60)
                                         "signal ~D: the viewer did not start: ~A" signal
                                         (file-text (merge-pathnames "err.txt" directory)))
                                (sleep 0.5)
                                (let ((sent (get-internal-real-time)))
                                  (sb-ext:process-kill process signal)
                                  (let ((stopped (wait-until (lambda () (not (sb-ext:process-alive-p process)))
                                                             :timeout 10))
                                        (seconds (/ (- (get-internal-real-time) sent) internal-time-units-per-second)))
                                    (is-true stopped "signal ~D: still running" signal)
                                    (is (< seconds 1) "signal ~D: ~,2F s to stop" signal seconds)))
                                (is (eq :exited (sb-ext:process-status process)))
                                (is (eql status (sb-ext:process-exit-code process))
                                    "signal ~D: exit ~A, stderr: ~A" signal (sb-ext:process-exit-code process)
                                    (file-text (merge-pathnames "err.txt" directory)))
                                (is (search " frames in " (file-text out))
                                    "signal ~D: the window did not close the ordinary way" signal))
                           (when (sb-ext:process-alive-p process)
                             (sb-ext:process-kill process 9)
                             (sb-ext:process-wait process))))))
                 (uiop:delete-directory-tree directory :validate t :if-does-not-exist :ignore))))))
