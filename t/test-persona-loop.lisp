;;;; test-persona-loop.lisp -- Persona's whole loop: sentences generated from
;;;; the jukebox dialogue's utterance patterns, spoken by espeak-ng, heard by
;;;; pocketsphinx with the dialogue's own JSGF grammar, matched to input
;;;; events and slots; `chat --wav` and `speak` as a user runs them; a
;;;; rendered conversation whose speech.wav holds Peedy's replies while his
;;;; beak moves.  Skips with a note when libespeak-ng or pocketsphinx is missing.

(in-package #:player-tests)

(def-suite* persona-loop :in player-tests)

(defmacro with-speech-libraries ((what) &body body)
  "Run BODY when espeak-ng and pocketsphinx are both installed; otherwise skip,
saying WHAT is not tested."
  `(cond ((not (espeak-available-p))
          (skip "libespeak-ng is not installed (Debian libespeak-ng1): ~A not tested" ,what))
         ((not (pocketsphinx-available-p))
          (skip "pocketsphinx or its model is not installed (Debian pocketsphinx, pocketsphinx-en-us): ~A not tested" ,what))
         (t ,@body)))

;;; ---------------------------------------------------------------------------
;;; Sentences from the grammar

(defun pattern-sentence (pattern choice)
  "A sentence PATTERN (an utterance pattern) generates: CHOICE picks each
slot's alternative (stepping through them about 7 at a time, so CHOICEs
differ in artist and title) and which optional elements are said."
  (let ((words '()))
    (loop for element in (player.dialogue::utterance-pattern-elements pattern)
          for k from 0
          unless (and (player.dialogue::pattern-optional-p element) (evenp (+ choice k)))
            do (setf words
                     (append words
                             (if (player.dialogue::pattern-words-p element)
                                 (player.dialogue::pattern-words-words element)
                                 (let ((alternatives (player.dialogue::pattern-slot-alternatives element)))
                                   (car (nth (mod (+ (* 7 (+ choice k)) (floor (+ choice k) 2)) (length alternatives))
                                             alternatives)))))))
    (format nil "~(~{~A~^ ~}~)" words)))

(defun jukebox-sentences (&optional (choices 3))
  "CHOICES sentences for each of the jukebox dialogue's utterance patterns, in
order, each pattern's choice numbered apart so artists and titles vary."
  (let ((dialogue (jukebox)))
    (loop for choice below choices
          append (loop for pattern in (player.dialogue::dialogue-utterances dialogue)
                       for index from 0
                       collect (pattern-sentence pattern (+ index (* 5 choice)))))))

(test generated-sentences-cover-every-input-and-match-as-typed
  (let* ((dialogue (jukebox))
         (sentences (jukebox-sentences))
         (events (mapcar (lambda (text) (symbol-name (match-utterance dialogue text))) sentences)))
    (is (<= 12 (length sentences)))
    (dolist (text sentences)
      (is-true (nth-value 2 (match-utterance dialogue text)) "~S is not matched" text))
    (dolist (event '("evHello" "evPlayArtist" "evHaveYouGot" "evOK" "evNo" "evWhoWroteTrack" "evThanks" "evStop"))
      (is (member event events :test #'string=) "no sentence says ~A" event))
    ;; Several artists and titles, and the optional time reference both ways.
    (is (<= 6 (length (remove-duplicates (loop for text in sentences
                                                for slots = (nth-value 1 (match-utterance dialogue text))
                                                append (mapcar #'cdr slots))
                                          :test #'string=))))
    (is (find-if (lambda (s) (search "after that" s)) sentences))))

;;; ---------------------------------------------------------------------------
;;; The round trip: text -> espeak-ng -> WAV -> pocketsphinx -> event and slots

(test spoken-requests-give-the-right-events-and-slots
  (with-speech-libraries ("the round trip at the event and slot level")
    (let* ((dialogue (jukebox))
           (grammar (dialogue-jsgf dialogue))
           (sentences (sweep-sample (jukebox-sentences) 12))
           (wrong '())
           ;; The recogniser's round trip, its rejection of speech outside the
           ;; grammar off: test-speech-rejection.lisp measures that trade-off.
           (player::*rejection-margin* most-negative-single-float)
           (player::*longest-phone* most-positive-single-float)
           (player::*most-unexplained-speech* most-positive-fixnum))
      (loop for text in sentences
            for k from 1
            for wav = (speech-file (format nil "request-~2,'0D.wav" k))
            do (write-wav wav (utterance-sound (synthesize-speech text)))
               (let ((heard (recognize-wav wav :grammar grammar)))
                 (multiple-value-bind (event slots) (match-utterance dialogue text)
                   (multiple-value-bind (heard-event heard-slots) (match-utterance dialogue (or heard ""))
                     (unless (and (eq event heard-event) (equal slots heard-slots))
                       (push (list text heard) wrong))))))
      (let* ((total (length sentences))
             (right (- total (length wrong))))
        (format t "~&; round trip: ~D of ~D spoken requests gave the right input event and slots~%" right total)
        ;; The issue asks for 10 of 12; the same share of these.
        (is (>= right (ceiling (* 10 total) 12)) "only ~D of ~D right; wrong (said heard): ~S"
            right total (reverse wrong))))))

;;; ---------------------------------------------------------------------------
;;; The command line: speak, chat --wav

(test speak-writes-a-wav-that-chat-hears
  (with-speech-libraries ("speak and chat --wav")
    (let ((wav (speech-file "cli-request.wav")))
      (multiple-value-bind (out err code) (player-command "speak" "have you got anything by joe jackson" "--out" wav)
        (is (= 0 code) "~A" err)
        (is (search "; wrote " out))
        (is (< 1 (sound-duration (read-wav wav)) 4)))
      (multiple-value-bind (out err code) (player-command "chat" "specs/peedy-dialogue.lisp" "--wav" wav)
        (is (= 0 code) "~A" err)
        (is (equal '("heard: \"have you got anything by joe jackson\"")
                   (mapcar (lambda (line) (subseq line 0 (search " (score " line))) (chat-lines-starting "heard: " out))))
        (is (equal '("input: evHaveYouGot artist=\"Joe Jackson\"") (chat-lines-starting "input: " out)))
        (is (equal '("transition: stIdle --evHaveYouGot--> stGotCD") (chat-lines-starting "transition: " out)))
        (is (member "(:event ev-search :time 0)" (lines out) :test #'string=))
        (is (= 1 (length (chat-lines-starting "peedy: " out))))))))

(test chat-wav-errors-are-one-line
  (let ((text (speech-file "not-a-sound.wav")))
    (write-octets text (map 'list #'char-code "not a sound"))
    ;; Every file is read before the first turn.
    (check-cli-error 1 (format nil "cannot read the WAV file ~A: it is not a RIFF WAVE file" text)
                     "chat" "specs/peedy-dialogue.lisp" "--wav" text)
    (check-cli-error 1 "there is no such file"
                     "chat" "specs/peedy-dialogue.lisp" "--wav" (speech-file "no-such-request.wav")))
  (check-cli-error 2 "--video needs --render DIR" "chat" "specs/peedy-dialogue.lisp" "--video" "x.mp4")
  (check-cli-error 2 "--silent silences --render or --view" "chat" "specs/peedy-dialogue.lisp" "--silent")
  (check-cli-error 2 "it takes neither --wav nor --render" "chat" "specs/peedy-dialogue.lisp" "--view" "--wav" "x.wav")
  (check-cli-error 2 "speak needs a TEXT" "speak" " ")
  (check-cli-error 2 "--rate takes words a minute from 80 to 450" "speak" "hi" "--rate" "20"))

;;; ---------------------------------------------------------------------------
;;; Peedy speaks in the rendered conversation

(defun speaking-jukebox ()
  "A jukebox conversation played on Peedy's body, his replies said by a
speaker: (VALUES CONVERSATION SPEAKER PERFORMANCE)."
  (let* ((dialogue (jukebox))
         (spec (dialogue-player-spec dialogue))
         (presenter (make-body-presenter spec))
         (controller (make-controller (compile-spec spec) :initial-state (player::dialogue-player-initial dialogue)
                                                          :presenter presenter))
         (performance (presenter-performance presenter)))
    (values (make-conversation dialogue :seed 1 :controller controller)
            (make-speaker performance)
            performance)))

(defun beak-opening (performance time)
  "How far Peedy's beak is open (a fraction of its range) at TIME in PERFORMANCE."
  (player::performance-frame performance time)
  (let* ((body (player::performance-body performance))
         (index (player::dof-index (player::body-skeleton body) 'beak 'open))
         (high (player.body::body-dof-max (nth-value 1 (player.body::skeleton-dof (player::body-skeleton body) index)))))
    (/ (aref (player::body-pose body) index) high)))

(defun loudness (sound from to)
  "The root-mean-square sample of SOUND between FROM and TO seconds."
  (let* ((samples (sound-samples sound))
         (start (min (length samples) (round (* from (sound-rate sound)))))
         (end (min (length samples) (round (* to (sound-rate sound))))))
    (if (>= start end)
        0d0
        (sqrt (/ (loop for i from start below end sum (expt (aref samples i) 2)) (float (- end start) 1d0))))))

(test replies-are-said-at-the-player-clock-with-the-beak
  (if (not (espeak-available-p))
      (skip "libespeak-ng is not installed (Debian libespeak-ng1): spoken replies not tested")
      (multiple-value-bind (conversation speaker performance) (speaking-jukebox)
        (let ((controller (conversation-controller conversation))
              (resumed nil))
          (with-speaker (speaker)
            (conversation-hear conversation "hi")
            (setf resumed (speaker-wait speaker controller))
            (conversation-hear conversation "have you got anything by madonna"))
          (destructuring-bind ((start-2 end-2 text-2 who-2) (start-1 end-1 text-1 who-1))
              (speaker-lines speaker)
            (is (equal '(:peedy :peedy) (list who-1 who-2)))
            (is (string= "Hi! What would you like to hear?" text-1))
            (is (search "Summer Radio" text-2))
            ;; Said when his animation had ended: the Player clock of the moment.
            (is (= 5.5d0 start-1) "the greeting is said at ~A, when ev-hello's ops end" start-1)
            (is (= start-2 (controller-clock controller)) "the answer is said when the search ends")
            ;; The second turn waited for the first reply, and a pause.
            (is (< end-1 resumed start-2))
            (let ((middle-1 (/ (+ start-1 end-1) 2))
                  (sound (player::performance-audio performance (+ end-2 0.5d0))))
              (is (< 0.3 (loop for time from start-1 to end-1 by 0.02 maximize (beak-opening performance time)))
                  "the beak opens during the greeting")
              (is (< (beak-opening performance (+ end-1 0.3d0)) 0.05) "and shuts after it")
              (is (< 500 (loudness sound (- middle-1 0.2) (+ middle-1 0.2))) "the greeting sounds on the track")
              (is (< 500 (loudness sound start-2 end-2)) "so does the answer")
              (is (< (loudness sound (+ end-1 0.05) (+ end-1 0.35)) 50) "a pause between them")))))))

(test chat-render-speaks-the-replies-into-speech-wav
  (if (not (espeak-available-p))
      (skip "libespeak-ng is not installed (Debian libespeak-ng1): chat --render's speech not tested")
      (let ((out (speech-file "chat-render/")))
        (multiple-value-bind (text err code)
            (player-command-with-input (format nil "hi~%") "chat" "specs/peedy-dialogue.lisp"
                                       "--render" out "--fps" "4" "--size" "64x48")
          (is (= 0 code) "~A" err)
          (is (equal '("peedy: \"Hi! What would you like to hear?\"") (chat-lines-starting "peedy: " text)))
          (is (member (format nil "; wrote ~Aspeech.wav" out) (lines text) :test #'string=))
          (let ((sound (read-wav (format nil "~Aspeech.wav" out))))
            ;; ev-hello's ops end at 5.5 s; the greeting lasts about 2 s.
            (is (< 500 (loudness sound 5.7 7.3)) "the greeting is on the track")
            (is (< 7.6 (sound-duration sound)) "the frames cover the whole greeting"))))))

(test without-espeak-rendering-is-silent-after-one-note
  (let ((player.speech::*espeak-library-names* '("libespeak-ng-missing-for-a-test.so.1"))
        (player.speech::*espeak-rate* nil)
        (player.speech::*loaded-speech-libraries* '()))
    (let* ((available t)
           (note (with-output-to-string (*standard-output*)
                   (setf available (player.cli::speech-available-or-note)))))
      (is-false available)
      (is (= 1 (length (lines note))) "~S" note)
      (is (search "; no speech: " note))
      (is (search "install the Debian package libespeak-ng1" note)))))
