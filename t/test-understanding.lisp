;;;; test-understanding.lisp -- Peedy understands paraphrases (issue 28, item
;;;; 1): the written-down set of t/fixtures/paraphrases.lisp (the paper's
;;;; Figure 3/4 lines, surnames, tracks, yes/no, out-of-domain sentences),
;;;; names without accents, "after that" queueing behind the playing track,
;;;; and readings explained.

(in-package #:player-tests)

(def-suite* understanding :in player-tests)

(defun read-paraphrases ()
  "The paraphrase set, as (HELD-OUT TEXT EVENT (SLOT VALUE)...) lists: HELD-OUT
true for the last third, after the file's `;;; HELD-OUT` line.  Read, not evaluated."
  (with-open-file (in (checkout-file "t/fixtures/paraphrases.lisp"))
    (let ((*read-eval* nil) (held-out nil) (items '()))
      (loop for line = (read-line in nil) while line
            do (cond ((eql 0 (search ";;; HELD-OUT" line)) (setf held-out t))
                     ((and (plusp (length line)) (char= (char line 0) #\())
                      (push (cons held-out (read-from-string line)) items))))
      (nreverse items))))

(defun paraphrase-right-p (dialogue text event slots)
  "Does DIALOGUE read TEXT as EVENT (a name string) with exactly SLOTS ((SLOT VALUE)...)?"
  (multiple-value-bind (heard-event heard-slots) (match-utterance dialogue text)
    (and (string-equal (symbol-name heard-event) event)
         (= (length heard-slots) (length slots))
         (every (lambda (slot)
                  (equal (second slot) (cdr (assoc (string-upcase (first slot)) heard-slots :test #'string=))))
                slots))))

(test nine-paraphrases-in-ten-reach-the-right-input-and-slots
  (let* ((dialogue (jukebox))
         (items (read-paraphrases))
         (wrong (loop for (nil text event . slots) in items
                      unless (paraphrase-right-p dialogue text event slots) collect text))
         (held-out (remove-if-not #'first items))
         (held-out-right (count-if (lambda (item) (not (member (second item) wrong :test #'string=))) held-out)))
    (format t "~&; paraphrases: ~D of ~D right (held-out third: ~D of ~D)~@[; wrong: ~S~]~%"
            (- (length items) (length wrong)) (length items) held-out-right (length held-out) wrong)
    (is (<= 60 (length items)))
    (is (<= 20 (length held-out)))
    ;; Every kind the issue names is in the set.
    (dolist (text '("how about some madonna" "a little debussy please" "spin a platter by madonna"
                    "play before you accuse me by clapton" "have you got anything by raitt"))
      (is (find text items :key #'second :test #'string=) "the set lacks ~S" text))
    (is (<= 8 (count "evBadSpeech" items :key #'third :test #'string=)))
    (is (>= (- (length items) (length wrong)) (* 0.9 (length items))) "wrong: ~S" wrong)))

(test names-match-without-case-or-accents
  (let ((dialogue (jukebox)))
    (is-true (paraphrase-right-p dialogue "Play something by CLAUDE DÉBUSSY" "evPlayArtist" '(("artist" "Claude Debussy"))))
    (is-true (paraphrase-right-p dialogue "who wrote Angel from Montgomery?" "evWhoWroteTrack"
                                 '(("title" "Angel From Montgomery"))))
    ;; A title by its significant words, its function words changed.
    (is-true (paraphrase-right-p dialogue "play sunken cathedral" "evPlayTrack" '(("title" "The Sunken Cathedral"))))
    ;; A name the catalogue lacks is not understood, nor is a word near one.
    (is-true (paraphrase-right-p dialogue "play something by frank zappa" "evBadSpeech" '()))
    (is-true (paraphrase-right-p dialogue "the cathedral was sunken" "evBadSpeech" '()))))

(test readings-are-scored-and-explained
  (let* ((readings (player.dialogue::utterance-readings (jukebox) "spin a platter by madonna"))
         (best (first readings)))
    (is (string= "evPlayArtist" (symbol-name (player.dialogue::reading-event best))))
    (is (< 0.6 (player.dialogue::reading-score best) 1.0))
    (is (every (lambda (r) (<= (player.dialogue::reading-score r) (player.dialogue::reading-score best))) readings))
    (let ((notes (format nil "~{~A~^; ~}" (player.dialogue::reading-notes best))))
      (is (search "\"spin\" is \"play\"" notes) "~A" notes)
      (is (search "\"platter\" is \"something\"" notes) "~A" notes)
      (is (search "artist=\"Madonna\"" notes) "~A" notes))))

(test after-that-queues-the-request-behind-the-playing-track
  (let ((c (jukebox-conversation)))
    (turn! c "play something by madonna" "stIdle" "stPlaying" '("ev-search" "ev-found"))
    (let ((playing (context-value c "track")))
      (is (string= "Summer Radio" (player.dialogue::cd-title (player.dialogue::track-cd playing))))
      ;; Queued, not played: no pePlay (ev-found), the state stays stPlaying.
      (turn! c "spin something by pearl jam after that" "stPlaying" "stPlaying" '("ev-search"))
      (turn! c "play before you accuse me by clapton next" "stPlaying" "stPlaying" '("ev-search")
             "After this one, Before You Accuse Me.")
      (is (eql 2 (context-value c "queued")))
      ;; The track ends: the queue plays in order, then Peedy is done.
      (let ((turn (conversation-input c 'evTrackEnded)))
        (is (equal '("ev-found") (mapcar #'string-downcase (mapcar #'symbol-name (turn-events turn)))))
        (is (string= "Evergreen" (player.dialogue::cd-title (player.dialogue::track-cd (context-value c "track"))))))
      (conversation-input c 'evTrackEnded)
      (is (string= "Before You Accuse Me" (player.dialogue::track-title (context-value c "track"))))
      (turn! c '(evTrackEnded) "stPlaying" "stAttending" '()))
    ;; Without a time reference a request replaces the playing track at once.
    (turn! c "play madonna" "stAttending" "stPlaying" '("ev-search" "ev-found"))
    (turn! c "play something by pearl jam" "stPlaying" "stPlaying" '("ev-search" "ev-found"))
    (is (eql 0 (context-value c "queued")))
    (is (no-failures-p c))))

(test chat-explain-prints-readings-and-keeps-the-input-line
  (multiple-value-bind (out err code)
      (player-command-with-input (format nil "how about a little debussy~%what time is it~%")
                                 "chat" "specs/peedy-dialogue.lisp" "--explain")
    (is (= 0 code) "~A" err)
    (let ((explained (chat-lines-starting "explain: " out)))
      ;; The best reading first, with its score and why; then the threshold.
      (is (alexandria:starts-with-subseq "explain: 0.8" (first explained)) "~S" explained)
      (is (search "evPlayArtist artist=\"Claude Debussy\"" (first explained)))
      (is (search "\"how about\" is \"play\"" (first explained)))
      (is (search "(last name of Claude Debussy)" (first explained)))
      (is (find "explain: understood at 0.60 or more; nothing is: evBadSpeech" explained :test #'string=)))
    ;; The input line keeps its shape, which other tools read.
    (is (equal '("input: evPlayArtist artist=\"Claude Debussy\"" "input: evBadSpeech (not understood)")
               (chat-lines-starting "input: " out))))
  ;; Without --explain, no explain lines.
  (is (null (chat-lines-starting "explain: " (player-command-with-input (format nil "hi~%")
                                                                        "chat" "specs/peedy-dialogue.lisp")))))
