;;;; dialogue.lisp -- issue 15's figure: one turn of Peedy's jukebox dialogue,
;;;; from the typed sentence to the Player events it sends (matching, the
;;;; input's query, choosing the transition, templates, episodic memory and
;;;; Peedy's controller on a null presenter), without audio.  Two turns are
;;;; paraphrases, scored against every pattern (issue 28).

(in-package #:player-bench)

(defparameter *dialogue-file* (merge-pathnames "../specs/peedy-dialogue.lisp" *bench-directory*))

(defparameter *dialogue-turns*
  '("hello" "have you got anything by bonnie raitt" "sure" "no" "who wrote that" "yes"
    "mumble" "stop the music" "play something by andrew lloyd webber after that" "thanks"
    "let's see, i think i'd like to hear a little debussy" "play before you accuse me by clapton")
  "A conversation that visits every state; the benchmark plays it again and again.")

(defun play-dialogue-round (dialogue machine)
  "One conversation of *DIALOGUE-TURNS*, with a fresh memory and controller."
  (let ((conversation (player:make-conversation
                       dialogue :controller (player:make-controller
                                             machine :presenter (player:make-null-presenter)
                                                     :initial-state (player:dialogue-player-initial dialogue)))))
    (dolist (text *dialogue-turns*)
      (player:conversation-hear conversation text))))

(defun bench-dialogue ()
  "The row for a dialogue turn: text to Player events."
  (let* ((dialogue (first (player:load-dialogue *dialogue-file*)))
         (machine (player:compile-spec (player:dialogue-player-spec dialogue)))
         (per-turn (/ (seconds-per-call (lambda () (play-dialogue-round dialogue machine)))
                      (length *dialogue-turns*))))
    (row "11. dialogue turn, typed text to Player events (jukebox, null presenter)"
         (format-seconds per-turn) "< 1 ms" (< per-turn 1d-3))
    (note "dialogue turn: a conversation of ~D turns, a fresh memory and controller each time"
          (length *dialogue-turns*))))
