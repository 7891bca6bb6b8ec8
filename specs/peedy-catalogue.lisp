;;;; peedy-catalogue.lisp -- the CDs Peedy's jukebox holds (data, read by the
;;;; dialogue in peedy-dialogue.lisp).  The artists are those of Persona's
;;;; Figure 3 plus Clapton of Figure 4; the Bonnie Raitt Collection and "Angel
;;;; From Montgomery" are the paper's, the other titles are invented.
;;;; (cd ID :title T :artist A :year Y :tracks (TITLE or (TITLE :composer C) ...))

(in-package :player-user)

(cd bonnie-raitt-collection :title "The Bonnie Raitt Collection" :artist "Bonnie Raitt" :year 1990
    :tracks ("Angel From Montgomery" "River Of Slow Light" "Kitchen Table Blues"))
(cd summer-radio :title "Summer Radio" :artist "Madonna" :year 1987
    :tracks ("Dance All Night" "Open Window" "Holiday Lights"))
(cd night-and-traffic :title "Night And Traffic" :artist "Joe Jackson" :year 1982
    :tracks ("Rain In The City" "Walking Home" "Steel Bridges"))
(cd images-of-the-sea :title "Images Of The Sea" :artist "Claude Debussy" :year 1905
    :tracks ("The Sunken Cathedral" "Clouds Over The Water" "Gardens In The Rain"))
(cd stage-lights :title "Stage Lights" :artist "Andrew Lloyd Webber" :year 1986
    :tracks ("Think Of Me Tonight" "Masks And Mirrors"))
(cd sunny-days :title "Sunny Days" :artist "Synchro System" :year 1983
    :tracks ("Synchro Dance" "Morning Drums"))
(cd evergreen :title "Evergreen" :artist "Pearl Jam" :year 1993
    :tracks ("Black Ocean" "Alive Again" "Long Road North"))
(cd little-help :title "With A Little Help" :artist "Joe Cocker" :year 1969
    :tracks (("A Little Help From My Friends" :composer "John Lennon") "Feeling Alright Tonight"))
(cd journeyman-blues :title "Journeyman Blues" :artist "Eric Clapton" :year 1989
    :tracks (("Before You Accuse Me" :composer "Bo Diddley") "Running On Faith Again"))
