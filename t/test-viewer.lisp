;;;; test-viewer.lisp -- `bin/player view` as a user (or CI) runs it: under
;;;; Xvfb it opens a window, plays frames, takes scripted keys and terminal
;;;; input and saves a screenshot that shows the body; with no display it
;;;; fails with one clear error.  Uses PLAYER-COMMAND's neighbours from
;;;; test-cli.lisp and DECODE-PNGS from test-render-base.lisp.
;;;;
;;;; The window tests need xvfb-run and xauth (the Debian packages xvfb and
;;;; xauth, which .ci/run installs); where they are missing the tests say so
;;;; on stdout and pass without running, rather than fail on a headless box.

(in-package #:player-tests)

(def-suite* viewer :in player-tests)

(defun missing-window-programs ()
  "The programs the window tests need that are not installed."
  (remove-if #'player.base::find-executable '("xvfb-run" "xauth")))

(defun view-command (arguments &key (xvfb t) (input nil))
  "Run `bin/player view ARGUMENTS`, under `xvfb-run -a` when XVFB, else with no
display in the environment; INPUT, a string, is its standard input.  Returns
(VALUES STDOUT STDERR EXIT-CODE)."
  (ensure-player-core)
  (let* ((out (make-string-output-stream))
         (err (make-string-output-stream))
         (player (namestring (checkout-file "bin/player")))
         (environment (remove-if (lambda (entry)
                                   (and (not xvfb)
                                        (some (lambda (name) (eql 0 (search name entry)))
                                              '("DISPLAY=" "WAYLAND_DISPLAY="))))
                                 (sb-ext:posix-environ)))
         (process (if xvfb
                      (sb-ext:run-program "xvfb-run" (list* "-a" player "view" arguments)
                                          :search t :output out :error err :environment environment
                                          :input (and input (make-string-input-stream input))
                                          :directory (namestring *root*))
                      (sb-ext:run-program player (list* "view" arguments)
                                          :output out :error err :environment environment
                                          :directory (namestring *root*)))))
    (values (get-output-stream-string out) (get-output-stream-string err)
            (sb-ext:process-exit-code process))))

(defmacro with-window-programs (() &body body)
  "Run BODY when xvfb-run and xauth are installed; otherwise say which are missing and pass."
  `(let ((missing (missing-window-programs)))
     (if missing
         (progn (format t "~&; skipped a window test: ~{~A~^ and ~} not installed (apt-get install xvfb xauth)~%"
                        missing)
                (pass))
         (progn ,@body))))

(defun body-pixel-share (pixels width height)
  "The share of the middle third (both ways) of an RGBA image whose colour is
more than 40 levels from its row's median colour, the background's estimate:
sky and floor change little along a row, so what differs is what stands there."
  (let ((differing 0) (total 0))
    (loop for y from (floor height 3) below (floor (* 2 height) 3)
          for median = (loop for c below 3
                             collect (let ((row (sort (loop for x below width
                                                            collect (aref pixels (+ c (* 4 (+ x (* y width))))))
                                                      #'<)))
                                       (nth (floor width 2) row)))
          do (loop for x from (floor width 3) below (floor (* 2 width) 3)
                   do (incf total)
                      (when (loop for c below 3
                                  for m in median
                                  thereis (> (abs (- (aref pixels (+ c (* 4 (+ x (* y width))))) m)) 40))
                        (incf differing))))
    (/ differing total)))

(test view-shows-peedy-and-takes-scripted-keys
  (with-window-programs ()
    (let ((screenshot (temporary-png "view")))
      (unwind-protect
           (multiple-value-bind (out err code)
               (view-command (list (namestring (checkout-file "specs/peedy.lisp")) "--size" "320x240"
                                   "--frames" "30" "--screenshot" (namestring screenshot) "--keys" "1@0"))
             (let ((lines (lines out)))
               (is (= 0 code) "exit ~D, stderr: ~A" code err)
               (is (member "1 ev-search" lines :test #'string=) "no key map in ~A" out)
               (is (member "2 ev-bad-speech" lines :test #'string=))
               ;; Key 1 sends ev-search on the first frame, at time 0.
               (is (member "(:event ev-search :time 0)" lines :test #'string=) "no event in ~A" out)
               (is (find-if (lambda (line) (search "(:op search" line)) lines))
               (is (member "; 30 frames" lines :test (lambda (a b) (eql 0 (search a b))))))
             (destructuring-bind (&optional width height depth colour-type &rest more)
                 (first (decode-pngs (list screenshot)))
               (is (equal '(320 240 8 6) (list width height depth colour-type)) "bad PNG: ~A" width)
               (when (eql width 320)
                 (let ((share (body-pixel-share (car (last more)) 320 240)))
                   (is (< 0.05 share 0.9) "~,1F% of the middle differs from the background"
                       (* 100 share))))))
        (ignore-errors (delete-file screenshot))))))

(test view-takes-terminal-input-and-escape
  (with-window-programs ()
    (multiple-value-bind (out err code)
        (view-command (list (fixture "anim.lisp") "--size" "160x120" "--frames" "100000"
                            "--keys" "2@0,escape@1.5")
                      :input (format nil "ev-wave~%bogus~%"))
      (let ((lines (lines out)))
        (is (= 0 code) "exit ~D, stderr: ~A" code err)
        (is (equal '("1 ev-pick" "2 ev-drop" "3 ev-wave" "4 ev-pan")
                   (remove-if-not (lambda (line) (eql 1 (search " ev-" line))) lines)))
        ;; The key and the typed name both send their events at the playback time;
        ;; the second waits its turn and starts when the first ends, at 1 s.
        (is (member "(:event ev-drop :time 0)" lines :test #'string=) "~A" out)
        (is (member "(:event ev-wave :time 1)" lines :test #'string=) "~A" out)
        (is (find-if (lambda (line) (search "no event bogus" line)) lines))
        ;; Escape ended it long before 100000 frames.
        (is (find-if (lambda (line) (and (eql 0 (search "; " line)) (search " frames in " line)
                                         (< (parse-integer line :start 2 :junk-allowed t) 1000)))
                     lines))))))

(test view-without-a-display-fails-clearly
  (multiple-value-bind (out err code)
      (view-command (list (fixture "anim.lisp") "--frames" "1") :xvfb nil)
    (declare (ignore out))
    (is (= 1 code))
    (is (equal '("player: error: cannot open a window: no display (set DISPLAY or run under xvfb-run)")
               (lines err)))))

(test view-rejects-bad-options
  ;; All found before a window is opened, so no display is needed.
  (loop for (arguments status text)
          in '((("--keys" "1") 2 "--keys takes KEY@SECONDS")
               (("--keys" "shift@1") 2 "unknown key shift")
               (("--keys" "9@1") 2 "scripted key 9")
               (("--size" "big") 2 "--size takes WIDTHxHEIGHT")
               (("--frames" "0") 2 "--frames takes a positive integer"))
        do (multiple-value-bind (out err code)
               (view-command (list* (fixture "anim.lisp") arguments) :xvfb nil)
             (declare (ignore out))
             (is (= status code) "~A: exit ~D" arguments code)
             (is (= 1 (length (lines err))) "~A: ~A" arguments err)
             (is (search text err) "~A: ~A" arguments err))))

;;; In-process pieces, no window needed

(test view-title-shows-the-state
  (with-spec (spec viewed
              (state-variable on boolean false)
              (state-variable mode string low (low high))
              (time-variable poked (ev-on))
              (op switch-on :add on :duration 1)
              (event ev-on :op switch-on))
    (let* ((controller (make-controller (compile-spec spec)))
           (viewer (player.render::%make-viewer :controller controller :name "viewed")))
      (is (string= "viewed -- on=false mode=low poked=-" (player.render::view-title viewer)))
      (send-event controller 'ev-on :at 2.5)
      (setf (player.render::viewer-paused-at viewer) 0d0)
      (is (string= "viewed -- on=true mode=low poked=2.5 [paused]" (player.render::view-title viewer))))))

(test view-prints-trace-lines-when-their-time-comes
  (with-spec (spec timed
              (state-variable on boolean false)
              (op first-half :duration 1)
              (op second-half :add on :duration 1)
              (event ev :op first-half :op second-half))
    (let* ((controller (make-controller (compile-spec spec)))
           (viewer (player.render::%make-viewer :controller controller)))
      (send-event controller 'ev :at 0.5)
      (flet ((printed-at (now)
               (setf (player.render::viewer-now viewer) now)
               (lines (with-output-to-string (*standard-output*) (player.render::print-due-trace viewer)))))
        (is (equal '() (printed-at 0.25d0)))
        (is (equal '("(:event ev :time 0.5)" "(:op first-half :script first-half :start 0.5 :end 1.5)")
                   (printed-at 1d0)))
        ;; The state line follows the last op's line.
        (is (equal '("(:op second-half :script second-half :start 1.5 :end 2.5)" "(:state (on . t))") (printed-at 2d0)))
        (is (equal '() (printed-at 5d0)))))))

(defun keys-option (text)
  "What view's --keys TEXT reads as."
  (getf (nth-value 1 (player.cli::parse-command-arguments (player.cli::find-command "view") (list "spec.lisp" "--keys" text)))
        :keys))

(test view-keys-option
  (is (equal '((0d0 . #\1) (2.5d0 . :space) (3d0 . :escape) (4d0 . #\a))
             (keys-option "1@0, space@2.5,Escape@3,A@4")))
  (signals player::usage-error (keys-option "1@-1"))
  (signals player::usage-error (keys-option "@1"))
  (signals player::usage-error (keys-option "f1@1")))

(test view-input-orbits-and-sends-events
  ;; Input records as GLFW-POLL-INPUT returns them; no window needed.
  (with-spec (spec keyed
              (state-variable on boolean false)
              (op switch-on :add on :duration 1)
              (op switch-off :sub on :duration 1)
              (event ev-on :op switch-on)
              (event ev-off :op switch-off))
    (let* ((controller (make-controller (compile-spec spec)))
           (orbit (player.render::make-orbit))
           (viewer (player.render::%make-viewer
                    :controller controller :now 0.5d0
                    :keys '((#\1 . ev-on) (#\2 . ev-off))
                    :renderer (make-instance 'player.render::renderer :orbit orbit))))
      (dolist (input `((:button 0 ,player.render::+glfw-press+ 0) (:cursor 100d0 50d0) (:cursor 110d0 30d0)
                       (:button 0 ,player.render::+glfw-release+ 0) (:cursor 300d0 300d0)
                       (:scroll 0d0 1d0) (:key ,player.render::+glfw-key-right+ ,player.render::+glfw-repeat+ 0)
                       (:char ,(char-code #\1)) (:char ,(char-code #\2)) (:char ,(char-code #\9))))
        (player.render::handle-input viewer input))
      ;; Dragged 10 px right and 20 up, then the right arrow: 5 degrees.
      (is (< (abs (- (player.render::orbit-yaw orbit) (+ -0.1d0 (/ pi 36)))) 1d-9))
      (is (< (abs (- (player.render::orbit-pitch orbit) 0.2d0)) 1d-9))
      (is (< (abs (- (player.render::orbit-distance orbit) 0.9d0)) 1d-9))
      ;; Keys 1 and 2 sent their events, the second queued after the first; 9 is no key.
      (is (equal '("(:event ev-on :time 0.5)" "(:event ev-off :time 1.5)")
                 (remove-if-not (lambda (line) (search "(:event" line)) (trace-of controller)))))))

(test view-keeps-the-state-graph-with-the-current-state
  "With --dot, the viewer rewrites the state graph whenever the state changes,
the current state's node marked: after ev-pick, the holding one."
  (with-window-programs ()
    (let ((path (format nil "/tmp/player-view-~36R.dot" (random (expt 2 40) (make-random-state t)))))
      (unwind-protect
           (multiple-value-bind (out err code)
               (view-command (list (fixture "anim.lisp") "--size" "160x120" "--frames" "100000"
                                   "--keys" "1@0,escape@1.5" "--dot" path))
             (declare (ignore out))
             (is (= 0 code) "exit ~D, stderr: ~A" code err)
             (let ((marked (remove-if-not (lambda (line) (search "penwidth=3" line))
                                          (lines (alexandria:read-file-into-string path)))))
               (is (= 1 (length marked)) "~S" marked)
               (is (search "label=\"holding=true\"" (first marked)))))
        (when (probe-file path) (delete-file path))))))
