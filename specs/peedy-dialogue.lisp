;;;; peedy-dialogue.lisp -- Peedy's CD jukebox conversation, after Persona's
;;;; dialogue manager ("Lifelike Computer Characters: the Persona project at
;;;; Microsoft Research", Figures 3 and 6-9): five conversational states,
;;;; input events with the sentences that say them, transitions sending the
;;;; events of specs/peedy.lisp, and verbal templates by category.
;;;; Try:  bin/player chat specs/peedy-dialogue.lisp
;;;;   > have you got anything by bonnie raitt     > sure     > who wrote that
;;;;
;;;; Read with the readtable case :invert, so the paper's names keep their
;;;; spelling (stGotCD, evOK, haveCD); names are compared without regard to case.

(in-package :player-user)

(defdialogue peedy-jukebox
  "Peedy the parrot finds and plays CDs (Persona's CD jukebox)."
  (:player "peedy.lisp")
  (:player-initial ((alert . snore) (posture . sit)))   ; asleep on his perch
  (:catalogue "peedy-catalogue.lisp")
  (:initial stIdle)
  (:not-understood evBadSpeech)
  (:ignore-words "please" "peedy")

  ;;; The five conversational states

  (state stIdle "nobody is talking to Peedy")
  (state stAttending "awake, waiting for a request")
  (state stGotCD "he has offered a CD: would you like to hear something from that?")
  (state stSuggested "he has suggested a track: how about ...?")
  (state stPlaying "a track plays")

  ;;; Input events; a query runs before the transition is chosen (Figure 8)

  (input evHello "a greeting")
  (input evPlayArtist "a request by artist" :query ((findCDs)))
  (input evHaveYouGot "have you got anything by ARTIST?" :query ((findCDs)))
  (input evOK "sure, ok, yes")
  (input evNo "no")
  (input evWhoWroteTrack "who wrote that? (the last referenced object)" :query ((whoWrote)))
  (input evThanks "thanks")
  (input evStop "stop the music")
  (input evBadSpeech "nothing the grammar allows was recognised")

  ;;; What the user may say (the typed-text matcher and the JSGF grammar)

  (phrases timeref "after that" "next")
  (utterance evHello "hello")
  (utterance evHello "hi")
  (utterance evPlayArtist "play something by" (:slot artist) (:optional timeref))   ; Figure 3
  (utterance evPlayArtist "play" (:slot artist) (:optional timeref))
  (utterance evPlayArtist "i want to hear something by" (:slot artist))
  (utterance evHaveYouGot "have you got anything by" (:slot artist))
  (utterance evHaveYouGot "what do you have by" (:slot artist))
  (utterance evOK "sure")
  (utterance evOK "ok")
  (utterance evOK "okay")
  (utterance evOK "yes")
  (utterance evNo "no")
  (utterance evNo "no thanks")
  (utterance evWhoWroteTrack "who wrote that")
  (utterance evWhoWroteTrack "who wrote" (:slot title))
  (utterance evThanks "thanks")
  (utterance evThanks "thank you")
  (utterance evStop "stop")
  (utterance evStop "stop the music")

  ;;; The paper's animation names, as events of specs/peedy.lisp

  (animation peSearch ev-search)         ; fetch the note naming the CD
  (animation pePickTrack ev-think)       ; consider a choice
  (animation pePlay ev-found)            ; slot the CD in
  (animation peHuh ev-bad-speech)        ; wing to the ear
  (animation peThanks ev-thanks)         ; bow, camera pulls back, sit

  ;;; Transitions: rules for the state come before rules for any state (*),
  ;;; each in this order; the first whose :if holds is taken.

  (on * evHello :to stAttending :do ((do ev-hello) (say greeting)))
  (on * evHaveYouGot :if (= cnt0 0) :to stAttending :do ((do peSearch) (do ev-not-found) (say noCD)))
  (on * evHaveYouGot :if (asked-before artist) :to stGotCD
      :do ((do peSearch) (getLastCD) (say haveCDAgain)))
  (on * evHaveYouGot :to stGotCD :do ((do peSearch) (getLastCD) (say haveCD)))
  (on * evPlayArtist :if (= cnt0 0) :to stAttending :do ((do peSearch) (do ev-not-found) (say noCD)))
  (on * evPlayArtist :to stPlaying
      :do ((do peSearch) (genTracks) (doSelect) (do pePlay) (mood happy) (say playing)))
  (on stGotCD evOK :to stSuggested :do ((do pePickTrack) (genTracks) (doSelect) (say suggestTrack))) ; Figure 7
  (on stGotCD evNo :to stAttending :do ((do ev-confirm) (say maybeLater)))
  (on stSuggested evOK :to stPlaying :do ((do pePlay) (mood happy) (say playing)))
  (on stSuggested evNo :do ((do pePickTrack) (doSelect) (say suggestOther)))
  (on * evOK :do ((do ev-think) (say whatToPlay)))
  (on * evNo :do ((do ev-confirm) (say whatToPlay)))
  (on * evWhoWroteTrack :if (= cnt0 1) :do ((do ev-point) (say composer)))     ; Figure 8
  (on * evWhoWroteTrack :if (= cnt0 0) :do ((do ev-no) (say dontKnow)))
  (on stPlaying evStop :to stAttending :do ((do ev-stop) (say stopped)))
  (on * evStop :do ((do ev-no) (say nothingPlays)))
  (on stPlaying evThanks :do ((do peThanks) (say welcome)))
  (on * evThanks :to stIdle :do ((do peThanks) (say welcome)))
  ;; Episodic memory: the second failure in a row is not another "Huh?".
  (on * evBadSpeech :if (>= (streak evBadSpeech) 2) :do ((do peHuh) (mood sad) (say sorry)))
  (on * evBadSpeech :do ((do peHuh) (say huh)))

  ;;; Verbal templates: each taken with its probability when the cascade
  ;;; reaches it (Figure 9: four equally likely ways to say haveCD)

  (template greeting 1 "Hi! What would you like to hear?")
  (template haveCD 0.25 "I have <=Title> from <=Year>.")
  (template haveCD 0.333 "I've got <=Title>.")
  (template haveCD 0.5 "I've got <=Title>, would you like to hear something from that?")
  (template haveCD 1 "I have <=Title> from <=Year>, would you like to hear something from that?")
  (template haveCDAgain 1 "<=Artist> again? I still have <=Title>, would you like to hear something from that?")
  (template noCD 0.5 "Sorry, I have nothing by <=artist>.")
  (template noCD 1 "I looked, but there is nothing by <=artist> here.")
  (template suggestTrack 0.5 "How about <=track>?")
  (template suggestTrack 1 "Would you like to hear <=track>?")
  (template suggestOther 1 "Then how about <=track>?")
  (template playing 0.25 "Crank it up! Here is <=track>." :limit :conversation)  ; once per conversation
  (template playing 1 "Here is <=track>.")
  (template maybeLater 1 "OK, maybe later.")
  (template whatToPlay 1 "What would you like me to play?")
  (template composer 1 "<=composer>")
  (template dontKnow 1 "I don't know.")
  (template stopped 1 "OK, the music is off.")
  (template nothingPlays 1 "Nothing is playing.")
  (template welcome 0.5 "Any time! I like this one too." :if (= mood :happy))
  (template welcome 1 "You're welcome!")
  (template huh 1 "Huh?")
  (template sorry 1 "I am really sorry, I just can't make that out." :if (>= (streak evBadSpeech) 3))
  (template sorry 1 "Sorry, could you repeat that?"))
