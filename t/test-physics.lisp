;;;; test-physics.lisp -- physics through ODE (issue 29, item 6): the bindings
;;;; against free fall worked by hand, the missing library, dynamic props that
;;;; fall, rest, fly when tossed and land where Peedy drops them, the same
;;;; frames for the same inputs.

(in-package #:player-tests)

(def-suite* physics :in player-tests)

;;;# The ODE layer

(test ode-sphere-falls-as-integrated-by-hand
  ;; Semi-implicit Euler, as dWorldStep integrates: after n steps of h from
  ;; rest, y = y0 - g h² n(n+1)/2 (worked by hand, not by ODE).
  (let* ((world (player.ode:make-ode-world :step-size 0.01))
         (body (player.ode:make-ode-body world '(:sphere 0.05) :mass 1 :position '(0 2 0))))
    (unwind-protect
         (loop for n in '(1 10 40)
               for done = 0 then previous
               for previous = n
               do (player.ode:ode-world-step world (- n done))
                  (let ((expected (- 2 (* 9.81d0 0.01d0 0.01d0 n (1+ n) 1/2))))
                    (is (< (abs (- (nth-value 1 (player.ode:ode-body-position body)) expected)) 1d-6)
                        "after ~D steps the sphere is at ~A, not ~A" n
                        (nth-value 1 (player.ode:ode-body-position body)) expected)))
      (player.ode:destroy-ode-world world))))

(test ode-sphere-rests-on-a-plane
  (let* ((world (player.ode:make-ode-world))
         (body (player.ode:make-ode-body world '(:sphere 0.05) :mass 0.2 :position '(0 0.5 0))))
    (unwind-protect
         (progn
           (player.ode:make-ode-geom world '(:sphere 0.05) :body body)
           (player.ode:make-ode-geom world '(:plane 0 1 0 0))
           (player.ode:ode-world-step world 960)
           (multiple-value-bind (x y z) (player.ode:ode-body-position body)
             (is (< (abs (- y 0.05)) 0.001) "the ball rests at its radius, not ~A" y)
             (is (< (+ (abs x) (abs z)) 1d-6) "a ball dropped straight stays put, not ~A ~A" x z))
           (is (not (player.ode:ode-body-enabled-p body)) "a ball at rest sleeps"))
      (player.ode:destroy-ode-world world))))

(test ode-checks-its-arguments
  (let ((world (player.ode:make-ode-world)))
    (signals player:argument-error (player.ode:make-ode-geom world '(:box 1 0 1)))
    (signals player:argument-error (player.ode:make-ode-body world '(:plane 0 1 0 0)))
    (signals player:argument-error (player.ode:make-ode-body world '(:sphere 1) :mass -1))
    (signals player:argument-error (player.ode:make-ode-world :gravity '(0 :down 0)))
    (player.ode:destroy-ode-world world)
    (signals player:ode-error (player.ode:ode-world-step world))))

(test missing-ode-names-libode8
  (let ((player.ode::*ode-state* nil)
        (player.ode::*ode-library-names* '("libode-not-installed.so.99")))
    (handler-case (progn (player.ode:ensure-ode) (fail "no error for a missing libode"))
      (player:ode-unavailable (e)
        (is (search "libode8" (princ-to-string e)) "the error names libode8: ~A" e)))))

;;;# Dynamic props

(defparameter *physics-library-forms*
  '((defobject table :kind :prop :position (0 -0.02 0) :properties ((size :vector (1.8 0.04 1.2))))
    (defobject note :kind :prop :position (0.2 0.001 0.1) :dynamic t
      :properties ((size :vector (0.06 0.002 0.08))))
    (defobject ball :kind :prop :position (-0.3 0.05 0) :dynamic t :properties ((size :number 0.1)))
    (defscript hold-note (:duration 1)
      (:at 0 :attach note :to (:self :right-hand) :keep-world nil)
      (:at 0 :set (note position) (:vec3 0 0 0)))
    (defscript drop-it (:duration 0.1)
      (:at 0 :attach note :to nil))
    (defscript toss (:duration 0.1)
      (:at 0 :set (ball velocity) (:vec3 1 3 0))))
  "A table, a note a humanoid holds and drops, and a ball a script tosses.")

(defun physics-performance ()
  "A performance of *PHYSICS-LIBRARY-FORMS* on a humanoid called BOB."
  (player:make-performance (player.performance::parse-script-library-forms *physics-library-forms*)
                           '((bob humanoid))))

(defun object-y (performance name time)
  "The world height of object NAME in PERFORMANCE at TIME."
  (player.body:vec3-y (player:object-world-position
                       (player:find-object (player:performance-frame performance time) name))))

(test dropped-note-falls-and-rests-on-the-table
  (let ((performance (physics-performance)))
    (player:perform-script performance 'hold-note 0)
    (player:perform-script performance 'drop-it 1)
    (let ((held (object-y performance 'note 1)))
      (is (> held 0.5) "the hand holds the note up at ~A" held)
      (is (< 0.05 (object-y performance 'note 1.2) (- held 0.1)) "0.2 s after, the note is falling")
      ;; g t²/2: 0.2 s after letting go it has fallen about 0.196 m.
      (is (< (abs (- (- held (object-y performance 'note 1.2)) 0.196)) 0.02))
      (let ((rest (object-y performance 'note 3)))
        (is (< (abs (- rest 0.001)) 0.01) "the note rests on the table top (y = 0.001), not at ~A" rest)
        (is (player:physics-prop-resting-p (player:performance-scene performance) 'note))))))

(test tossed-ball-flies-and-lands
  (let ((performance (physics-performance)))
    (player:perform-script performance 'toss 0.5)
    (is (< (abs (- (object-y performance 'ball 0.4) 0.05)) 0.002) "the ball lies still before the toss")
    ;; Apex v²/2g = 9/19.62 = 0.459 m above where it was, 3/9.81 = 0.306 s after the toss.
    (let ((apex (loop for time from 0.5 to 1.2 by 0.01 maximize (object-y performance 'ball time))))
      (is (< (abs (- apex (+ 0.05 0.459))) 0.03) "the ball rises to ~A" apex))
    (let ((x (player.body:vec3-x (player:object-world-position
                                  (player:find-object (player:performance-frame performance 1.0) 'ball)))))
      (is (< (abs (- x (+ -0.3 (* 1 0.5)))) 0.02) "the ball flew 1 m/s for 0.5 s, to ~A" x))
    (is (< (abs (- (object-y performance 'ball 4) 0.05)) 0.005) "the ball ends on the table")))

(defun physics-frames (performance &key (fps 30) (seconds 3))
  "PERFORMANCE's frame forms at FPS for SECONDS."
  (loop for index to (* fps seconds)
        for time = (/ index (float fps 1d0))
        collect (player.performance:frame-form index time (player:performance-frame performance time))))

(test physics-gives-the-same-frames-for-the-same-inputs
  (flet ((perform ()
           (let ((performance (physics-performance)))
             (player:perform-script performance 'hold-note 0)
             (player:perform-script performance 'drop-it 1)
             (player:perform-script performance 'toss 0.5)
             performance)))
    (let ((performance (perform)))
      (is (equal (physics-frames performance) (physics-frames (perform))))
      ;; Scrubbing back replays from the start: the same frames again.
      (is (equal (physics-frames performance) (physics-frames performance))))))

(test dynamic-is-for-props
  (signals player:script-error
    (player.performance::parse-script-library-forms '((defobject cam :kind :camera :dynamic t))))
  (signals player:script-error
    (player.performance::parse-script-library-forms '((defobject box :kind :prop :dynamic 3))))
  (let ((library (player.performance::parse-script-library-forms '((defobject box :kind :prop :dynamic t)))))
    (is (= 1 (length (player.performance::script-library-objects library))))))

(test peedy-drops-the-note-onto-the-table
  ;; The search finds the note and he holds it up; drop-note lets go 0.25 s in.
  (let* ((library (player:load-script-library (checkout-file "specs/peedy-scripts.lisp")))
         (performance (player:make-performance library '((peedy parrot)))))
    (player:perform-director performance 'stream 0)
    (player:perform-script performance 'drop-note 3)
    (let ((held (object-y performance 'note 3.25)))
      (is (> held 0.02) "he holds the note above the table (~A)" held)
      (is (< (object-y performance 'note 3.3) held) "let go, it falls")
      (let ((rest (object-y performance 'note 5)))
        (is (< (abs (- rest 0.001)) 0.01) "it rests on the table top, at ~A" rest)))))

;;;# Newton's cradle swung by ODE

(defun cradle-ball-x (performance name time)
  "The world x of cradle object NAME at TIME."
  (player.body:vec3-x (player:object-world-position
                       (player:find-object (player:performance-frame performance time)
                                           (intern (string-upcase name) '#:player-user)))))

(test ode-cradle-swings-with-pendulum-timing
  (let* ((library (player.performance::parse-script-library-forms (player:cradle-ode-script-forms :n 5 :lifted 1)))
         (performance (player:make-performance library '((nobody none))))
         (length 0.35d0) (theta (* 35 (/ pi 180))) (g 9.81d0))
    (player:perform-script performance (intern "RELEASE" '#:player-user) 0)
    ;; Lifted 35 degrees over 1 s, then let go: the quarter period of a
    ;; 35-degree pendulum, T0/4 (1 + θ²/16 + 11θ⁴/3072), worked by hand.
    (let* ((quarter (* (/ pi 2) (sqrt (/ length g)) (+ 1 (/ (* theta theta) 16) (/ (* 11 (expt theta 4)) 3072))))
           (lifted-x (cradle-ball-x performance "ball-1" 1))
           (hit (loop for time from 1d0 to 1.6d0 by (/ 1d0 240)
                      when (>= (cradle-ball-x performance "ball-1" time) -0.2006d0) return (- time 1))))
      (is (< (abs (- lifted-x (- -0.2 (* length (sin theta))))) 0.002) "lifted to ~A" lifted-x)
      (is (and hit (< (abs (- hit quarter)) 0.015)) "it reaches the row after ~A s, not ~A s" hit quarter)
      ;; The last ball takes the momentum: out to nearly the lifted angle, the others stay.
      (let ((out (loop for time from 1.2d0 to 1.8d0 by 0.01d0 maximize (cradle-ball-x performance "ball-5" time))))
        (is (> out (+ 0.2 (* 0.8 length (sin theta)))) "the last ball swings out to ~A" out))
      (is (< (abs (- (cradle-ball-x performance "ball-3" 1.6) 0)) 0.01) "the middle ball stays")
      ;; The string turns with its ball (the physics turns the pivot).
      (let ((scene (player:performance-frame performance 1.1)))
        (is (< (abs (- (player.body:vec3-x (player:object-world-position
                                            (player:find-object scene (intern "STRING-1" '#:player-user))))
                       (+ -0.2 (/ (- (cradle-ball-x performance "ball-1" 1.1) -0.2) 2))))
               0.002)
            "the string's middle is halfway to its ball")))))

(test ode-cradle-scripts-file-is-the-generated-one
  (is (string= (player.compose:cradle-ode-scripts-text)
               (alexandria:read-file-into-string (checkout-file "specs/newtons-cradle-ode-scripts.lisp")))
      "regenerate it: (player.compose:write-cradle-ode-scripts-file \"specs/newtons-cradle-ode-scripts.lisp\")")
  ;; The spec plays it: the last ball swings out after the release.
  (let* ((spec (first (load-spec (checkout-file "specs/newtons-cradle-ode.lisp"))))
         (simulation (player::simulate spec :events '(ev-release) :until 2 :silent t :stream nil))
         (performance (player.performance::simulation-performance simulation)))
    (is (> (cradle-ball-x performance "ball-5" 1.6) 0.3))))
