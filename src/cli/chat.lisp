;;;; chat.lisp -- `player chat`: Persona's loop on typed text.  Each line the
;;;; user types is matched to an input event, the dialogue takes a transition,
;;;; Player plays the events it sends and Peedy's words are printed; with
;;;; --render the whole conversation's animation is drawn at the end.

(in-package #:player)

(defun choose-dialogue (file)
  "The dialogue of the dialogue FILE: its only one; an error when it has none or several."
  (let ((dialogues (load-dialogue file)))
    (cond ((null dialogues) (error 'player-error-with-message :message (format nil "~A defines no dialogue" file)))
          ((rest dialogues)
           (error 'player-error-with-message
                  :message (format nil "~A defines several dialogues (~{~A~^, ~}); chat takes a file with one"
                                   file (mapcar (lambda (d) (display-name (dialogue-name d))) dialogues))))
          (t (first dialogues)))))

(defun terminal-input-p ()
  "Is standard input a terminal (so a prompt is shown rather than the input echoed)?"
  (let ((answer (ignore-errors (sb-unix:unix-isatty 0))))
    ;; SBCL answers 1 or 0 (or T or NIL, in some versions).
    (and answer (not (eql answer 0)))))

(defun chat-lines (conversation)
  "Play a turn of CONVERSATION for each line of standard input, until its end or
a line `quit`.  From a pipe, each line is echoed as `you: TEXT`."
  (let ((terminal (terminal-input-p)))
    (loop (when terminal (format t "> ") (finish-output))
          (let ((line (read-line *standard-input* nil nil)))
            (when (null line) (return))
            (let ((text (string-trim '(#\Space #\Tab #\Return) line)))
              (cond ((string= text ""))
                    ((member text '("quit" "exit" "bye-bye") :test #'string-equal) (return))
                    (t (unless terminal (format t "you: ~A~%" text))
                       (conversation-hear conversation text)
                       (finish-output))))))))

(define-command "chat" (file &key initial seed memory user render view frames fps size)
    (:summary "talk to the character: typed requests in; input events, transitions, Player's trace and spoken text out"
     :description "Reads one request a line from standard input (a terminal or a pipe) until
its end or `quit`.  For each, prints `input: EVENT slot=\"value\"...` (with
`(not understood)` when no utterance pattern matched), `transition: FROM
--EVENT--> TO` (`(no rule)` when none applied), the trace lines of the Player
events the transition sends, as `run` prints them, and `peedy: \"TEXT\"` for
each thing said.  From a pipe, each request is echoed first as `you: TEXT`."
     :arguments ("DIALOGUE-FILE")
     :options ("--initial"
               ("--seed" :help "the seed of the random source templates and track choices draw from (and of --render's drivers)")
               ("--memory" :string "FILE" "load the user's episodic memory from FILE (when it exists) and save it there at the end")
               ("--user" :string "NAME" "whose memory this conversation adds to" :default "user")
               ("--render" :string "DIR" "at the end, draw the conversation's Player events offscreen into DIR, as render does")
               ("--view" :flag "" "play the conversation live in a window, as view does: each typed line is a request (Escape quits)")
               ("--frames" :positive-integer "N" "with --view, stop after N frames")
               ("--fps" :default 24) "--size")
     :output "the turns on standard output; with --render, DIR/frame-0001.png ... and
        DIR/sheet.png; with --memory, FILE; with --view, a window")
  (when (and frames (not view)) (usage-fail "--frames counts the frames of --view"))
  (let* ((dialogue (choose-dialogue file))
         (spec (or (dialogue-player-spec dialogue)
                   (error 'player-error-with-message
                          :message (format nil "dialogue ~A names no Player spec: give it (:player SPEC)"
                                           (display-name (dialogue-name dialogue))))))
         (initial (or initial (dialogue-player-initial dialogue)))
         (controller (make-controller (compile-spec spec) :initial-state initial
                                                          :presenter (make-trace-presenter :stream *standard-output*)))
         (remembered (if memory (load-memory memory user) (make-memory :user user)))
         (conversation (make-conversation dialogue :seed seed :memory remembered :controller controller
                                                   :presenter (make-text-presenter))))
    (format t "; ~A: ~A talks to ~A (~A); state ~A~%" (file-namestring file) user
            (display-name (dialogue-name dialogue)) (display-name (spec-name spec))
            (display-name (conversation-state conversation)))
    (if view
        (view-conversation conversation spec initial :seed seed :size size :frames frames)
        (chat-lines conversation))
    (format t "; ~D turn~:P; state ~A, mood ~(~A~)~%" (conversation-turns conversation)
            (display-name (conversation-state conversation)) (memory-mood remembered))
    (when memory
      (save-memory remembered memory)
      (format t "; wrote ~A~%" memory))
    (when render
      (render-conversation spec initial (reverse (conversation-player-events conversation))
                           :seed seed :fps fps :size size :out render))))

(defun view-conversation (conversation spec initial &key seed size frames)
  "Play CONVERSATION live in a window on SPEC's body from INITIAL: each line
typed at the terminal is a turn, its Player events sent to the viewer's
(timed) controller at the current playback time."
  (view-spec spec :initial initial :seed seed :size size :frames frames
                  :line-handler (lambda (viewer text)
                                  (setf (conversation-controller conversation) (viewer-controller viewer))
                                  (format t "you: ~A~%" text)
                                  (conversation-hear conversation text)
                                  (finish-output))))

(defun render-conversation (spec initial events &key seed fps size out)
  "Draw EVENTS played on SPEC from INITIAL offscreen into OUT, as `render` does."
  (if (null events)
      (format t "; nothing to render: no Player event was sent~%")
      (let* ((simulation (simulate spec :initial initial :events events :fps fps :seed seed))
             (paths (render-simulation simulation :out out :size size :fps fps))
             (frames (butlast paths)))
        (print-scenario-summary simulation (length frames) fps)
        (format t "; wrote ~A .. ~A~%; wrote ~A~%" (namestring (first frames))
                (file-namestring (car (last frames))) (namestring (car (last paths)))))))
