;;;; test-authoring.lisp -- issue 14's authoring aids: a spec without a script
;;;; library plays placeholders (a gesture per op, its name as a caption in
;;;; the frame, on the humanoid or the parrot), the caption font, and script
;;;; libraries' starting poses (:pose-when EXPR POSE), with their errors.
;;;; Uses the renderer helpers of test-render.lisp and the CLI and window
;;;; helpers of test-cli.lisp and test-viewer.lisp.

(in-package #:player-tests)

(def-suite* authoring :in player-tests)

(eval-when (:compile-toplevel :load-toplevel :execute)
  ;; Read into the tests' WITH-SPEC forms by #., so needed when compiling.
  (defparameter *door-forms*
    '((state-variable open boolean false)
      (state-variable locked boolean true)
      (op unlock :precond locked :sub locked)
      (op open-door :precond (not locked) :add open :duration 1.5)
      (event ev-enter :state open))
    "The README's door spec (open-door made longer), which names no script library."))

(defun door-simulation (&rest options)
  "The door spec's ev-enter played with placeholders; OPTIONS go to SIMULATE."
  (apply #'player::simulate 'door :events '(ev-enter) options))

;;;# Placeholders

(test placeholder-library-has-a-script-per-op
  (with-spec (spec door . #.*door-forms*)
    (let* ((presenter (player::make-body-presenter spec))
           (library (player.performance::presenter-library presenter)))
      (is (player.performance::presenter-placeholder-p presenter))
      ;; Each op's script lasts the op's :duration.
      (is (= 1 (player::script-duration (player::find-script library 'unlock t))))
      (is (= 1.5 (player::script-duration (player::find-script library 'open-door t))))
      ;; A library given is played as before: no placeholders, no captions.
      (is (not (player.performance::presenter-placeholder-p
                (player::make-body-presenter spec :scripts (player.performance::parse-script-library-forms
                                                            '((defscript unlock (:duration 1))
                                                              (defscript open-door (:duration 1)))))))))))

(test placeholder-gestures-vary-by-name-and-fit-the-body
  (let ((humanoid (player::load-skeleton 'humanoid))
        (parrot (player::load-skeleton 'parrot))
        (names '(unlock open-door search sit standup bow huh snort exhale focus drop-note raise-wing)))
    ;; The same name always makes the same gesture.
    (is (eq (player.performance::placeholder-gesture 'search humanoid) (player.performance::placeholder-gesture "SEARCH" humanoid)))
    (dolist (skeleton (list humanoid parrot))
      (let ((gestures (remove-duplicates (mapcar (lambda (n) (first (player.performance::placeholder-gesture n skeleton)))
                                                 names))))
        (is (<= 4 (length gestures)) "only ~A on ~A" gestures (player.body::skeleton-name skeleton))))
    ;; Every gesture plays on both bodies: the library checks as playing would.
    (dolist (skeleton (list humanoid parrot))
      (let ((library (player.performance::parse-script-library-forms
                      (loop for gesture in player.performance::*placeholder-gestures*
                            for k from 0
                            collect `(defscript ,(intern (format nil "G~D" k)) (:duration 1.2)
                                       (:at 0 :motor ,(player.performance::gesture-motor-frame gesture skeleton 1.2)))))))
        (is (null (player.performance::check-library-scripts
                   library skeleton (loop for k below (length player.performance::*placeholder-gestures*)
                                          collect (intern (format nil "G~D" k)))
                   :characters '(figure))))))))

(test placeholder-ops-move-the-body-and-caption-their-names
  (with-spec (spec door . #.*door-forms*)
    (let* ((simulation (door-simulation))
           (performance (player.performance::simulation-performance simulation)))
      (is (= 2.5 (player::controller-clock (player.performance::simulation-controller simulation))))
      (is (<= 2.5 (player.performance::simulation-end simulation) 4) "the frames go on while the body settles")
      (flet ((caption (time) (player.body::scene-caption (player::performance-frame performance time)))
             (pose (time)
               (declare (ignore time))
               (copy-seq (player::body-pose (player::performance-body performance)))))
        (is (equal "unlock" (caption 0.5)))
        (is (equal "open-door" (caption 1.2)))
        (is (null (caption 2.6)))
        ;; Asking for an earlier time replays: the caption follows the time.
        (is (equal "unlock" (caption 0.1)))
        (let ((rest (progn (caption 0) (pose 0))))
          (is (some (lambda (time)
                      (caption time)
                      (let ((moved (pose time)))
                        (some (lambda (a b) (> (abs (- a b)) 1)) rest moved)))
                    '(0.3 0.45 0.6 1.4 1.6 1.9))
              "no placeholder gesture moved the body"))))))

(test placeholder-caption-is-cut-with-its-op
  (with-spec (spec flight
              (state-variable posture string stand (stand sit fly))
              (op take-off :precond posture.stand :add posture.fly :duration 1.25 :interrupt :anytime)
              (op fly-loop :precond posture.fly :duration 3 :interrupt (:at 0.75 1.5 2.25))
              (op land :precond posture.fly :add posture.stand :duration 1.5)
              (op sit :precond posture.stand :add posture.sit :duration 1.5)
              (event ev-fly :op take-off :op fly-loop :op land)
              (event ev-sit (:when-busy :preempt) :state posture.sit))
    (let* ((simulation (player::simulate spec :events '((ev-fly . 0) (ev-sit . 1.8)) :body 'parrot))
           (performance (player.performance::simulation-performance simulation)))
      (flet ((caption (time) (player.body::scene-caption (player::performance-frame performance time))))
        (is (equal "take-off" (caption 1)))
        (is (equal "fly-loop" (caption 1.9)))
        ;; The loop is cut at 2 s; landing follows.
        (is (equal "land" (caption 2.1)))))))

(test simulate-plays-a-spec-without-scripts
  (multiple-value-bind (out err code)
      (player-command "simulate" (fixture "mini.lisp") "--events" "ev-search" "--body" "parrot")
    (is (= 0 code) "exit ~D: ~A" code err)
    (is (search "(:op search :script stream :start 0 :end 2.5)" out) "~A" out)))

;;;# What the frames show

(defun image-statistics (pixels)
  "The mean and standard deviation of the luminance of the RGBA image PIXELS, and
its number of distinct colours (three values)."
  (let ((n (floor (length pixels) 4)) (sum 0) (squares 0) (colours (make-hash-table)))
    (dotimes (i n)
      (let* ((r (aref pixels (* 4 i))) (g (aref pixels (+ 1 (* 4 i)))) (b (aref pixels (+ 2 (* 4 i))))
             (y (+ (* 0.299 r) (* 0.587 g) (* 0.114 b))))
        (incf sum y) (incf squares (* y y))
        (setf (gethash (+ r (* 256 g) (* 65536 b)) colours) t)))
    (let ((mean (/ sum n)))
      (values mean (sqrt (max 0 (- (/ squares n) (* mean mean)))) (hash-table-count colours)))))

(defun region-difference (a b width box)
  "How many pixels of BOX (LEFT TOP WIDTH HEIGHT) differ by more than 24 levels between images A and B of WIDTH."
  (destructuring-bind (left top w h) box
    (loop for y from top below (+ top h)
          sum (loop for x from left below (+ left w)
                    count (> (pixel-difference a b (+ x (* y width))) 24)))))

(test placeholder-frames-are-not-blank-and-captions-differ
  (with-spec (spec door . #.*door-forms*)
    (dolist (body '(humanoid parrot))
      (let* ((performance (player.performance::simulation-performance (door-simulation :body body)))
             (width 320) (height 240)
             (frames (call-with-renderer
                      width height
                      (lambda (renderer)
                        (mapcar (lambda (time)
                                  (copy-seq (draw renderer (player::performance-frame performance time))))
                                '(0.5 1.7 2.6))))))
        (destructuring-bind (unlock open-door after) frames
          (dolist (frame frames)
            (multiple-value-bind (mean deviation colours) (image-statistics frame)
              (is (< 30 mean 240) "~A: mean luminance ~,1F" body mean)
              (is (< 8 deviation) "~A: luminance deviation ~,1F: a blank frame" body deviation)
              (is (< 200 colours) "~A: only ~D colours" body colours))
            (is (< 0.03 (body-pixel-share frame width height)) "~A: no figure in the middle" body))
          (let ((unlock-box (player.render::caption-layout-box (player.render::layout-caption "unlock" width height)))
                (door-box (player.render::caption-layout-box (player.render::layout-caption "open-door" width height))))
            ;; The caption's letters differ between two ops with different names ...
            (is (< 40 (region-difference unlock open-door width unlock-box)) "~A: same caption" body)
            ;; ... and it is gone when nothing plays.
            (is (< 40 (region-difference open-door after width door-box)) "~A: caption stays" body)))))))

;;;# The caption font

(test caption-font-has-every-glyph-it-promises
  (dolist (entry player.render::*caption-glyphs*)
    (is (= player.render::+glyph-rows+ (length (rest entry))) "~S" (first entry))
    (is (every (lambda (row) (and (= player.render::+glyph-columns+ (length row)) (every (lambda (c) (find c "#.")) row)))
               (rest entry))
        "~S" (first entry)))
  (is (every (lambda (char) (assoc char player.render::*caption-glyphs*))
             "ABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789-._?!"))
  ;; Runs cover exactly the lit dots; lower case draws as upper case, the unknown as ?.
  (flet ((dots (text) (reduce #'+ (player.render::caption-text-runs text) :key #'third)))
    (is (= (count #\# (apply #'concatenate 'string (player.render::caption-glyph #\W))) (dots "W")))
    (is (equal (player.render::caption-text-runs "open-door") (player.render::caption-text-runs "OPEN-DOOR")))
    (is (equal (player.render::caption-text-runs "?") (player.render::caption-text-runs "%")))
    (is (/= (dots "unlock") (dots "open-door"))))
  ;; A long caption shrinks, then is cut, to fit the frame.
  (let ((layout (player.render::layout-caption (make-string 200 :initial-element #\M) 160 120)))
    (is (= 1 (player.render::caption-layout-scale layout)))
    (is (<= (third (player.render::caption-layout-box layout)) 160)))
  (is (null (player.render::layout-caption "x" 4 4))))

;;;# Starting poses

(defun peedy-start (initial)
  "Peedy's body at time 0 from INITIAL, before any event: its pose (a copy) and position."
  (let* ((simulation (player::simulate 'player-user::peedy :initial initial :events '()))
         (body (player::find-object (player::performance-frame (player.performance::simulation-performance simulation) 0)
                                    'player-user::peedy)))
    (values (copy-seq (player::body-pose body)) (player::property-value body 'position)
            (player::body-skeleton body))))

(test peedy-starts-in-the-pose-of-his-initial-posture
  (load-spec (checkout-file "specs/peedy.lisp"))
  (multiple-value-bind (sit sit-position skeleton) (peedy-start '((posture . sit)))
    (multiple-value-bind (stand stand-position) (peedy-start '((posture . stand)))
      (flet ((angle (pose joint dof) (aref pose (player::dof-index skeleton joint dof))))
        ;; The sit pose folds the legs (peedy-poses.lisp: sit-legs) and draws the head in.
        (loop for (joint dof degrees) in '((l_knee x 45) (r_knee x 45) (l_ankle x -50) (l_hip x -15) (neck x 8))
              do (is (< (abs (- degrees (angle sit joint dof))) 1d-6) "~A ~A: ~A sitting" joint dof (angle sit joint dof))
                 (is (< 5 (abs (- degrees (angle stand joint dof)))) "~A ~A: ~A standing" joint dof (angle stand joint dof)))
        (is (< (abs (- -0.026 (player.body::vec3-y sit-position))) 1d-9))
        (is (zerop (player.body::vec3-y stand-position)))
        ;; Flying, he starts in the air.
        (multiple-value-bind (fly fly-position) (peedy-start '((posture . fly)))
          (is (= 90 (angle fly 'l_knee 'x)))
          (is (< (abs (- 0.25 (player.body::vec3-y fly-position))) 1d-9)))))))

(defun pose-when-files (line)
  "Write a spec and a script library whose third line is LINE; the spec file's path."
  (let ((library (temp-path "pw-scripts.lisp"))
        (spec (temp-path "pw.lisp")))
    (alexandria:write-string-into-file
     (format nil ";;;; a library~%(defscript sit (:duration 1) (:at 0 :motor (:pose :name bow-down)))~%~A~%" line)
     library :if-exists :supersede)
    (alexandria:write-string-into-file
     "(in-package :player-user)
(defspec pw (:scripts \"pw-scripts.lisp\")
  (state-variable posture string stand (stand sit))
  (state-variable tired boolean false)
  (op sit :precond posture.stand :add posture.sit)
  (event ev-sit :op sit))
" spec :if-exists :supersede)
    spec))

(test pose-when-chooses-the-first-entry-that-holds
  (load-spec (pose-when-files "(:pose-when (and posture.sit tired) arms-raised) (:pose-when posture.sit bow-down)"))
  (flet ((start-angle (initial)
           (let* ((simulation (player::simulate 'player-user::pw :initial initial :events '()))
                  (body (player::find-object (player::performance-frame (player.performance::simulation-performance simulation) 0)
                                             'player-user::pw))
                  (skeleton (player::body-skeleton body)))
             (list (aref (player::body-pose body) (player::dof-index skeleton 'vl5 'x))
                   (aref (player::body-pose body) (player::dof-index skeleton 'l_shoulder 'z))))))
    (let ((rest (start-angle '()))
          (bowed (start-angle '((posture . sit))))
          (raised (start-angle '((posture . sit) (tired . true)))))
      (is (zerop (first rest)))
      (is (/= (first bowed) (first rest)) "bow-down bends the trunk")
      (is (/= (second raised) (second bowed)) "arms-raised lifts the arms"))))

(test pose-when-errors-name-the-file-line-and-entry
  (loop for (line expected) in '(("(:pose-when postur.sit bow-down)" "postur.sit is not a state expression of spec pw")
                                 ("(:pose-when posture.lie bow-down)" "lie is not a value of posture")
                                 ("(:pose-when posture.sit squat)" "unknown pose squat")
                                 ("(:pose-when posture.sit)" "a starting pose is written (:pose-when EXPRESSION POSE")
                                 ("(:pose-when posture.sit bow-down :rotation (0 0 0))" ":pose-when has no option :rotation")
                                 ("(:pose-when posture.sit bow-down :position (0 x 0))" ":position must be 3 numbers")
                                 ("(:pose-when (and posture.sit nap) bow-down)" "unknown"))
        do (let ((file (pose-when-files line)))
             (multiple-value-bind (out err code) (player-command "simulate" file "--events" "ev-sit")
               (declare (ignore out))
               (is (= 1 code) "~A: exit ~D" line code)
               (is (= 1 (length (lines err))) "~A: ~A" line err)
               (is (search "player: error: pw-scripts.lisp:3: " err) "~A: no file and line in ~A" line err)
               (is (search "(:pose-when" err) "~A: the entry is not named in ~A" line err)
               (is (search expected err) "~A: ~S not in ~A" line expected err))))
  ;; check reports the same as an error line.
  (multiple-value-bind (out err code) (player-command "check" (pose-when-files "(:pose-when posture.sit squat)"))
    (declare (ignore err))
    (is (= 1 code))
    (is (search "pw-scripts.lisp:3: (:pose-when posture.sit squat): unknown pose squat" out) "~A" out)))

;;;# In the window

(test view-plays-placeholders-with-captions
  (with-window-programs ()
    (let ((screenshot (temporary-png "view-door"))
          (spec (temp-path "door.lisp")))
      (alexandria:write-string-into-file
       (format nil "(in-package :player-user)~%(defspec door ~{~S~^ ~})~%" *door-forms*)
       spec :if-exists :supersede)
      (unwind-protect
           (multiple-value-bind (out err code)
               (view-command (list spec "--size" "320x240" "--frames" "8"
                                   "--screenshot" (namestring screenshot) "--keys" "1@0"))
             (is (= 0 code) "exit ~D, stderr: ~A" code err)
             (is (search "(:op unlock :script unlock :start 0 :end 1)" out) "~A" out)
             (destructuring-bind (&optional width height depth colour-type &rest more)
                 (first (decode-pngs (list screenshot)))
               (declare (ignore depth colour-type))
               (when (eql width 320)
                 (let ((pixels (car (last more)))
                       (layout (player.render::layout-caption "unlock" width height)))
                   (is (< 0.03 (body-pixel-share pixels width height)))
                   ;; The caption box is there, dark, with light letters in it.
                   (destructuring-bind (left top w h) (player.render::caption-layout-box layout)
                     (let ((levels (loop for y from top below (+ top h)
                                         append (loop for x from left below (+ left w)
                                                      collect (aref pixels (* 4 (+ x (* y width))))))))
                       (is (< 100 (count-if (lambda (v) (< v 60)) levels)) "no dark box")
                       (is (< 30 (count-if (lambda (v) (> v 200)) levels)) "no letters")))))))
        (ignore-errors (delete-file screenshot))))))
