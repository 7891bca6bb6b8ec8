;;;; chat.lisp -- `player chat`: Persona's loop.  Each line the user types (or
;;;; each WAV file pocketsphinx hears, with --wav) is matched to an input event,
;;;; the dialogue takes a transition, Player plays the events it sends and
;;;; Peedy's words are printed; with --render the conversation is played on
;;;; his body as it goes, his replies spoken with the beak in sync, and drawn
;;;; at the end.

(in-package #:player.cli)

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
  ;; SB-POSIX has no isatty (SBCL 2.2), so it is called through CFFI: 1 or 0.
  (let ((answer (ignore-errors (cffi:foreign-funcall "isatty" :int 0 :int))))
    (and answer (not (eql answer 0)))))

;;;; Turns from typed lines

(defun hear-turn (conversation text explain)
  "Play the turn of CONVERSATION on TEXT (a string or NIL); with EXPLAIN, print
the matcher's best readings of it first."
  (when explain
    (explain-utterance (conversation-dialogue conversation) (or text "")))
  (conversation-hear conversation text))

(defun chat-lines (conversation &key speaker explain)
  "Play a turn of CONVERSATION for each line of standard input, until its end or
a line `quit`.  From a pipe, each line is echoed as `you: TEXT`.  With
SPEAKER, each turn waits until the speech before it has ended; with EXPLAIN,
the readings of each line are printed before its turn."
  (let ((terminal (terminal-input-p)))
    (loop (when terminal (format t "> ") (finish-output))
          (let ((line (read-line *standard-input* nil nil)))
            (when (null line) (return))
            (let ((text (string-trim '(#\Space #\Tab #\Return) line)))
              (cond ((string= text ""))
                    ((member text '("quit" "exit" "bye-bye") :test #'string-equal) (return))
                    (t (unless terminal (format t "you: ~A~%" text))
                       (when speaker (speaker-wait speaker (conversation-controller conversation)))
                       (hear-turn conversation text explain)
                       (finish-output))))))))

;;;; Turns from spoken requests

(defun check-recogniser ()
  "Signal SPEECH-UNAVAILABLE, naming the Debian package, unless pocketsphinx and its English model are installed."
  (load-pocketsphinx-library)
  (pocketsphinx-model-files)
  t)

(defun print-heard (text score sentence)
  "Print what the recogniser heard: `heard: \"SENTENCE\" (score S)`, with
`, rejected` when the score is too low (TEXT NIL), or `heard: nothing`."
  (if sentence
      (format t "heard: ~S (score ~,1F~:[, rejected~;~])~%" sentence score text)
      (format t "heard: nothing~%")))

(defun chat-wavs (conversation requests grammar &key speaker explain)
  "Play a turn of CONVERSATION for each of REQUESTS, a list of (PATH . SOUND):
pocketsphinx hears the SOUND against GRAMMAR (JSGF text), `heard: \"...\"
\(score S)` (or `heard: nothing`) is printed and the sentence heard is the
turn's text; a rejected one is not understood.  With SPEAKER, the request
goes on the audio track before Peedy answers; with EXPLAIN, the readings of
what was heard are printed before its turn."
  (loop for (path . sound) in requests
        do (multiple-value-bind (heard score sentence) (recognize-sound sound :grammar grammar)
             (print-heard heard score sentence)
             (when speaker
               (speaker-wait speaker (conversation-controller conversation))
               (speaker-listen speaker sound (file-namestring path) (conversation-controller conversation)))
             (hear-turn conversation heard explain)
             (finish-output))))

;;;; Turns from a microphone

(defun chat-listen (conversation grammar &key device seconds explain)
  "Play a turn of CONVERSATION for each request heard from the ALSA DEVICE
(arecord), found by pocketsphinx's voice-activity detection and heard
against GRAMMAR, printed as chat-wavs prints them, until the recording ends
or SECONDS of sound have been heard.  EXPLAIN as for chat-wavs."
  (let ((capture (open-capture :device (or device *capture-device*))))
    (format t "; listening to ~A~@[ for ~D s~]~%" (or device *capture-device*) seconds)
    (finish-output)
    (unwind-protect
         (listen-for-requests capture grammar
                              (lambda (text score sentence heard-at)
                                (declare (ignore heard-at))
                                (print-heard text score sentence)
                                (hear-turn conversation text explain)
                                (finish-output))
                              :seconds seconds)
      (close-capture capture))))

;;;; Push-to-talk in the viewer

(defparameter *longest-push* 10
  "The most seconds a held key records: what is said after is not kept.")

(defun record-while (capture recording)
  "Read CAPTURE into a list of sample pieces, newest first, while
\(CAR RECORDING) is true and less than *LONGEST-PUSH* seconds are kept;
return the pieces."
  (let ((pieces '()) (kept 0) (limit (* *longest-push* 16000)))
    (loop while (and (car recording) (< kept limit))
          do (let* ((piece (make-array 1024 :element-type '(signed-byte 16)))
                    (count (read-capture capture piece)))
               (when (zerop count) (return))
               (push (subseq piece 0 count) pieces)
               (incf kept count)))
    pieces))

(defun make-push-to-talk (conversation grammar &key device explain (turn #'hear-turn))
  "A key handler for the viewer: holding Enter records from the ALSA DEVICE
\(a thread reads it), letting go hears what was said against GRAMMAR and
plays it as a turn of CONVERSATION (TURN, a function of the conversation,
the text and EXPLAIN), printing `heard:` as chat-wavs does."
  (let ((recording nil) (capture nil) (thread nil))
    (lambda (viewer code action)
      (when (= code +glfw-key-enter+)
        (cond ((and (= action +glfw-press+) (null capture))
               (setf capture (open-capture :device (or device *capture-device*))
                     recording (list t))
               (let ((capture capture) (recording recording))
                 (setf thread (bt:make-thread (lambda () (record-while capture recording)) :name "push-to-talk")))
               (format t "; listening (let go of Enter to stop)~%"))
              ((and (= action +glfw-release+) capture)
               (setf (car recording) nil)
               (let ((pieces (bt:join-thread thread)))
                 (close-capture (shiftf capture nil))
                 (multiple-value-bind (text score sentence)
                     (recognize-sound (make-sound (apply #'concatenate '(simple-array (signed-byte 16) (*)) (reverse pieces))
                                                  16000)
                                      :grammar grammar)
                   (print-heard text score sentence)
                   (when viewer (setf (conversation-controller conversation) (viewer-controller viewer)))
                   (funcall turn conversation text explain)))
               (finish-output)))
        t))))

;;;; Speech when rendering

(defun speech-available-or-note ()
  "Can Peedy speak (libespeak-ng installed)?  When not, print one note saying
so: the conversation is then drawn or viewed silently."
  (handler-case (progn (ensure-espeak) t)
    (speech-unavailable (condition)
      (format t "; no speech: ~A~%" (condition-line condition))
      nil)))

(define-command "chat" (file &key no-code initial seed memory user wav listen device seconds explain render video silent view frames fps size)
    (:summary "talk to the character: typed or spoken requests in; input events, transitions, Player's trace and spoken text out"
     :description "Reads one request a line from standard input (a terminal or a pipe) until
its end or `quit`, or with --wav hears each WAV file with pocketsphinx
against the JSGF grammar made from the dialogue's utterances, printing
`heard: \"SENTENCE\" (score S)` (or `heard: nothing`, which is not
understood), or with --listen hears the requests said into a microphone,
one a turn, as they come (arecord, Debian alsa-utils; pocketsphinx's
voice-activity detection finds where each ends).  The score is how much
worse the sentence fits the sound than English phones do, per 10 ms frame;
a sentence scoring below the rejection margin, or whose phones would each
have to last too long, is `, rejected` and not understood: speech outside
the grammar is never a command.  For
each request, prints `input: EVENT slot=\"value\"...` (with `(not
understood)` when no utterance pattern matched), `transition: FROM --EVENT-->
TO` (`(no rule)` when none applied), the trace lines of the Player events the
transition sends, as `run` prints them, and `peedy: \"TEXT\"` for each thing
said.  From a pipe, each request is echoed first as `you: TEXT`.  With
--explain, each request's best readings come first, one a line, as
`explain: SCORE EVENT slot=\"value\"... (WHY)`: how the matcher scored it
against the dialogue's utterance patterns, and the least score understood.  With
--render, the conversation is played on Peedy's body as it goes: each reply
is spoken by espeak-ng at the time he says it, his beak in sync, the next
turn starting once he has finished; the requests heard from --wav are on the
track too.  With --view he says his replies at once, as they come.  Without
libespeak-ng it is drawn or viewed silently, after a note."
     :arguments ("DIALOGUE-FILE")
     :options (("--no-code" :help "refuse a dialogue whose Player spec holds :code or :c++, so an untrusted dialogue runs no code")
               "--initial"
               ("--seed" :help "the seed of the random source templates and track choices draw from (and of --render's drivers)")
               ("--memory" :string "FILE" "load the user's episodic memory from FILE (when it exists) and save it there at the end")
               ("--user" :string "NAME" "whose memory this conversation adds to" :default "user")
               ("--wav" :names "FILE.wav,..." "instead of standard input, hear these WAV files, a turn each, in order (pocketsphinx, Debian pocketsphinx and pocketsphinx-en-us)")
               ("--listen" :flag "" "instead of standard input, hear requests from a microphone (ALSA, through arecord of Debian alsa-utils) as they are said; with --view, what is said while Enter is held in the window (push-to-talk)")
               ("--device" :string "NAME" "with --listen, the ALSA device to record from" :default-text "default")
               ("--seconds" :positive-integer "N" "with --listen, stop after N seconds of sound")
               ("--explain" :flag "" "before each turn, print the best readings of the request, their scores and why")
               ("--render" :string "DIR" "draw the conversation offscreen into DIR at the end, as render does, Peedy's replies in DIR/speech.wav")
               ("--video" :string "FILE.mp4" "with --render, also encode the frames as a video with the sound (ffmpeg)")
               ("--silent" :help "with --render or --view, Peedy says nothing aloud and his beak stays still (espeak-ng is then not needed)")
               ("--view" :flag "" "play the conversation live in a window, as view does: each typed line is a request (Escape quits)")
               ("--frames" :positive-integer "N" "with --view, stop after N frames")
               ("--fps" :default 24) "--size")
     :output "the turns on standard output; with --render, DIR/frame-0001.png ...,
        DIR/sheet.png and DIR/speech.wav (and the --video file); with --memory,
        FILE; with --view, a window")
  (when (and frames (not view)) (usage-fail "--frames counts the frames of --view"))
  (when (and video (not render)) (usage-fail "--video needs --render DIR, where its frames go"))
  (when (and silent (not (or render view)))
    (usage-fail "--silent silences --render or --view; without them nothing is spoken aloud"))
  (when (and view (or wav render))
    (usage-fail "--view plays typed lines live; it takes neither --wav nor --render"))
  (when (and wav listen) (usage-fail "--wav and --listen are two sources of requests: give one"))
  (when (and (or seconds device) (not listen))
    (usage-fail "--device and --seconds say how to --listen"))
  (when video (find-ffmpeg))
  (with-escaped-output ()
    (chat-session file :no-code no-code :initial initial :seed seed :memory memory :user user :wav wav
                       :listen listen :device device :seconds seconds :explain explain :render render :video video :silent silent :view view
                       :frames frames :fps fps :size size)))

(defun chat-session (file &key no-code initial seed memory user wav listen device seconds explain render video silent view frames fps size)
  "The work of `player chat` once its options are checked (see COMMAND-CHAT)."
  (let* ((dialogue (choose-dialogue file))
         (spec (or (dialogue-player-spec dialogue)
                   (error 'player-error-with-message
                          :message (format nil "dialogue ~A names no Player spec: give it (:player SPEC)"
                                           (display-name (dialogue-name dialogue))))))
         (initial (progn (when no-code (refuse-code spec))
                         (or initial (dialogue-player-initial dialogue))))
         ;; Every WAV read and the recogniser found before the first turn: a bad file stops nothing half-done.
         (requests (mapcar (lambda (path) (cons path (read-request-wav path))) wav))
         (grammar (and (or wav listen) (check-recogniser) (dialogue-jsgf dialogue)))
         (silent (and (or render view) (or silent (not (speech-available-or-note)))))
         ;; Rendering plays the conversation on a body as it goes, so speech is timed by its clock.
         (presenter (if render
                        (make-body-presenter spec :seed seed :stream *standard-output* :silent silent)
                        (make-trace-presenter :stream *standard-output*)))
         (controller (make-controller (compile-spec spec) :initial-state initial :presenter presenter))
         (speaker (and render (not silent) (make-speaker (presenter-performance presenter))))
         (remembered (if memory (load-memory memory user) (make-memory :user user)))
         (conversation (make-conversation dialogue :seed seed :memory remembered :controller controller
                                                   :presenter (make-text-presenter))))
    (format t "; ~A: ~A talks to ~A (~A); state ~A~%" (file-namestring file) user
            (display-name (dialogue-name dialogue)) (display-name (spec-name spec))
            (display-name (conversation-state conversation)))
    (with-speaker (speaker)
      (cond (view (view-conversation conversation spec initial :seed seed :size size :frames frames
                                                                :silent silent :explain explain
                                                                :push-to-talk (and listen (make-push-to-talk conversation grammar :device device :explain explain))))
            (wav (chat-wavs conversation requests grammar :speaker speaker :explain explain))
            (listen (chat-listen conversation grammar :device device :seconds seconds :explain explain))
            (t (chat-lines conversation :speaker speaker :explain explain))))
    (format t "; ~D turn~:P; state ~A, mood ~(~A~)~%" (conversation-turns conversation)
            (display-name (conversation-state conversation)) (memory-mood remembered))
    (when memory
      (save-memory remembered memory)
      (format t "; wrote ~A~%" memory))
    (when render
      (render-conversation controller speaker :fps fps :size size :out render :video video))))

(defun view-conversation (conversation spec initial &key seed size frames silent explain push-to-talk)
  "Play CONVERSATION live in a window on SPEC's body from INITIAL: each line
typed at the terminal is a turn, its Player events sent to the viewer's
(timed) controller at the current playback time.  Unless SILENT, Peedy says
his replies at once, the beak moving, through the viewer's sound.  EXPLAIN
prints each line's readings first.  PUSH-TO-TALK, a key handler from
MAKE-PUSH-TO-TALK, hears what is said while Enter is held."
  (let ((speaker nil))
    (view-spec spec :initial initial :seed seed :size size :frames frames :silent silent
                    :key-handler push-to-talk
                    :line-handler (lambda (viewer text)
                                    (setf (conversation-controller conversation) (viewer-controller viewer))
                                    (unless (or silent speaker)
                                      (setf speaker (make-speaker (viewer-performance viewer))))
                                    (format t "you: ~A~%" text)
                                    (with-speaker (speaker)
                                      (hear-turn conversation text explain))
                                    (finish-output)))))

(defun render-conversation (controller speaker &key fps size out video)
  "Draw what CONTROLLER's body presenter played in the conversation offscreen
into OUT, as `render` does, to the end of the last Player event or of what
SPEAKER (or NIL) said, whichever is later; VIDEO as for RENDER-SIMULATION."
  (let ((end (max (controller-clock controller) (if speaker (speaker-end speaker) 0d0))))
    (if (zerop end)
        (format t "; nothing to render: no Player event was sent and nothing was said~%")
        (let* ((simulation (controller-simulation controller :fps fps :end end))
               (paths (render-simulation simulation :out out :size size :fps fps :video video))
               (frames (remove-if-not #'frame-file-p paths)))
          (print-scenario-summary simulation (length frames) fps)
          (format t "; wrote ~A .. ~A~%" (namestring (first frames)) (file-namestring (car (last frames))))
          (dolist (path (remove-if #'frame-file-p paths))
            (format t "; wrote ~A~%" (namestring path)))))))
