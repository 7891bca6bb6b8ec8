;;;; test-fragments.lisp -- issue 28, item 2: context that acts.  A surname
;;;; two artists share (t/fixtures/namesakes-dialogue.lisp) makes Peedy ask which one; a fragment answering him
;;;; ("the one by ...", "the second one", the name) completes the request.

(in-package #:player-tests)

(def-suite* fragments :in player-tests)

(defun namesakes-conversation ()
  "A conversation of t/fixtures/namesakes-dialogue.lisp, whose catalogue has Joe and Janet Jackson."
  (make-conversation (first (load-dialogue (checkout-file "t/fixtures/namesakes-dialogue.lisp")))))

(defun hear-all (conversation &rest texts)
  "Hear TEXTS in CONVERSATION; the last turn."
  (let ((turn nil))
    (dolist (text texts turn) (setf turn (conversation-hear conversation text)))))

(test a-shared-surname-asks-which-artist
  (let* ((conversation (namesakes-conversation))
         (turn (conversation-hear conversation "have you got anything by jackson")))
    (is (string= "evWhichArtist" (symbol-name (turn-event turn))))
    (is (equal '("Do you mean Joe Jackson or Janet Jackson?") (turn-utterances turn)))
    ;; A full name is not ambiguous, nor a surname only one artist has.
    (is (string= "evHaveYouGot" (symbol-name (turn-event (conversation-hear conversation "have you got anything by joe jackson")))))
    (is (string= "evHaveYouGot" (symbol-name (turn-event (conversation-hear conversation "have you got anything by clapton")))))))

(test fragments-answer-the-question
  (loop for (answer artist) in '(("the one by janet" "Janet Jackson") ("joe" "Joe Jackson")
                                 ("the second one" "Janet Jackson") ("the first" "Joe Jackson")
                                 ("janet jackson please" "Janet Jackson") ("the last one" "Janet Jackson"))
        do (let* ((conversation (namesakes-conversation))
                  (turn (hear-all conversation "have you got anything by jackson" answer)))
             (is (string= "evHaveYouGot" (symbol-name (turn-event turn))) "~S gave ~A" answer (turn-event turn))
             (is (equal (list (cons "ARTIST" artist)) (turn-slots turn)) "~S gave ~S" answer (turn-slots turn))
             (is (= 1 (length (turn-utterances turn))))))
  ;; The request's other slots come along: a time reference, a play request.
  (let ((turn (hear-all (namesakes-conversation) "play something by jackson" "the one by janet")))
    (is (string= "evPlayArtist" (symbol-name (turn-event turn))))
    (is (equal '(("ARTIST" . "Janet Jackson")) (turn-slots turn)))))

(test a-fragment-without-a-question-is-not-an-answer
  ;; No question pending: "the second one" is nothing; an unrelated request after a question is itself.
  (is (string= "evBadSpeech" (symbol-name (turn-event (conversation-hear (namesakes-conversation) "the second one")))))
  (let ((turn (hear-all (namesakes-conversation) "have you got anything by jackson" "stop the music")))
    (is (string= "evStop" (symbol-name (turn-event turn)))))
  ;; The question is answered once: a second fragment is not.
  (let ((turn (hear-all (namesakes-conversation) "have you got anything by jackson" "the second one" "the first")))
    (is (string= "evBadSpeech" (symbol-name (turn-event turn))))))
