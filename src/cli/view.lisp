;;;; view.lisp -- `player view`: the controller played live in a window.

(in-package #:player.cli)

(defmethod read-option-value ((type (eql :keys)) text option)
  ;; KEY@SECONDS,... as ((SECONDS . KEY) ...): KEY a character or a control key's name.
  (mapcar (lambda (part)
            (let* ((at (position #\@ part))
                   (name (and at (subseq part 0 at)))
                   (seconds (and at (< at (1- (length part))) (read-cli-value (subseq part (1+ at))))))
              (unless (and at (plusp at) (realp seconds) (>= seconds 0))
                (bad-option-value option part "KEY@SECONDS pairs such as 1@0.5"))
              (cons (float seconds 1d0)
                    (if (= (length name) 1)
                        (char-downcase (char name 0))
                        (or (car (assoc name *view-control-keys* :test #'string-equal))
                            (usage-fail "~A: unknown key ~A (a character, or ~{~(~A~)~^, ~})"
                                        (option-name option) name (mapcar #'car *view-control-keys*)))))))
          (split-list text)))

(defmethod read-option-value ((type (eql :port)) text option)
  ;; A TCP port number.
  (let ((port (read-cli-value text)))
    (unless (typep port '(integer 1 65535))
      (bad-option-value option text "a TCP port number from 1 to 65535"))
    port))

;;;# Stopping on a signal

(defparameter *viewer-stop-signals*
  (list (cons sb-unix:sigterm "SIGTERM") (cons sb-unix:sigint "SIGINT") (cons sb-unix:sighup "SIGHUP"))
  "The signals that close `player view`'s window, which then exits 128 + the
signal's number (143, 130, 129), as a program killed by it would.")

(defun call-with-viewer-stop-signals (function)
  "Call FUNCTION with SIGTERM, SIGINT and SIGHUP asking the viewer to close
\(REQUEST-VIEWER-STOP): the window closes at the next frame and everything is
let go as after Escape.  Then, when one of them came, exit 128 + its number;
otherwise return FUNCTION's values.  The handlers only set a variable: SBCL's
own would unwind (or debug) from wherever the signal lands, a foreign call
into GL included, and leave the process running."
  (clear-viewer-stop-request)
  (let ((previous (loop for (signal) in *viewer-stop-signals*
                        collect (cons signal
                                      (sb-sys:enable-interrupt
                                       signal (lambda (number info context)
                                                (declare (ignore info context))
                                                (request-viewer-stop number)))))))
    (multiple-value-prog1
        (unwind-protect (funcall function)
          (loop for (signal . handler) in previous
                do (sb-sys:enable-interrupt signal (or handler :default))))
      (let ((signal (viewer-stop-request)))
        (when (integerp signal)
          (ignore-errors (finish-output *standard-output*))
          (sb-ext:exit :code (+ 128 signal) :abort t))))))

(defmacro with-viewer-stop-signals (() &body body)
  "Run BODY with the viewer closing on SIGTERM, SIGINT and SIGHUP (CALL-WITH-VIEWER-STOP-SIGNALS)."
  `(call-with-viewer-stop-signals (lambda () ,@body)))

(define-command "view" (file &key spec no-code initial body scripts size seed frames screenshot keys dot
                             cast silent watch swank)
    (:summary "play the controller live in a window"
     :description "Keys from the printed map (or event names typed at the terminal) send
events, space pauses, the arrows and the mouse orbit the camera, the scroll
wheel zooms, Escape or closing the window quits; so do SIGTERM, SIGINT
and SIGHUP, the exit status then 143, 130 or 129.  Speech and sounds play
on the audio device when there is one.  Under xvfb-run -a it runs
without a screen."
     :arguments ("SPEC-FILE")
     :options ("--spec" "--no-code" "--initial" "--body" "--scripts" "--size" "--seed" "--cast" "--silent"
               ("--frames" :positive-integer "N" "stop after N frames")
               ("--screenshot" :string "FILE.png" "save the last frame shown")
               ("--keys" :keys "KEY@SECONDS,..." "press keys at times after the start, e.g. 1@0,space@2.5")
               ("--dot" :string "FILE" "keep the state graph (.dot, .svg or .png, as for `player dot`) in FILE, rewritten with the current state marked whenever it changes")
               ("--watch" :flag "" "read SPEC-FILE, its script library, pose library and skeleton file again whenever they change (one line a save): the character switches to the new definition, keeping its state and time; errors are printed and the window plays on")
               ("--swank" :port "PORT" "start a Swank server on 127.0.0.1, port PORT (Debian's cl-swank), so Emacs/SLIME can connect (M-x slime-connect) and redefine the spec in the running viewer; clients must send the secret in ~/.slime-secret (made, mode 0600, when missing)"))
     :output "a window; the key map and the trace on standard output")
  (when-let (scene (command-cast file spec cast (not no-code)))
    (refuse-scene-option "--dot" dot)
    (refuse-scene-option "--watch" watch)
    (refuse-scene-option "--swank" swank)
    (let ((problem (scripted-keys-problem keys (scene-event-keys scene))))
      (when problem (usage-fail "--keys: ~A" problem)))
    (with-viewer-stop-signals ()
      (view-scene scene :initial initial :body body :scripts scripts :frames frames :screenshot screenshot
                        :size size :seed seed :keys keys))
    (return-from command-view))
  (let* ((spec (choose-spec file spec :allow-code (not no-code)))
         (problem (scripted-keys-problem keys (view-event-keys spec))))
    (when problem (usage-fail "--keys: ~A" problem))
    (when swank
      (format t "; Swank listens on port ~D of 127.0.0.1, admitting only clients that send the secret in ~A (SLIME does): M-x slime-connect RET 127.0.0.1 RET ~D~%"
              swank (sb-ext:native-namestring (nth-value 1 (start-swank swank))) swank)
      (finish-output))
    (with-viewer-stop-signals ()
      (unwind-protect
           (view-spec spec :initial initial :body body :scripts scripts
                           :frames frames :screenshot screenshot :size size
                           :seed seed :keys keys :dot dot :silent silent :watch watch :allow-code (not no-code))
        (when swank (stop-swank swank))))))
