;;;; test-dialogue-mood.lisp -- a dialogue's (mood NAME) reaches the body: the
;;;; speaker sets the performance's mood at the controller's time, so Peedy's
;;;; gestures grow when he is happy and shrink when he is sad (issue 29, item 5).

(in-package #:player-tests)

(def-suite* dialogue-mood :in player-tests)

(defun body-mood-at (performance time)
  "The mood of PERFORMANCE's character at TIME."
  (player::performance-frame performance time)
  (player.body::body-mood (player::performance-body performance)))

(test a-dialogue-mood-reaches-the-body
  (if (not (espeak-available-p))
      (skip "libespeak-ng is missing: the speaking jukebox not tested")
      (multiple-value-bind (conversation speaker performance) (speaking-jukebox)
        (let ((controller (conversation-controller conversation)))
          (with-speaker (speaker)
            (conversation-hear conversation "hi")
            (speaker-wait speaker controller)
            (let ((before (float (controller-time controller) 1d0)))
              (is (= 0 (body-mood-at performance before)) "neutral before any (mood ...)")
              ;; Peedy's dialogue: playing a track makes him happy.
              (conversation-hear conversation "play something by madonna")
              (is (eq :happy (player.dialogue::memory-mood (player.dialogue::conversation-memory conversation))))
              (let ((after (+ 0.5d0 (float (controller-time controller) 1d0))))
                (is (< 0 (body-mood-at performance after))
                    "happy: the body's mood is positive at ~,2F s" after)
                (is (= (player.body::emotion-mood :happy) (body-mood-at performance after))))))))))

(test without-a-speaker-a-mood-is-only-remembered
  (let ((conversation (make-conversation (jukebox) :seed 1)))
    (conversation-hear conversation "play something by madonna")
    (is (eq :happy (player.dialogue::memory-mood (player.dialogue::conversation-memory conversation))))))
