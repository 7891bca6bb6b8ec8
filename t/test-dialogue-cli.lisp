;;;; test-dialogue-cli.lisp -- `bin/player chat` as a user runs it: a piped
;;;; conversation, its memory file, and its errors.

(in-package #:player-tests)

(def-suite* dialogue-cli :in player-tests)

(defun player-command-with-input (input &rest arguments)
  "Run bin/player with ARGUMENTS and INPUT (a string) on its standard input;
return (VALUES STDOUT STDERR EXIT-CODE)."
  (ensure-player-core)
  (with-input-from-string (in input)
    (let* ((out (make-string-output-stream))
           (err (make-string-output-stream))
           (process (sb-ext:run-program (namestring (checkout-file "bin/player")) arguments
                                        :input in :output out :error err :search nil
                                        :directory (namestring *root*))))
      (values (get-output-stream-string out) (get-output-stream-string err)
              (sb-ext:process-exit-code process)))))

(defun chat-lines-starting (prefix text)
  "The lines of TEXT that start with PREFIX."
  (remove-if-not (lambda (line) (alexandria:starts-with-subseq prefix line)) (lines text)))

(test chat-plays-a-piped-conversation
  (multiple-value-bind (out err code)
      (player-command-with-input (format nil "hello~%have you got anything by bonnie raitt~%sure~%who wrote that~%~%yes~%blah~%quit~%thanks~%")
                                 "chat" "specs/peedy-dialogue.lisp" "--seed" "2")
    (is (= 0 code))
    (is (string= "" err))
    (is (equal '("transition: stIdle --evHello--> stAttending"
                 "transition: stAttending --evHaveYouGot--> stGotCD"
                 "transition: stGotCD --evOK--> stSuggested"
                 "transition: stSuggested --evWhoWroteTrack--> stSuggested"
                 "transition: stSuggested --evOK--> stPlaying"
                 "transition: stPlaying --evBadSpeech--> stPlaying")
               (chat-lines-starting "transition: " out)))
    (is (equal '("input: evHello" "input: evHaveYouGot artist=\"Bonnie Raitt\"" "input: evOK"
                 "input: evWhoWroteTrack" "input: evOK" "input: evBadSpeech (not understood)")
               (chat-lines-starting "input: " out)))
    (is (equal "you: have you got anything by bonnie raitt" (second (chat-lines-starting "you: " out))))
    (is (equal "peedy: \"Bonnie Raitt\"" (fourth (chat-lines-starting "peedy: " out))))
    ;; Player's trace of the events the transitions sent.
    (is (member "(:event ev-search :time 5.5)" (lines out) :test #'string=))
    (is (member "(:op search :script stream :start 7 :end 10)" (lines out) :test #'string=))
    (is (equal "; 6 turns; state stPlaying, mood happy" (car (last (lines out)))))))

(test chat-keeps-episodic-memory-in-a-file
  (uiop:with-temporary-file (:pathname memory :type "lisp" :keep nil)
    (delete-file memory)
    (flet ((chat () (player-command-with-input (format nil "what do you have by madonna~%")
                                               "chat" "specs/peedy-dialogue.lisp" "--memory" (namestring memory)
                                               "--user" "carol")))
      (multiple-value-bind (out err code) (chat)
        (is (= 0 code) "~A" err)
        (is (not (search "again?" out))))
      (multiple-value-bind (out err code) (chat)
        (is (= 0 code) "~A" err)
        (is (equal '("peedy: \"Madonna again? I still have Summer Radio, would you like to hear something from that?\"")
                   (chat-lines-starting "peedy: " out))))
      (is (= 2 (memory-conversations (load-memory memory "carol")))))))

(test chat-errors-are-one-line
  (check-cli-error 1 "bad-dialogue.lisp:8: on stA: (do ev-nope): ev-nope is neither an animation of the dialogue nor an event of Player spec mini"
                   "chat" (fixture "bad-dialogue.lisp"))
  (check-cli-error 1 "cannot open dialogue file nowhere.lisp: no such file" "chat" "nowhere.lisp")
  (check-cli-error 2 "chat needs a DIALOGUE-FILE" "chat"))

(test chat-views-the-conversation-live
  ;; Under Xvfb: typed lines are turns, played in the window as they come.
  (with-window-programs ()
    (ensure-player-core)
    (let* ((out (make-string-output-stream))
           (err (make-string-output-stream))
           (process (sb-ext:run-program "xvfb-run" (list "-a" (namestring (checkout-file "bin/player"))
                                                         "chat" "specs/peedy-dialogue.lisp" "--view"
                                                         "--frames" "12" "--size" "160x120")
                                        :search t :output out :error err
                                        :input (make-string-input-stream (format nil "hello~%have you got anything by madonna~%"))
                                        :directory (namestring *root*)))
           (text (get-output-stream-string out)))
      (is (= 0 (sb-ext:process-exit-code process)) "~A" (get-output-stream-string err))
      (is (equal '("transition: stIdle --evHello--> stAttending" "transition: stAttending --evHaveYouGot--> stGotCD")
                 (chat-lines-starting "transition: " text)))
      (is (member "(:event ev-hello :time 0)" (lines text) :test #'string=))
      ;; Peedy answers at once; his search waits its turn on the timeline, past these 12 frames.
      (is (search "Summer Radio" (second (chat-lines-starting "peedy: " text)))))))

(test chat-frames-need-view
  (check-cli-error 2 "--frames counts the frames of --view" "chat" "specs/peedy-dialogue.lisp" "--frames" "3"))
