;;;; test-dialogue.lisp -- Peedy's jukebox dialogue (specs/peedy-dialogue.lisp):
;;;; every transition taken, Figure 9's cascade, anaphora, episodic memory
;;;; saved and loaded, the emotional state, the matcher and the JSGF grammar.

(in-package #:player-tests)

(def-suite* dialogue :in player-tests)

(defun jukebox ()
  "Peedy's jukebox dialogue, loaded from specs/."
  (first (load-dialogue (checkout-file "specs/peedy-dialogue.lisp"))))

(defun jukebox-conversation (&key (seed 0) memory (controller t))
  "A conversation with the jukebox; with CONTROLLER, driving Peedy's Player
controller from the dialogue's initial state, its trace kept."
  (let ((dialogue (jukebox)))
    (make-conversation dialogue :seed seed :memory memory
                                :controller (and controller
                                                 (make-controller (compile-spec (dialogue-player-spec dialogue))
                                                                  :initial-state (dialogue-player-initial dialogue))))))

(defvar *taken-transitions* nil
  "While a test counts them: the forms of the transitions taken.")

(defun turn! (conversation input from to events &optional utterance)
  "Play INPUT (a sentence, or (EVENT . SLOTS)) and check the turn went FROM
-> TO (state names) sending the Player EVENTS; with UTTERANCE, that Peedy said
it.  Returns the turn."
  (let ((turn (if (stringp input)
                  (conversation-hear conversation input)
                  (conversation-input conversation (car input) :slots (cdr input)))))
    (is (string-equal from (symbol-name (turn-from turn))) "~S: from ~A, not ~A" input (turn-from turn) from)
    (is (string-equal to (symbol-name (turn-to turn))) "~S: to ~A, not ~A" input (turn-to turn) to)
    (is (equal events (mapcar #'string-downcase (mapcar #'symbol-name (turn-events turn))))
        "~S: events ~S, not ~S" input (turn-events turn) events)
    (when utterance
      (is (equal (list utterance) (turn-utterances turn)) "~S: said ~S, not ~S" input (turn-utterances turn) utterance))
    (when (player.dialogue::turn-transition turn)
      (push (player.dialogue::transition-form (player.dialogue::turn-transition turn)) *taken-transitions*))
    turn))

(defun no-failures-p (conversation)
  "Did every Player event the conversation sent reach its goals?"
  (notany (lambda (line) (search "(:fail" line)) (trace-of (conversation-controller conversation))))

(test every-jukebox-transition-is-taken
  (let ((*taken-transitions* '()))
    ;; Figure 7's path, anaphora, refusals.
    (let ((c (jukebox-conversation)))
      (turn! c "hello" "stIdle" "stAttending" '("ev-hello") "Hi! What would you like to hear?")
      (turn! c "who wrote that" "stAttending" "stAttending" '("ev-no") "I don't know.")
      (turn! c "have you got anything by bonnie raitt" "stAttending" "stGotCD" '("ev-search"))
      (turn! c "no thanks" "stGotCD" "stAttending" '("ev-confirm") "OK, maybe later.")
      (turn! c "what do you have by bonnie raitt" "stAttending" "stGotCD" '("ev-search"))
      (turn! c "sure" "stGotCD" "stSuggested" '("ev-think"))
      (turn! c "no" "stSuggested" "stSuggested" '("ev-think"))
      (turn! c "who wrote that" "stSuggested" "stSuggested" '("ev-point") "Bonnie Raitt")
      (turn! c "ok" "stSuggested" "stPlaying" '("ev-found"))
      (turn! c "thank you" "stPlaying" "stPlaying" '("ev-thanks"))
      (turn! c "stop the music" "stPlaying" "stAttending" '("ev-stop") "OK, the music is off.")
      (turn! c "stop" "stAttending" "stAttending" '("ev-no") "Nothing is playing.")
      (turn! c "yes" "stAttending" "stAttending" '("ev-think") "What would you like me to play?")
      (turn! c "no" "stAttending" "stAttending" '("ev-confirm") "What would you like me to play?")
      (turn! c "mumble" "stAttending" "stAttending" '("ev-bad-speech") "Huh?")
      (turn! c "mumble mumble" "stAttending" "stAttending" '("ev-bad-speech") "Sorry, could you repeat that?")
      (turn! c "play something by pearl jam next" "stAttending" "stPlaying" '("ev-search" "ev-found"))
      (turn! c "thanks" "stPlaying" "stPlaying" '("ev-thanks"))
      (turn! c "stop" "stPlaying" "stAttending" '("ev-stop"))
      (turn! c "thanks" "stAttending" "stIdle" '("ev-thanks"))
      (is (no-failures-p c)))
    ;; Artists the catalogue lacks can only come from a recogniser's slots.
    (let ((c (jukebox-conversation)))
      (turn! c '(evHaveYouGot (artist . "Frank Zappa")) "stIdle" "stAttending" '("ev-search" "ev-not-found"))
      (turn! c '(evPlayArtist (artist . "Frank Zappa")) "stAttending" "stAttending" '("ev-search" "ev-not-found"))
      (turn! c "have you got anything by madonna" "stAttending" "stGotCD" '("ev-search"))
      (turn! c "have you got anything by madonna" "stGotCD" "stGotCD" '("ev-search")
             "Madonna again? I still have Summer Radio, would you like to hear something from that?")
      (is (no-failures-p c)))
    ;; Tracks by title, and requests queued while one plays.
    (let ((c (jukebox-conversation)))
      (turn! c "play the sunken cathedral" "stIdle" "stPlaying" '("ev-search" "ev-found"))
      (turn! c "play something by madonna after that" "stPlaying" "stPlaying" '("ev-search"))
      (turn! c "play angel from montgomery next" "stPlaying" "stPlaying" '("ev-search"))
      (turn! c '(evTrackEnded) "stPlaying" "stPlaying" '("ev-found"))
      (turn! c '(evTrackEnded) "stPlaying" "stPlaying" '("ev-found"))
      (turn! c '(evTrackEnded) "stPlaying" "stAttending" '() "That was the last track.")
      (turn! c '(evPlayTrack (title . "Zappa Plays Zappa")) "stAttending" "stAttending" '("ev-search" "ev-not-found"))
      (is (no-failures-p c)))
    (let* ((all (player.dialogue::dialogue-transitions (jukebox)))
           (missed (remove-if (lambda (transition)
                                (find (player.dialogue::transition-form transition) *taken-transitions* :test #'equal))
                              all)))
      (is (= 26 (length all)))
      (is (null missed) "transitions never taken: ~S" (mapcar #'player.dialogue::transition-form missed)))))

(test figure-7-sends-pe-pick-track-gen-tracks-do-select-say
  ;; stGotCD + evOK: pePickTrack (ev-think), genTracks, doSelect, Say.
  (let ((c (jukebox-conversation)))
    (conversation-hear c "have you got anything by bonnie raitt")
    (let* ((turn (conversation-hear c "sure"))
           (track (context-value c "track"))
           (tracks (context-value c "tracks")))
      (is (equal '(ev-think) (mapcar (lambda (e) (intern (symbol-name e) :player-tests)) (turn-events turn))))
      (is (= 3 (length tracks)))
      (is (member track tracks))
      (is (eq track (context-value c "lastRef")))
      (is (member (first (turn-utterances turn))
                  (list (format nil "How about ~A?" (player.dialogue::track-title track))
                        (format nil "Would you like to hear ~A?" (player.dialogue::track-title track)))
                  :test #'string=)))))

(test template-cascade-gives-equal-shares
  ;; Figure 9: p = 0.25, 0.333, 0.5, 1 makes four equally likely templates.
  (let* ((c (jukebox-conversation :seed 7 :controller nil))
         (counts (make-array 5 :initial-element 0))
         (draws 10000))
    (dotimes (i draws)
      (incf (aref counts (player.dialogue::template-index (choose-template c 'haveCD)))))
    (loop for index from 1 to 4
          do (is (< (abs (- (/ (aref counts index) draws) 1/4)) 0.02)
                 "template ~D drawn ~D times in ~D" index (aref counts index) draws))
    ;; The same seed draws the same sequence.
    (let ((a (jukebox-conversation :seed 3 :controller nil))
          (b (jukebox-conversation :seed 3 :controller nil)))
      (is (equal (loop repeat 50 collect (player.dialogue::template-index (choose-template a 'haveCD)))
                 (loop repeat 50 collect (player.dialogue::template-index (choose-template b 'haveCD))))))))

(test template-expansion-substitutes-context-variables
  (let ((c (jukebox-conversation :controller nil)))
    (conversation-hear c "have you got anything by bonnie raitt")
    (is (equal '("I have The Bonnie Raitt Collection from 1990."
                 "I've got The Bonnie Raitt Collection."
                 "I've got The Bonnie Raitt Collection, would you like to hear something from that?"
                 "I have The Bonnie Raitt Collection from 1990, would you like to hear something from that?")
               (mapcar (lambda (template) (expand-template template c))
                       (player.dialogue::dialogue-category-templates (jukebox) 'haveCD))))))

(test a-template-limited-to-once-per-conversation-is-said-once
  ;; "crank it up!" (p 0.25, :limit :conversation): over many plays, once.
  (let ((c (jukebox-conversation :seed 1 :controller nil)))
    (let ((cranks (loop repeat 40
                        for turn = (conversation-hear c "play something by madonna")
                        count (search "Crank it up" (first (turn-utterances turn))))))
      (is (= 1 cranks)))
    ;; A new conversation with the same memory may say it again.
    (let ((again (make-conversation (jukebox) :seed 1 :memory (conversation-memory c))))
      (is (= 1 (loop repeat 40
                     count (search "Crank it up"
                                   (first (turn-utterances (conversation-hear again "play madonna"))))))))))

(test who-wrote-that-resolves-the-last-referenced-object
  (let ((c (jukebox-conversation)))
    ;; The last referenced object is the CD: its artist.
    (conversation-hear c "have you got anything by joe cocker")
    (is (equal '("Joe Cocker") (turn-utterances (conversation-hear c "who wrote that"))))
    ;; Then a track Peedy suggests: its composer.
    (conversation-hear c "sure")
    (let ((track (context-value c "lastRef")))
      (is (typep track 'player.dialogue::track))
      (is (equal (list (player.dialogue::track-composer track)) (turn-utterances (conversation-hear c "who wrote that")))))
    ;; A title named: that track, which becomes the object "that" refers to.
    (is (equal '("Bo Diddley") (turn-utterances (conversation-hear c "who wrote before you accuse me"))))
    (is (equal '("Bo Diddley") (turn-utterances (conversation-hear c "who wrote that"))))
    (is (equal '("John Lennon")
               (turn-utterances (conversation-hear c "who wrote a little help from my friends"))))))

(test memory-survives-save-and-load
  (uiop:with-temporary-file (:pathname path :type "lisp" :keep nil)
    (let ((c (jukebox-conversation :controller nil)))
      (conversation-hear c "have you got anything by madonna")
      (conversation-hear c "mumble")
      (conversation-hear c "mumble")
      (save-memory (conversation-memory c) path)
      ;; Another user's memory in the same file leaves alice's alone.
      (let ((bob (make-memory :user "bob")))
        (setf (memory-mood bob) :happy)
        (save-memory bob path))
      (let ((loaded (load-memory path "user"))
            (original (conversation-memory c)))
        (is (eq :sad (memory-mood loaded)))
        (is (= 1 (memory-conversations loaded)))
        (is (= 6 (length (memory-log loaded))))
        (is (equalp (memory-log original) (memory-log loaded)))
        (is (eq :happy (memory-mood (load-memory path "bob"))))
        (is (eq :neutral (memory-mood (load-memory path "nobody"))))
        ;; The loaded memory remembers the request: a second conversation says "again".
        (let ((later (make-conversation (jukebox) :memory loaded)))
          (is (eql 0 (search "Madonna again?"
                             (first (turn-utterances (conversation-hear later "have you got anything by madonna"))))))
          (is (= 2 (memory-conversations loaded))))))))

(test a-memory-file-is-data
  (uiop:with-temporary-file (:pathname path :stream out :type "lisp")
    (write-string "(user \"eve\" :mood :sad)
#.(error \"no\")" out)
    :close-stream
    (signals dialogue-error (load-memory path "eve"))
    (handler-case (load-memory path "eve")
      (dialogue-error (e) (is (search ":2:" (princ-to-string e))))))
  (uiop:with-temporary-file (:pathname path :stream out :type "lisp")
    (write-string "(user \"eve\" :mood 3)" out)
    :close-stream
    (signals dialogue-error (load-memory path "eve"))))

(test repeated-bad-speech-makes-peedy-sad-and-apologetic
  (let ((c (jukebox-conversation)))
    (conversation-hear c "hello")
    (is (eq :neutral (memory-mood (conversation-memory c))))
    (is (equal '("Huh?") (turn-utterances (conversation-hear c "blah"))))
    (is (eq :neutral (memory-mood (conversation-memory c))))
    (is (equal '("Sorry, could you repeat that?") (turn-utterances (conversation-hear c "blah blah"))))
    (is (eq :sad (memory-mood (conversation-memory c))))
    (is (equal '("I am really sorry, I just can't make that out.") (turn-utterances (conversation-hear c "blah"))))
    ;; Understood at last: the streak ends, and success makes him happy.
    (conversation-hear c "play bonnie raitt")
    (is (eq :happy (memory-mood (conversation-memory c))))
    (is (equal '("Huh?") (turn-utterances (conversation-hear c "blah"))))
    ;; A recogniser that heard nothing it knows gives NIL: bad speech too.
    (let ((turn (conversation-hear c nil)))
      (is (string= "evBadSpeech" (symbol-name (turn-event turn))))
      (is-false (turn-understood turn))
      (is (equal '("Sorry, could you repeat that?") (turn-utterances turn))))
    ;; His mood picks the template: happy, "any time!" is possible.
    (is (no-failures-p c))))

(test the-matcher-finds-events-and-slots
  (let ((d (jukebox)))
    (flet ((match (text) (multiple-value-list (match-utterance d text))))
      (destructuring-bind (event slots understood score) (match "Play something by Bonnie Raitt after that, please!")
        (is (= 1.0 score))
        (is (string= "evPlayArtist" (symbol-name event)))
        (is (equal '(("ARTIST" . "Bonnie Raitt") ("TIMEREF" . "after that")) slots))
        (is-true understood))
      (is (equal '(("ARTIST" . "Andrew Lloyd Webber")) (second (match "play andrew lloyd webber"))))
      (is (equal '(("TITLE" . "Angel From Montgomery")) (second (match "Who wrote Angel from Montgomery?"))))
      (is (string= "evNo" (symbol-name (first (match "no thanks")))))
      (is (string= "evThanks" (symbol-name (first (match "thanks")))))
      ;; A first name, or a request buried in other words, is not understood.
      (dolist (text '("play something by bonnie" "play something by bonnie raitt and then tidy my room" "" "sure sure"))
        (destructuring-bind (event slots understood score) (match text)
          (is (< score player.dialogue::*understanding-threshold*))
          (is (string= "evBadSpeech" (symbol-name event)) "~S" text)
          (is (null slots))
          (is-false understood))))))

(defun jsgf-rule (grammar name)
  "The right-hand side of the JSGF rule <NAME> in GRAMMAR, or NIL."
  (let* ((start (search (format nil "<~A> = " name) grammar))
         (end (and start (position #\; grammar :start start))))
    (and start (subseq grammar (+ start (length name) 5) end))))

(test jsgf-grammar-comes-from-the-utterance-patterns
  (let ((grammar (dialogue-jsgf (jukebox))))
    (is (eql 0 (search (format nil "#JSGF V1.0;~2%grammar peedy_jukebox;") grammar)))
    (is (search "public <request> = [<filler>] (<evhello> | <evplayartist> | <evplaytrack> | <evhaveyougot> | <evok> | <evno> | <evwhowrotetrack> | <evthanks> | <evstop>);" grammar))
    (is (search "id like to" (jsgf-rule grammar "filler")))
    ;; Figure 3's statement, its TIMEREF optional, its words offered with their synonyms.
    (is (search "(play | " (jsgf-rule grammar "evplayartist")))
    (is (search " | spin | " (jsgf-rule grammar "evplayartist")))
    (is (search " | platter | " (jsgf-rule grammar "evplayartist")))
    (is (search ") by <artist> [<timeref>]" (jsgf-rule grammar "evplayartist")))
    (is (equal '("after that" "next" "afterwards" "later")
               (mapcar (lambda (s) (string-trim " 
|" s)) (uiop:split-string (jsgf-rule grammar "timeref") :separator "|"))))
    ;; Slot alternatives are the catalogue's names, in words the recogniser knows.
    (let ((artists (jsgf-rule grammar "artist")))
      (dolist (artist '("bonnie raitt" "joe jackson" "andrew lloyd webber" "madonna" "bo diddley" "raitt" "lloyd webber"))
        (is (search artist artists) "<artist> lacks ~A" artist)))
    (is (search "angel from montgomery" (jsgf-rule grammar "title")))
    ;; No input without patterns (evBadSpeech) gets a rule.
    (is (null (jsgf-rule grammar "evbadspeech")))))

(defun pocketsphinx-program ()
  "The path of pocketsphinx_continuous, or NIL when it is not installed."
  (let ((path (ignore-errors (uiop:run-program '("sh" "-c" "command -v pocketsphinx_continuous")
                                               :output '(:string :stripped t)))))
    (and path (plusp (length path)) path)))

(defun write-silent-wav (path seconds)
  "Write SECONDS of silence to PATH as a 16 kHz, 16-bit mono WAV."
  (let* ((samples (round (* 16000 seconds)))
         (data (* 2 samples)))
    (with-open-file (out path :direction :output :element-type '(unsigned-byte 8) :if-exists :supersede)
      (flet ((text (s) (loop for c across s do (write-byte (char-code c) out)))
             (int (n bytes) (dotimes (i bytes) (write-byte (ldb (byte 8 (* 8 i)) n) out))))
        (text "RIFF") (int (+ 36 data) 4) (text "WAVE")
        (text "fmt ") (int 16 4) (int 1 2) (int 1 2) (int 16000 4) (int 32000 4) (int 2 2) (int 16 2)
        (text "data") (int data 4)
        (dotimes (i data) (write-byte 0 out))))))

(defun write-dictionary-with (path words)
  "Write pocketsphinx's English dictionary to PATH with WORDS ((WORD PHONES)...) added:
the words the recogniser learns from espeak-ng when it loads a grammar."
  (with-open-file (out path :direction :output :if-exists :supersede)
    (with-open-file (in (nth-value 1 (player.speech::pocketsphinx-model-files)))
      (loop for line = (read-line in nil) while line do (write-line line out)))
    (loop for (word phones) in words do (format out "~A ~A~%" word phones))))

(test pocketsphinx-accepts-the-grammar
  (let ((program (pocketsphinx-program)))
    (if (null program)
        (skip "pocketsphinx_continuous is not installed")
        (uiop:with-temporary-file (:pathname wav :type "wav")
          (write-silent-wav wav 0.3)
          (uiop:with-temporary-file (:pathname dictionary :type "dict")
            ;; "peedy", an ignored word, is not in the dictionary: the recogniser learns it.
            (write-dictionary-with dictionary '(("peedy" "P IY D IY")))
            (flet ((accepts-p (grammar)
                     (uiop:with-temporary-file (:pathname path :stream out :type "gram")
                       (write-string grammar out)
                       :close-stream
                       (zerop (nth-value 2 (uiop:run-program (list program "-jsgf" (namestring path)
                                                                   "-dict" (namestring dictionary)
                                                                   "-infile" (namestring wav))
                                                             :ignore-error-status t :output nil :error-output nil))))))
              (is-true (accepts-p (dialogue-jsgf (jukebox))))
              ;; The check can fail: a word the dictionary lacks is refused.
              (is-false (accepts-p (format nil "#JSGF V1.0;~%grammar g;~%public <request> = play zzxqj;~%")))))))))

(test say-hook-and-presenter-hear-every-utterance
  (let* ((said '())
         (*say-function* (lambda (text conversation)
                           (declare (ignore conversation))
                           (push text said)))
         (out (make-string-output-stream))
         (c (make-conversation (jukebox) :presenter (make-text-presenter :stream out))))
    (conversation-hear c "have you got anything by bonnie raitt")
    (conversation-hear c "zzz")
    (is (= 2 (length said)))
    (is (equal (list "input: evHaveYouGot artist=\"Bonnie Raitt\""
                     "transition: stIdle --evHaveYouGot--> stGotCD"
                     (format nil "peedy: ~S" (second said))
                     "input: evBadSpeech (not understood)"
                     "transition: stGotCD --evBadSpeech--> stGotCD"
                     "peedy: \"Huh?\"")
               (lines (get-output-stream-string out))))))

(defun pattern-sentences (elements)
  "Every sentence (a list of words) the pattern ELEMENTS generate."
  (if (null elements)
      (list '())
      (let* ((element (first elements))
             (rests (pattern-sentences (rest elements)))
             (heads (append (if (player.dialogue::pattern-words-p element)
                                (list (player.dialogue::pattern-words-words element))
                                (mapcar #'car (player.dialogue::pattern-slot-alternatives element)))
                            (and (player.dialogue::pattern-optional-p element) (list '())))))
        (loop for head in heads append (loop for rest in rests collect (append head rest))))))

(test every-sentence-of-the-grammar-is-matched
  ;; The JSGF grammar and the matcher come from the same patterns: whatever
  ;; the recogniser can return, the matcher understands, as the same event.
  (let ((d (jukebox)) (sentences 0))
    (dolist (utterance (player.dialogue::dialogue-utterances d))
      (dolist (words (pattern-sentences (player.dialogue::utterance-pattern-elements utterance)))
        (incf sentences)
        (multiple-value-bind (event slots understood) (match-utterance d (format nil "~{~A~^ ~}" words))
          (declare (ignore slots))
          (is-true understood "~{~A~^ ~} is not understood" words)
          (is (eq (player.dialogue::utterance-pattern-event utterance) event) "~{~A~^ ~}: ~A" words event))))
    (is (< 100 sentences))))
