;;;; package.lisp -- player.dialogue: Persona's dialogue manager: sentences to input events, transitions, templates, memory, speaking.

(defpackage #:player.dialogue
  (:use #:cl #:player.base #:player.spec #:player.planner #:player.ir #:player.control #:player.speech #:player.body #:player.ode #:player.physics #:player.performance #:player.model #:player.rig)
  (:import-from #:alexandria
                #:when-let #:if-let #:ensure-list #:hash-table-keys
                #:with-gensyms #:once-only #:appendf #:read-file-into-string)
  (:documentation "Persona's dialogue manager: sentences to input events, transitions, templates, memory, speaking.")
  (:export
   #:*say-function* #:begin-conversation #:call-with-speaker #:choose-template
   #:context-value #:conversation #:conversation-controller #:conversation-dialogue
   #:conversation-hear #:conversation-input #:conversation-memory
   #:conversation-player-events #:conversation-state #:conversation-turns #:defdialogue
   #:define-dialogue #:define-dialogue-action #:dialogue #:dialogue-error
   #:dialogue-initial-state #:dialogue-jsgf #:dialogue-name #:dialogue-not-understood
   #:dialogue-p #:dialogue-player-initial #:dialogue-player-spec #:dialogue-presenter
   #:dialogue-state-names #:display-name #:episodic-memory #:expand-template #:gesture-marks #:*music-function* #:speaker-play-music #:track-sound #:explain-utterance
   #:find-dialogue #:load-dialogue #:load-memory #:make-conversation #:make-memory
   #:make-speaker #:make-text-presenter #:match-utterance #:memory-conversations
   #:memory-log #:memory-mood #:memory-user #:present-input #:present-transition
   #:present-utterance #:save-memory #:speaker #:speaker-end #:speaker-lines
   #:speaker-listen #:speaker-say #:speaker-say-function #:speaker-wait #:text-presenter
   #:text-words #:turn-event #:turn-events #:turn-from #:turn-slots #:turn-text #:turn-to
   #:turn-understood #:turn-utterances #:with-speaker))
