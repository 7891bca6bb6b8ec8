;;;; test-word-sync.lisp -- gestures on words (issue 28, item 5): espeak-ng's
;;;; word events as an utterance's word timeline, (:word ...) sync points in
;;;; scripts, a :say item's length in its script's inferred duration, and the
;;;; <!beat>/<!point> marks of dialogue templates landing on their words.
;;;; WITH-ESPEAK (test-speech.lisp) skips what needs libespeak-ng.

(in-package #:player-tests)

(def-suite* word-sync :in player-tests)

(defparameter *raitt-line* "Play something by Bonnie Raitt, please."
  "A sentence whose words the tests sync to.")

(test espeak-reports-each-word-and-when-it-is-said
  (with-espeak
    (let* ((utterance (player::synthesize-speech *raitt-line*))
           (words (player::utterance-words utterance))
           )
      (is (equal '("Play" "something" "by" "Bonnie" "Raitt" "please") (mapcar #'first words))
          "the words as written, without punctuation")
      (is (every #'< (mapcar #'second words) (mapcar #'second (rest words))) "in order")
      ;; Checked against the phoneme timeline: each word begins with its own
      ;; first sound, and ends within the sound.
      (loop for word in words
            for sound in '("p" "s" "b" "b" "r" "p")
            for phoneme = (find (second word) (player::utterance-phonemes utterance)
                                :key #'second :test (lambda (a b) (< (abs (- a b)) 1d-6)))
            do (is (and phoneme (string= sound (first phoneme)))
                   "~A starts at ~,3F s, with the phoneme ~A" (first word) (second word) phoneme)
               (is (<= (second word) (third word) (player::utterance-duration utterance))))
      (is (= (second (fifth words)) (player::utterance-word-time utterance "raitt")) "by spelling, any case")
      (is (= (second (fifth words)) (player::utterance-word-time utterance 5)) "by number")
      (is (null (player::utterance-word-time utterance "madonna")))
      (is (null (player::utterance-word-time utterance 7))))
    (let ((words (player::utterance-words (player::synthesize-speech "Café éclair time"))))
      (is (equal '("Café" "éclair" "time") (mapcar #'first words)) "positions count characters, not bytes"))))

(defun word-library (&rest items)
  "A library whose script TALK (no :duration) holds ITEMS."
  (player.performance::parse-script-library-forms `((defscript talk () ,@items))))

(test a-say-item-counts-its-whole-sentence-for-the-inferred-duration
  (with-espeak
    (let ((script (player::find-script (word-library `(:at 0.5 :say ,*raitt-line*)) 'talk))
          (length (player::utterance-duration (player::synthesize-speech *raitt-line*))))
      (is (< 1.5 length))
      (is (< (abs (- (+ 0.5 length) (player::script-duration script))) 1d-9)
          "the script lasts ~,3F s, the speech ends at ~,3F s" (player::script-duration script) (+ 0.5 length)))))

