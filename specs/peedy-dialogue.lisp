;;;; peedy-dialogue.lisp -- Peedy's CD jukebox conversation, after Persona's
;;;; dialogue manager ("Lifelike Computer Characters: the Persona project at
;;;; Microsoft Research", Figures 3 and 6-9): five conversational states,
;;;; input events with the sentences that say them, transitions sending the
;;;; events of specs/peedy.lisp, and verbal templates by category.
;;;; Try:  bin/player chat specs/peedy-dialogue.lisp
;;;;   > have you got anything by bonnie raitt     > sure     > who wrote that
;;;;   > how about a little debussy                > spin something by madonna after that
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
  (input evPlayTrack "a request for a track by title (and maybe artist)" :query ((findTrack)))
  (input evTrackEnded "the playing track has ended (the jukebox says so)")
  (input evHaveYouGot "have you got anything by ARTIST?" :query ((findCDs)))
  (input evOK "sure, ok, yes")
  (input evNo "no")
  (input evWhoWroteTrack "who wrote that? (the last referenced object)" :query ((whoWrote)))
  (input evThanks "thanks")
  (input evStop "stop the music")
  (input evBadSpeech "nothing the grammar allows was recognised")

  ;;; How people say it: Persona's synonym rules ("platter" is obCD, "spin"
  ;;; is vbPlay; one abstract word for whatever can be played, as the paper's
  ;;; obPlayable), its colloquialisms ("how about" is "play") and the verbal
  ;;; artifacts and wishes that mean "please do" ("let's see", "i'd like to")

  (synonyms "play" "hear" "put on" "spin" "start" "let's hear" "let me hear" "how about"
            "what about" "listen to" "give me")
  (synonyms "something" "anything" "some" "a little" "a bit of" "music" "song" "songs" "track"
            "tracks" "tune" "piece" "record" "records" "cd" "cds" "platter" "album" "albums"
            "collection" "stuff")
  (synonyms "have you got" "do you have" "have you" "is there")
  (synonyms "wrote" "composed" "write" "made")
  (synonyms "yes" "yeah" "yep" "yup" "sure" "sure thing" "ok" "okay" "alright" "all right"
            "of course" "sounds good" "go ahead" "why not" "please do" "definitely" "absolutely")
  (synonyms "no" "nope" "nah" "no way" "not now" "not really" "not yet")
  (synonyms "thanks" "thank you" "cheers" "thanks a lot" "much obliged")
  (synonyms "stop" "turn it off" "turn off" "switch it off" "switch off" "enough"
            "quiet" "silence")
  (synonyms "hello" "hi" "hey" "howdy" "good morning" "good afternoon" "good evening")
  (fillers "let's see" "i think" "i'd like to" "i would like to" "i want to" "i wanna" "i'd love to"
           "it would be nice to" "could you" "can you" "would you" "will you" "um" "uh" "well")

  ;;; What the user may say (the matcher scores sentences against these, and
  ;;; the JSGF grammar is made of them, synonyms as alternatives)

  (phrases timeref "after that" "next" "afterwards" "later")
  (utterance evHello "hello")
  (utterance evPlayArtist "play something by" (:slot artist) (:optional timeref))   ; Figure 3
  (utterance evPlayArtist "play" (:slot artist) (:optional timeref))
  (utterance evPlayArtist "something by" (:slot artist) (:optional timeref))       ; "A little Mozart, please."
  (utterance evPlayArtist (:slot artist))
  (utterance evPlayTrack "play" (:slot title) (:optional timeref))
  (utterance evPlayTrack "play" (:slot title) "by" (:slot artist) (:optional timeref)) ; Figure 4
  (utterance evHaveYouGot "have you got anything by" (:slot artist))
  (utterance evHaveYouGot "what do you have by" (:slot artist))
  (utterance evOK "yes")
  (utterance evNo "no")
  (utterance evNo "no thanks")
  (utterance evWhoWroteTrack "who wrote that")
  (utterance evWhoWroteTrack "who wrote" (:slot title))
  (utterance evThanks "thanks")
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
;; "After that" / "next" while a track plays: the request waits its turn.
  (on stPlaying evPlayArtist :if (and timeref (> cnt0 0))
      :do ((do peSearch) (genTracks) (doSelect) (queueTrack) (say queued)))
  (on stPlaying evPlayTrack :if (and timeref (> cnt0 0)) :do ((do peSearch) (queueTrack) (say queued)))
  (on * evPlayTrack :if (= cnt0 0) :to stAttending :do ((do peSearch) (do ev-not-found) (say noTrack)))
  (on * evPlayTrack :to stPlaying :do ((do peSearch) (clearQueue) (do pePlay) (mood happy) (say playing)))
  (on stPlaying evTrackEnded :if (> queued 0) :do ((playNext) (do pePlay) (say playing)))
  (on stPlaying evTrackEnded :to stAttending :do ((say trackOver)))
  (on * evPlayArtist :if (= cnt0 0) :to stAttending :do ((do peSearch) (do ev-not-found) (say noCD)))
  (on * evPlayArtist :to stPlaying
      :do ((do peSearch) (genTracks) (doSelect) (clearQueue) (do pePlay) (mood happy) (say playing)))
  (on stGotCD evOK :to stSuggested :do ((do pePickTrack) (genTracks) (doSelect) (say suggestTrack))) ; Figure 7
  (on stGotCD evNo :to stAttending :do ((do ev-confirm) (say maybeLater)))
  (on stSuggested evOK :to stPlaying :do ((do pePlay) (mood happy) (say playing)))
  (on stSuggested evNo :do ((do pePickTrack) (doSelect) (say suggestOther)))
  (on * evOK :do ((do ev-think) (say whatToPlay)))
  (on * evNo :do ((do ev-confirm) (say whatToPlay)))
  (on * evWhoWroteTrack :if (= cnt0 1) :do ((do ev-point) (say composer)))     ; Figure 8
  (on * evWhoWroteTrack :if (= cnt0 0) :do ((do ev-no) (say dontKnow)))
  (on stPlaying evStop :to stAttending :do ((clearQueue) (do ev-stop) (say stopped)))
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
  (template noTrack 1 "Sorry, I can't find that one.")
  (template queued 1 "After this one, <=track>.")
  (template trackOver 1 "That was the last track.")
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
