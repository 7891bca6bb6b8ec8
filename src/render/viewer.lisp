;;;; viewer.lisp -- a controller played live in a window (what `player view` runs).
;;;; The wall clock since the first frame, less the time spent paused, is
;;;; the animation time; keys (or event names typed at the terminal) send
;;;; events at that time, and trace lines print when the time reaches them.

(in-package #:player.render)

(defparameter *view-event-keys* "123456789abcdefghijklmnopqrstuvwxyz"
  "The window keys that send events, given to the spec's events in order.")

(defparameter *view-help*
  "; space pauses, arrows or a mouse drag orbit the camera, scroll or +/- zoom, Home resets it, Escape quits"
  "The line printed under the key map.")

(defparameter *view-control-keys*
  `((:space . ,+glfw-key-space+) (:escape . ,+glfw-key-escape+) (:home . ,+glfw-key-home+)
    (:left . ,+glfw-key-left+) (:right . ,+glfw-key-right+) (:up . ,+glfw-key-up+)
    (:down . ,+glfw-key-down+))
  "Keys read by key code, by the names --keys gives them.")

(defparameter *view-frame-time* (/ 1d0 60) "The shortest time a frame takes: the viewer draws at most 60 a second.")

(defstruct (viewer (:constructor %make-viewer))
  "One viewing session: the WINDOW, the CONTROLLER and the PERFORMANCE its
presenter plays, the RENDERER, KEYS (an alist from characters to event names),
scripted key presses still due (SCRIPT, (SECONDS . KEY) by time), the clock
(START, PAUSED-AT, PAUSED-TOTAL, in glfwGetTime seconds), NOW (the current
frame's animation time), the mouse DRAG (NIL, :START, or the last (X . Y)),
trace lines PRINTED so far, the TITLE shown and whether the terminal is still read."
  window controller performance renderer name keys script
  ;; A file the state graph is written to, current state highlighted, and the
  ;; state last written (see WRITE-CURRENT-STATE-GRAPH).
  (dot nil) (dot-state nil)
  ;; Audio clips already handed to the audio device, and whether the lack of
  ;; one has been reported.
  (clips-played (make-hash-table :test #'eq)) (silence-reported nil)
  ;; Live authoring (live-viewer.lisp): work other threads post (an INBOX),
  ;; a FILE-WATCHER and the function that reloads what it reports, the spec
  ;; whose key map was last printed, the last error, shown in the title, and
  ;; the spec file read again whose line is still to be printed.
  (inbox nil) (watcher nil) (reload nil) (spec nil) (message nil) (reloaded nil)
  (start 0d0) (paused-at nil) (paused-total 0d0) (now 0d0) (drag nil) (printed 0) (title "") (terminal t)
  ;; NIL, or a function of the viewer and each line typed at the terminal
  ;; (trimmed, not empty), which then is not read as an event's name: how
  ;; `chat --view` hears sentences.
  (line-handler nil)
  ;; NIL, or a function of the viewer, a GLFW key code and its action (press,
  ;; repeat, release) that takes the key when it returns true: push-to-talk.
  (key-handler nil))

(defun viewer-wall-time (viewer)
  "Seconds since VIEWER's first frame."
  (- (glfw-time) (viewer-start viewer)))

(defun viewer-tick (viewer clock)
  "Set VIEWER-NOW, the animation time of a frame begun at CLOCK (glfwGetTime
seconds): seconds since the start, paused time excluded -- or the first
critical time a script reaches since the last frame, so the viewer shows it
as every other output does (frame-times.lisp).  Everything the frame does
happens at that time."
  (let* ((previous (viewer-now viewer))
         (now (- (or (viewer-paused-at viewer) clock) (viewer-start viewer) (viewer-paused-total viewer)))
         (performance (viewer-performance viewer)))
    (setf (viewer-now viewer)
          (or (and performance (> now previous)
                   (performance-critical-time-between performance previous now))
              now))))

(defun toggle-pause (viewer)
  "Pause VIEWER's clock, or resume it."
  (let ((paused-at (viewer-paused-at viewer)))
    (if paused-at
        (setf (viewer-paused-total viewer) (+ (viewer-paused-total viewer) (- (glfw-time) paused-at))
              (viewer-paused-at viewer) nil)
        (setf (viewer-paused-at viewer) (glfw-time)))))

;;;# Events and the trace

(defgeneric view-send-event (viewer event)
  (:documentation "Send EVENT at the current playback time.  The viewer's controller is timed:
if another event is playing, EVENT's :when-busy policy decides (by default it
waits its turn), so a preempting event cuts the animation live.  A viewer of
several characters (src/cast/) sends to the members EVENT addresses.")
  (:method ((viewer viewer) event)
    (let ((controller (viewer-controller viewer)))
      (send-event controller event :at (max (viewer-now viewer) (controller-time controller))))))

(defgeneric advance-viewer (viewer)
  (:documentation "Bring VIEWER's controllers to the current playback time, and its state graph up to date.")
  (:method ((viewer viewer))
    (advance (viewer-controller viewer) (max (viewer-now viewer) (controller-time (viewer-controller viewer))))
    (write-current-state-graph viewer)))

(defgeneric viewer-scene (viewer time)
  (:documentation "The scene VIEWER draws at TIME.")
  (:method ((viewer viewer) time)
    (performance-frame (viewer-performance viewer) time)))

(defun write-current-state-graph (viewer)
  "When VIEWER has a --dot file and its controller's state changed since it
was last written, write the state graph there with the current state marked."
  (let* ((controller (viewer-controller viewer))
         (state (controller-bits controller)))
    (when (and (viewer-dot viewer) (not (eql state (viewer-dot-state viewer))))
      (write-state-graph-file (controller-machine controller) (viewer-dot viewer) :current state)
      (setf (viewer-dot-state viewer) state))))

(defun trace-line-time (line)
  "When trace LINE happens, or NIL for a :state line (it follows the line before)."
  (unless (eq (first line) :state)
    (let ((plist (cddr line)))
      (or (getf plist :time) (getf plist :start)))))

(defgeneric print-due-trace (viewer &optional time)
  (:documentation "Print the trace lines not yet printed whose time is at most TIME
\(default: now; all when TIME is T)."))

(defun trace-line-due-p (presenter line time)
  "May the viewer print PRESENTER's trace LINE at TIME (T: the end)?  When
its time has come, unless it is a macro-op's line still open: that line gets
its real end when the macro ends, and it and the lines after it wait until
then, as `run` writes them.  At the end every line is due."
  (or (eq time t)
      (let ((at (trace-line-time line)))
        (and (or (null at) (<= at time))
             (not (and (eq (first line) :op) (member line (trace-open-macros presenter) :test #'eq)))))))

(defmethod print-due-trace ((viewer viewer) &optional (time (viewer-now viewer)))
  (let* ((presenter (controller-presenter (viewer-controller viewer)))
         (lines (trace-line-vector presenter))
         (dropped (trace-dropped presenter)))
    ;; VIEWER-PRINTED counts every line ever recorded; a bounded trace forgets
    ;; its oldest ones, which are then skipped.
    (setf (viewer-printed viewer) (max (viewer-printed viewer) dropped))
    ;; The lines due are written as one group, no other thread's line among them.
    (with-output-lock ()
      (loop while (< (- (viewer-printed viewer) dropped) (length lines))
            do (let ((line (aref lines (- (viewer-printed viewer) dropped))))
                 (unless (trace-line-due-p presenter line time)
                   (return))
                 (write-trace-line line)
                 (incf (viewer-printed viewer))))
      (finish-output))))

(defun read-terminal (viewer)
  "Send the event named by a line typed at the terminal, if one is waiting; an
event's key from the map works too.  Never blocks."
  (when (viewer-terminal viewer)
    (let ((line (handler-case (and (listen *standard-input*) (read-line *standard-input* nil :eof))
                  (error () :eof))))
      (cond ((eq line :eof) (setf (viewer-terminal viewer) nil))
            ((null line))
            (t (let* ((text (string-trim '(#\Space #\Tab) line))
                      (key (and (= (length text) 1) (assoc (char-downcase (char text 0)) (viewer-keys viewer)))))
                 (cond ((string= text ""))
                       ((viewer-line-handler viewer) (funcall (viewer-line-handler viewer) viewer text))
                       (key (view-send-event viewer (cdr key)))
                       (t (handler-case (view-send-event viewer text)
                            (unknown-event ()
                              (write-live-line *standard-output* "; no event ~A: type one of the names above~%" text)))))))))))

;;;# The window

(defgeneric view-title (viewer)
  (:documentation "The window title: the spec's name and the controller's state, e.g.
\"peedy -- holding-note=false posture=stand ... last-heard=2.5\"."))

(defmethod view-title ((viewer viewer))
  (let ((controller (viewer-controller viewer)))
    (format nil "~A -- ~{~A~^ ~}~:[~; [paused]~]~@[ [~A]~]" (viewer-name viewer)
            ;; CONTROLLER-STATE lists the values in declaration order.
            (loop for var in (spec-variables (spec-of controller))
                  for (name . value) in (controller-state controller)
                  collect (format nil "~A=~A" (lisp-text name)
                                  (cond ((eq (var-kind var) :boolean) (if value "true" "false"))
                                        ((null value) "-")
                                        (t (lisp-text value)))))
            (viewer-paused-at viewer)
            (viewer-message viewer))))

(defun fit-renderer (viewer)
  "Remake VIEWER's renderer, keeping its orbit, when the window's framebuffer changed size."
  (multiple-value-bind (width height) (glfw-framebuffer-size (viewer-window viewer))
    (let ((renderer (viewer-renderer viewer)))
      (when (and (plusp width) (plusp height)
                 (or (/= width (renderer-width renderer)) (/= height (renderer-height renderer))))
        (let ((orbit (renderer-orbit renderer)))
          (delete-renderer renderer)
          (setf (viewer-renderer viewer) (make-renderer width height :orbit orbit)))))))

(defun draw-view (viewer)
  "Render VIEWER's scene at the current animation time into the window's back buffer."
  (fit-renderer viewer)
  (render-scene (viewer-renderer viewer) (viewer-scene viewer (viewer-now viewer))))

(defgeneric viewer-clips (viewer)
  (:documentation "The audio clips VIEWER's performance has started so far.  A
viewer of several characters (src/cast/) gathers every member's.")
  (:method ((viewer viewer))
    (replay-clips (viewer-performance viewer))))

(defun play-new-clips (viewer)
  "Play the audio clips the performance has started since the last frame, and
silence those cut by now (the music stopped); when the machine cannot play
sound, say so once (the first time something sounds)."
  (stop-cut-clips (viewer-now viewer))
  (dolist (clip (viewer-clips viewer))
    (unless (gethash clip (viewer-clips-played viewer))
      (setf (gethash clip (viewer-clips-played viewer)) t)
      (let ((problem (audio-playback-problem)))
        (cond ((null problem) (play-clip-now clip))
              ((not (viewer-silence-reported viewer))
               (setf (viewer-silence-reported viewer) t)
               (write-live-line *standard-output* "; ~A: playing silently~%" problem)))))))

(defun run-viewer (viewer frames)
  "Play VIEWER until its window closes, FRAMES frames (NIL: no limit) are
shown or REQUEST-VIEWER-STOP asks every viewer to close; return the number
of frames shown."
  (let ((window (viewer-window viewer)))
    (loop for frame from 0
          until (or (glfw-window-closing-p window) (viewer-stop-request) (and frames (>= frame frames)))
          do (let ((started (glfw-time)))
               (when (zerop frame) (setf (viewer-start viewer) started))
               (viewer-tick viewer started)
               (dolist (input (glfw-poll-input)) (handle-input viewer input))
               (serve-live-viewer viewer)
               (play-script-keys viewer)
               (read-terminal viewer)
               (advance-viewer viewer)
               (draw-view viewer)
               (play-new-clips viewer)
               (print-due-trace viewer)
               (let ((title (view-title viewer)))
                 (unless (string= title (viewer-title viewer))
                   (glfw-set-title window (setf (viewer-title viewer) title))))
               (glfw-swap-buffers window)
               (let ((spare (- *view-frame-time* (- (glfw-time) started))))
                 (when (plusp spare) (sleep spare))))
          finally (return frame))))

(defun view-spec (spec &key initial body scripts frames screenshot (size '(640 480)) (seed 0) keys dot silent
                             (terminal t) inbox watch (allow-code t) line-handler key-handler)
  "Open a window and play a controller of SPEC live on its body: INITIAL, BODY,
SCRIPTS and SEED as for SIMULATE; SIZE is (WIDTH HEIGHT) or \"WxH\".  Prints the
key map, then each trace line when the animation time reaches it (the rest at
the end).  Returns after FRAMES frames (NIL: when the window closes or Escape is pressed), writing the last frame to the PNG file SCREENSHOT
if given, and rewriting the state graph into DOT (a .dot, .svg or .png file)
each time the state changes, the current state marked.  Speech and sounds
play on the audio device (through aplay or sox's play); without one the viewer
says once that it plays silently.  With SILENT nothing sounds.  The controller
follows its spec: a redefinition (DEFSPEC again, or with WATCH a change of
the spec's file, read again with ALLOW-CODE as LOAD-SPEC does, or of its
script library) switches it at its next safe point; errors are printed as
\"player: error: ...\" lines and shown in the title, the window playing on.
INBOX, an INBOX, takes functions of the viewer from other threads (see VIEW);
unless TERMINAL, standard input is not read.  LINE-HANDLER, a
function of the viewer and a line, takes the lines typed at the terminal
instead of reading them as event names; KEY-HANDLER, a function of the
viewer, a GLFW key code and its action, takes the keys it returns true for.  KEYS scripts key presses for tests: ((SECONDS . KEY) ...), KEY a
character of the key map, #\+ or #\-, or one of :space :escape :left :right :up :down :home,
pressed SECONDS of wall-clock time after the first frame.  Signals a
RENDER-ERROR when there is no display or GL fails, and the errors of
MAKE-BODY-PRESENTER and MAKE-CONTROLLER; an ARGUMENT-ERROR, before any window
opens, for an argument of the wrong kind."
  (check-body-presenter-arguments 'view-spec spec scripts body seed nil *default-blend-time*)
  (check-argument 'view-spec :initial initial #'initial-state-p *initial-state-phrase*)
  (check-argument 'view-spec :frames frames (lambda (x) (or (null x) (typep x '(integer 1))))
                  "NIL or a positive integer")
  (check-argument 'view-spec :screenshot screenshot (lambda (x) (or (null x) (pathname-designator-p x)))
                  (format nil "NIL or ~A" *path-phrase*))
  (check-argument 'view-spec :inbox inbox (lambda (x) (or (null x) (inbox-p x))) "NIL or an inbox")
  (check-argument 'view-spec :dot dot (lambda (x) (or (null x) (pathname-designator-p x)))
                  (format nil "NIL or ~A" *path-phrase*))
  (check-argument 'view-spec :key-handler key-handler (lambda (x) (or (null x) (functionp x)))
                  "NIL or a function of the viewer, a key code and an action")
  (check-argument 'view-spec :line-handler line-handler (lambda (x) (or (null x) (functionp x)))
                  "NIL or a function of the viewer and a line")
  (check-argument 'view-spec :keys keys
                  (lambda (x) (and (alexandria:proper-list-p x)
                                   (every (lambda (entry) (and (consp entry) (seconds-p (car entry))
                                                               (>= (car entry) 0)))
                                          x)))
                  "a proper list of (seconds . key) with seconds a finite number from 0")
  (let* ((spec (if (spec-p spec) spec (find-spec spec)))
         (presenter (make-body-presenter spec :scripts scripts :body body :seed seed :silent silent))
         (controller (make-controller (compile-spec spec) :initial-state initial :presenter presenter
                                                          :timed t))
         (event-keys (view-event-keys spec)))
    (let ((problem (scripted-keys-problem keys event-keys)))
      (when problem (error 'player-error-with-message :message problem)))
    (show-viewer (lambda (window)
                   (%make-viewer :window window :controller controller :name (lisp-text (spec-name spec))
                                 :dot dot :terminal terminal :spec spec :line-handler line-handler :key-handler key-handler
                                 :performance (presenter-performance presenter) :keys event-keys
                                 :script (sort (copy-list keys) #'< :key #'car)))
                 (lisp-text (spec-name spec)) event-keys :size size :frames frames :screenshot screenshot
                 :terminal terminal :live t :inbox inbox :watch watch :allow-code allow-code)))

(defun show-viewer (make-viewer title event-keys &key size frames screenshot (terminal t)
                                                      live inbox watch (allow-code t))
  "Open a window called TITLE of SIZE, make the viewer by calling MAKE-VIEWER
with it, print the key map EVENT-KEYS and play the viewer as VIEW-SPEC
describes (FRAMES, SCREENSHOT, TERMINAL).  With LIVE its controller follows
its spec (START-LIVE-VIEWER: INBOX, WATCH, ALLOW-CODE)."
  (multiple-value-bind (width height) (image-size size)
    (with-glfw-window (window width height title)
      (let ((viewer (funcall make-viewer window)))
        (multiple-value-bind (fb-width fb-height) (glfw-framebuffer-size window)
          (setf (viewer-renderer viewer) (make-renderer fb-width fb-height :orbit (make-orbit))))
        (unwind-protect
             (progn
               (print-key-map event-keys terminal)
               (when live (start-live-viewer viewer :inbox inbox :watch watch :allow-code allow-code))
               (let ((shown (with-live-errors-reported (viewer) (run-viewer viewer frames))))
                 (print-due-trace viewer t)
                 (write-live-line *standard-output* "; ~D frames in ~,1F s~%" shown (viewer-wall-time viewer)))
               (when screenshot
                 (let ((renderer (viewer-renderer viewer)))
                   ;; The last frame shown has been swapped away: draw it again to read it.
                   (draw-view viewer)
                   (write-png screenshot (renderer-width renderer) (renderer-height renderer)
                              (renderer-pixels renderer))
                   (write-live-line *standard-output* "; wrote ~A~%" screenshot))))
          (when live (stop-live-viewer viewer))
          (delete-renderer (viewer-renderer viewer)))))))