(test an-unknown-voice-is-an-error-at-its-item
  (with-espeak
    (let ((text (handler-case (progn (word-library '(:at 0 :say "hello" :voice "xx-nonesuch")) nil)
                  (player::script-error (e) (princ-to-string e)))))
      (is (and text (search "has no voice xx-nonesuch" text) (search ":voice \"xx-nonesuch\"" text))
          "~A" text))))

(test items-start-on-the-words-they-name
  (with-espeak
    (let* ((library (word-library `(:at 0.5 :say ,*raitt-line*)
                                  '(:at (:word "raitt") :motor (:beat :times (0.15)))
                                  '(:at (:word 2 -0.1) :motor (:gaze :target (:point 0 1 2)))))
           (items (player.performance::script-items (player::find-script library 'talk)))
           (utterance (player::synthesize-speech *raitt-line*)))
      (is (< (abs (- (player.performance::script-item-at (second items))
                     (+ 0.5 (player::utterance-word-time utterance "Raitt"))))
             1d-6))
      (is (< (abs (- (player.performance::script-item-at (third items))
                     (+ 0.5 (player::utterance-word-time utterance 2) -0.1)))
             1d-6)))))

(test a-word-sync-point-may-name-its-sentence
  (with-espeak
    (let* ((library (word-library `(:at 0.2 :say ,*raitt-line* :as offer)
                                  '(:at 3 :say "Thank you")
                                  '(:at (:word offer "raitt") :motor (:beat :times (0.15)))
                                  '(:at (:word "you") :motor (:beat :times (0.15)))))
           (items (player.performance::script-items (player::find-script library 'talk))))
      (is (< (abs (- (player.performance::script-item-at (third items))
                     (+ 0.2 (player::utterance-word-time (player::synthesize-speech *raitt-line*) "raitt"))))
             1d-6)
          "the named sentence, though another was said since")
      (is (< (abs (- (player.performance::script-item-at (fourth items))
                     (+ 3 (player::utterance-word-time (player::synthesize-speech "Thank you") 2))))
             1d-6)
          "unnamed: the last sentence before it"))
    (is (search "names no :say item written before it with :as greeting"
                (handler-case (progn (word-library `(:at 0 :say ,*raitt-line* :as offer)
                                                   '(:at (:word greeting 1) :motor (:beat :times (0.15))))
                                     "")
                  (player::script-error (e) (princ-to-string e)))))))

(test a-word-sync-point-that-names-nothing-is-an-error-at-its-item
  (with-espeak
    (loop for (items fragment)
            in `((((:at 0 :motor (:beat :times (0.1))) (:at (:word 1) :motor (:beat :times (0.1))))
                  "no :say item comes before it")
                 (((:at 0 :say ,*raitt-line*) (:at (:word "madonna") :motor (:beat :times (0.1))))
                  "has no word \"madonna\"")
                 (((:at 0 :say ,*raitt-line*) (:at (:word 9) :motor (:beat :times (0.1))))
                  "has no word 9")
                 (((:at 0 :say ,*raitt-line*) (:at (:word 0) :motor (:beat :times (0.1))))
                  "a word sync point is")
                 (((:at 0 :say ,*raitt-line*) (:at (:word "play" -1) :motor (:beat :times (0.1))))
                  "before the script starts"))
          do (let ((text (handler-case (progn (apply #'word-library items) nil)
                           (player::script-error (e) (princ-to-string e)))))
               (is (and text (search fragment text)) "~S: ~A" items text)))))

(defun right-elbow-track (performance end &optional (step 0.01d0))
  "(TIME . DEGREES) of PERFORMANCE's right elbow flexion every STEP seconds to END."
  (let* ((body (player::performance-body performance))
         (index (player::dof-index (player::body-skeleton body) 'r_elbow :x)))
    (loop for time from 0d0 to end by step
          collect (progn (player::performance-frame performance time)
                         (cons time (aref (player::body-pose (player::performance-body performance)) index))))))

(defun deepest-dip (track)
  "The time of TRACK's largest elbow deviation from its first value."
  (let ((rest (cdr (first track))))
    (car (reduce (lambda (a b) (if (>= (abs (- (cdr a) rest)) (abs (- (cdr b) rest))) a b)) track))))

(test a-beat-lands-on-its-word
  (with-espeak
    (let* ((library (word-library `(:at 0.3 :say ,*raitt-line*)
                                  '(:at (:word "raitt" -0.15) :motor (:beat :times (0.15)))))
           (performance (player::make-performance library '((bob humanoid))))
           (word (+ 0.3 (player::utterance-word-time (player::synthesize-speech *raitt-line*) "raitt"))))
      (player::perform-script performance 'talk 0)
      (is (< (abs (- (deepest-dip (right-elbow-track performance 3)) word)) 0.015)
          "the beat's stroke is deepest when Raitt is said (~,2F s)" word))))

(test template-marks-say-which-word-gets-which-gesture
  (multiple-value-bind (text gestures) (player::gesture-marks "I've got <!point>this one by <!beat>Bonnie Raitt.")
    (is (equal "I've got this one by Bonnie Raitt." text))
    (is (equal '((3 :point) (6 :beat)) gestures)))
  (multiple-value-bind (text gestures) (player::gesture-marks "<!BEAT>Hello -- world")
    (is (equal "Hello -- world" text))
    (is (equal '((1 :beat)) gestures) "case-insensitive; a dash is no word"))
  (is (equal '("plain" nil) (multiple-value-list (player::gesture-marks "plain"))))
  (signals player.dialogue::dialogue-error (player::gesture-marks "a <!wave>hello")))

(test the-speaker-lands-a-marked-beat-on-its-word
  (with-espeak
    (let* ((library (player.performance::parse-script-library-forms '((defscript idle (:duration 1)))))
           (performance (player::make-performance library '((bob humanoid))))
           (text "Here is <!beat>Madonna for you")
           (plain "Here is Madonna for you")
           (word (player::utterance-word-time (player::synthesize-speech plain) "madonna")))
      (multiple-value-bind (duration run)
          (player::performance-say performance plain :at 1 :gestures (nth-value 1 (player::gesture-marks text)))
        (is (< 1 duration))
        (is (= 2 (length (player.performance::script-items (player.performance::script-run-script run)))))
        (is (< (abs (- (deepest-dip (right-elbow-track performance (+ 1 duration))) (+ 1 word))) 0.015)
            "the beat's stroke is deepest at Madonna (~,2F s)" (+ 1 word))))))
