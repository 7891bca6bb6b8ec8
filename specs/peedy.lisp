;;;; peedy.lisp -- Peedy the parrot, the CD-jukebox agent of Microsoft Research's
;;;; Persona project, as the Player papers describe it (Kurlander & Ling, CHI '95;
;;;; "Lifelike Computer Characters: the Persona project at Microsoft Research").
;;;;
;;;; Same size as the paper's prototype controller, scaled up: 7 state variables
;;;; (one a time variable), 5 autoscripts, 44 operators (3 of them macro-ops, 4
;;;; must-ask), 9 state classes and 38 events, which compile to 13 goals; two
;;;; idle timers and a trigger act when he runs on a timed controller.
;;;; Durations are in seconds. Try:
;;;;   bin/player run specs/peedy.lisp --initial alert=snore,posture=sit \
;;;;     --events ev-search,ev-search,ev-bad-speech,ev-thanks
;;;;
;;;; CHECK reports the states no op sequence can reach from the initial state:
;;;; a sleeping parrot cannot be flying, hold his wing to his ear or wear the
;;;; headphones. Every goal is reachable from every state, those included.

(in-package :player-user)

(defspec peedy
  "Peedy, the parrot who finds and plays CDs (Kurlander & Ling, CHI '95)."
  (:scripts "peedy-scripts.lisp")
  (:body parrot)

  ;;; State variables

  (state-variable holding-note boolean false)           ; the note found by a search, in his beak
  (state-variable posture string stand (fly stand sit))
  (state-variable alert string awake (snore sleep awake)) ; snore: deep sleep; sleep: dozing
  (state-variable wing-at-ear boolean false)            ; "I can't hear you"
  (state-variable wearing-phones boolean false)         ; headphones on, listening to a CD
  (state-variable music-playing boolean false)          ; the jukebox is playing
  ;; When the user last spoke to Peedy (ev-idle tests it).
  (time-variable last-heard (ev-speech ev-bad-speech ev-search ev-thanks ev-confirm ev-no))

  ;;; State classes

  ;; Acknowledging the user: awake, ears free.
  (state-class ack-op (alert.awake (not wing-at-ear) (not wearing-phones)))
  (state-class stand-op (ack-op posture.stand))
  (state-class sit-op (ack-op posture.sit))
  (state-class fly-op (ack-op posture.fly))
  ;; Most note and gesture scripts were authored standing, beak empty.
  (state-class stand-noteless (stand-op (not holding-note)))
  (state-class stand-holding (stand-op holding-note))
  ;; Standing with the headphones on: stand-op with wearing-phones overridden.
  (state-class listening (stand-op wearing-phones))
  (state-class music-on (ack-op music-playing))
  (state-class grooving (stand-op music-playing))

  ;;; Operators: waking and sleeping

  (op snort :duration 1)                                ; parts of hard-wake
  (op exhale :duration 0.75)
  (op focus :duration 0.75)                             ; eyes on the camera
  ;; From deep sleep to wakefulness (the paper's example macro-op).
  (macro-op hard-wake :precond alert.snore :add alert.awake
            :seq (:op snort :op exhale :op focus))
  (op blink :duration 0.25)                             ; parts of soft-wake
  (op stretch :duration 1.25)
  ;; From a doze to wakefulness: gentler than hard-wake.
  (macro-op soft-wake :precond alert.sleep :add alert.awake
            :seq (:op blink :op stretch :op focus))
  (op doze :precond sit-op :add alert.sleep :duration 2)      ; eyes close on the perch
  (op nod-off :precond alert.sleep :add alert.snore :duration 1.5) ; doze -> deep sleep

  ;;; Operators: posture

  (op standup :precond sit-op :add posture.stand :duration 1.5)
  (op sit :precond stand-op :add posture.sit :duration 1.5)
  ;; A take-off can be called off at any moment: he is still standing. Once
  ;; his feet reach for the perch (0.85 s into the landing), a cut landing
  ;; leaves him standing.
  (op take-off :precond stand-op :add posture.fly :duration 1.25 :interrupt :anytime)
  (op land :precond fly-op :add posture.stand :duration 1.5
           :interrupt (:at 0.85) :if-cut (:add posture.stand))
  (op hop :precond stand-op :duration 0.5)
  (op fly-loop :precond fly-op :duration 3              ; a lap around the room,
              :interrupt (:at 0.75 1.5 2.25)                 ; cut at a quarter turn,
              :channels (parrot-root root neck tail))        ; his eyes stay free
  ;; A glance at a voice moves only his eyes and needs nothing: it plays
  ;; beside whatever keeps his eyes free (try ev-circle@0,ev-voice@1 while flying).
  (op glance :duration 0.6 :channels (eyes))

  ;;; Operators: the wing

  (op raise-wing :precond ack-op :add wing-at-ear :duration 0.75)
  (op lower-wing :precond wing-at-ear :sub wing-at-ear :duration 0.75)
  ;; Huh? needs the wing at the ear, so it cannot use ack-op.
  (op huh :precond (alert.awake and wing-at-ear) :duration 1)

  ;;; Operators: the note (a search brings back a note naming the CD)

  (op search :script stream :precond stand-noteless :add holding-note :duration 3)
  (op drop-note :precond holding-note :sub holding-note :duration 0.5)
  ;; Hand the note to the user: only when an event asks for it.
  (op give-note :precond stand-holding :sub holding-note :must-ask true :duration 1)

  ;;; Operators: music and headphones

  ;; Slot the found CD into the jukebox: the note is used up, the music starts.
  (op play-cd :precond stand-holding :sub holding-note :add music-playing :duration 2)
  (op stop-cd :precond music-on :sub music-playing :duration 1)
  (op next-track :precond music-on :duration 0.75)
  (op dance :precond grooving :duration 4)
  (op put-on-phones :precond stand-op :add wearing-phones :duration 2)
  (op take-off-phones :precond (alert.awake and wearing-phones) :sub wearing-phones
      :duration 1.5)

  ;;; Operators: gestures

  (op greet :precond ack-op :duration 1.5)              ; a wave of the wing
  (op bow :precond stand-op :duration 1.25)
  (op shrug :precond stand-op :duration 1)
  (op nod :precond ack-op :duration 0.5)
  (op shake-head :precond ack-op :duration 0.75)
  (op whistle :precond ack-op :duration 1.5)
  (op look-around :precond ack-op :duration 2)
  (op scratch-head :precond ack-op :duration 1.5)       ; thinking
  (op yawn :precond ack-op :duration 1.5)
  (op point :precond stand-op :duration 1)              ; at the CD title on screen
  (op preen :precond sit-op :duration 2.5)
  (op wave-goodbye :precond ack-op :duration 1.5)
  ;; Pleased with himself: hop, whistle, bow.
  (macro-op celebrate :precond stand-op :seq (:op hop :op whistle :op bow))

  ;;; Operators: camera moves (no state, only when an event asks)

  (op camhello :must-ask true :duration 1.5)            ; push in for a close-up
  (op camgoodbye :must-ask true :duration 1.5)           ; pull back to the goodbye shot
  (op camwide :must-ask true :duration 2)               ; the whole room

  ;;; Autoscripts

  (autoscript alert snore (snore-loop))
  (autoscript alert sleep (doze-breathe))
  (autoscript posture fly (flap-wings))
  (autoscript music-playing true (tap-foot))
  (autoscript wearing-phones true (bob-head))

  ;;; Events: the dialogue

  (event ev-search :op search)                          ; "What do you have by Bonnie Raitt?"
  (event ev-bad-speech :state wing-at-ear :op huh)      ; recognition failed
  (event ev-thanks :op bow :label a :time (+ (label a) 3) :op camgoodbye
                   :time (+ (label a) 5) :op sit)
  (event ev-speech :op nod)                             ; heard and understood
  (event ev-hello :op camhello :op greet)
  (event ev-goodbye :op wave-goodbye :op camwide :state alert.sleep)
  (event ev-confirm :op nod)                            ; "yes"
  (event ev-no :op shake-head)
  (event ev-think :op scratch-head)
  (event ev-help :op scratch-head :op point)
  ;; Nobody has spoken for half a minute.
  (event ev-idle :if ((> (now) (+ last-heard 30)) :op yawn))

  ;;; Events: the jukebox

  (event ev-found :op play-cd)                          ; play what the search found
  (event ev-give :op give-note)
  (event ev-not-found :op shrug)
  (event ev-point :op point)
  (event ev-stop :op stop-cd)
  (event ev-next-track :op next-track)
  (event ev-cd-done :op stop-cd :op bow)
  (event ev-dance :op dance)
  (event ev-listen :state listening)                    ; put the headphones on
  (event ev-celebrate :op celebrate)
  (event ev-applause :op bow)

  ;;; Events: body and camera

  (event ev-wake :state ack-op :op stretch)
  (event ev-sleep :state alert.sleep)
  (event ev-nap :state alert.snore)
  (event ev-stand :state stand-op)
  ;; Sitting down preempts whatever he is doing (CHI'95's fly-then-sit example:
  ;; bin/player run specs/peedy.lisp --events ev-fly-to@0,ev-sit@0.4).
  (event ev-sit (:when-busy :preempt) :op sit)
  (event ev-fly-to :op take-off :op fly-loop :op land)  ; fly round the room to the perch
  (event ev-fly :op take-off)
  (event ev-land :op land)
  (event ev-circle :op fly-loop)
  (event ev-preen :op preen)
  (event ev-hop :op hop)
  (event ev-whistle :op whistle)
  (event ev-look :op look-around)
  (event ev-wide :op camwide)
  (event ev-rest :state sit-op)                         ; off his feet
  (event ev-voice :op glance)                           ; someone speaks off to his left

  ;;; Idle behaviour (Persona: "after a period of inaction will sit down ... and
  ;;; eventually fall asleep"), and a dance whenever the music starts.

  (timer idle-sit :after 20 :event ev-rest :restart-on :any)
  (timer idle-sleep :after 60 :event ev-sleep :restart-on :any)
  (trigger music-starts :when music-playing :event ev-dance))
