;;;; test-scenes.lisp -- several characters in one scene (src/cast/): members
;;;; and their places, events reaching only the members they address, two
;;;; Peedys in one scene against two separate runs (traces and poses), the
;;;; errors, scene files as data, the command line, and a drawn frame.

(in-package #:player-tests)

(def-suite* scenes :in player-tests)

(defun load-peedy ()
  "specs/peedy.lisp's spec, loaded afresh."
  (first (load-spec (checkout-file "specs/peedy.lisp"))))

(defun duet ()
  "A two-Peedy scene, LEFT at -0.4 m and RIGHT asleep at +0.4 m, with a scene event."
  (load-peedy)
  (define-cast 'test-duet '("Two Peedys."
                            (peedy :as left :at (-0.4d0 0 0))
                            (peedy :as right :at (0.4d0 0 0) :initial ((alert . snore) (posture . sit)))
                            (event both-search left/ev-search right/ev-search)
                            (event wave (left/ev-hop :after 0) (right/ev-hop :after 1.5)))))

(defun member-trace (ensemble member)
  "The printed trace lines of ENSEMBLE's MEMBER."
  (trace-of (ensemble-controller ensemble member)))

(defun scene-file (name text)
  "Write TEXT to a fresh scene file NAME beside a copy of specs/peedy.lisp; its path."
  (let ((path (temp-path (format nil "scenes/~A" name))))
    (ensure-directories-exist path)
    (with-open-file (out (temp-path "scenes/peedy.lisp") :direction :output :if-exists :supersede)
      (write-string (alexandria:read-file-into-string (checkout-file "specs/peedy.lisp")) out))
    (with-open-file (out path :direction :output :if-exists :supersede)
      (write-string text out))
    path))

;;;# Members

(test members-are-placed-and-share-one-machine
  (let* ((cast (duet))
         (ensemble (make-ensemble cast)))
    (is (equal '("LEFT" "RIGHT") (mapcar (lambda (m) (symbol-name (cast-member-name m))) (cast-members cast))))
    (is (equal '((-0.4d0 0d0 0d0) (0.4d0 0d0 0d0)) (mapcar #'cast-member-position (cast-members cast))))
    (is (eq (player::controller-machine (ensemble-controller ensemble 'left))
            (player::controller-machine (ensemble-controller ensemble 'right)))
        "members of one spec share its compiled machine")
    (is (not (eq (ensemble-controller ensemble 'left) (ensemble-controller ensemble 'right))))
    (is (string= "SNORE" (state-value (ensemble-controller ensemble 'right) 'alert)) "a member's :initial")
    (is (string= "AWAKE" (state-value (ensemble-controller ensemble 'left) 'alert))))
  ;; Without :at, members stand in a row *MEMBER-SPACING* apart, centred.
  (let ((cast (replicate-cast (load-peedy) 3)))
    (is (equal '("PEEDY1" "PEEDY2" "PEEDY3") (mapcar (lambda (m) (symbol-name (cast-member-name m))) (cast-members cast))))
    (is (equal (list (- player.cast::*member-spacing*) 0d0 player.cast::*member-spacing*)
               (mapcar (lambda (m) (first (cast-member-position m))) (cast-members cast))))))

(test namespaced-events-reach-only-their-member
  (let ((ensemble (make-ensemble (duet))))
    (is-true (send-scene-event ensemble 'left/ev-search))
    (is (eq t (state-value (ensemble-controller ensemble 'left) 'holding-note)))
    (is (null (state-value (ensemble-controller ensemble 'right) 'holding-note)))
    (is (notany (lambda (l) (search "(:event" l)) (member-trace ensemble 'right)) "the right one heard nothing")
    (is (equal "(:event ev-search :time 0)" (first (member-trace ensemble 'left))))
    ;; all/ and a scene event reach both; MEMBER+MEMBER/ the two named.
    (send-scene-event ensemble "right/ev-hop")
    (is (= 1 (count-if (lambda (l) (search "(:event ev-hop" l)) (member-trace ensemble 'right))))
    (is (= 0 (count-if (lambda (l) (search "(:event ev-hop" l)) (member-trace ensemble 'left))))
    (send-scene-event ensemble "all/ev-thanks")
    (send-scene-event ensemble "left+right/ev-hop")
    (send-scene-event ensemble 'both-search)
    (loop for member in '(left right)
          for searches in '(2 1)
          for hops in '(1 2)
          do (is (= 1 (count-if (lambda (l) (search "(:event ev-thanks" l)) (member-trace ensemble member))))
             (is (= hops (count-if (lambda (l) (search "(:event ev-hop" l)) (member-trace ensemble member)))
                 "~A: left+right/ev-hop" member)
             (is (= searches (count-if (lambda (l) (search "(:event ev-search" l)) (member-trace ensemble member)))
                 "~A: both-search sends ev-search to both" member))
    ;; A scene event can stagger its members, as a director would: each
    ;; address arrives its :after seconds past the time the event is sent at.
    (is-true (send-scene-event ensemble 'wave :at 40))
    (is (find "(:event ev-hop :time 40)" (member-trace ensemble 'left) :test #'string=))
    (is (find "(:event ev-hop :time 41.5)" (member-trace ensemble 'right) :test #'string=)
        "~S" (member-trace ensemble 'right))
    (multiple-value-bind (text class) (scene-error-text (lambda () (send-scene-event ensemble 'wave)))
      (is (eq 'scene-error class))
      (is (search "scene event wave sends its events :after a time: send it at one, wave@SECONDS" text) "~A" text))
    ;; The trace, member by member, each line tagged.
    (let ((text (with-output-to-string (out) (write-ensemble-trace ensemble out))))
      (is (eql 0 (search "left: (:event ev-search :time 0)" text)))
      (is (search (format nil "~%right: (:autoscript-start snore-loop") text)))))

;;;# A scene plays as its members would alone

(defparameter *duet-scenarios*
  '(("ev-search" "ev-bad-speech" "ev-thanks")
    (("ev-fly-to" . 0d0) ("ev-sit" . 2d0))
    (("ev-search" . 0d0) ("ev-thanks" . 1.5d0) ("ev-hop" . 9d0)))
  "Scenarios played by each member of a scene and by a lone controller: whole
events, and timed ones meeting (a preempting sit, a bow while searching).")

(test two-peedys-trace-as-two-separate-runs
  (let ((cast (duet)))
    (dolist (scenario *duet-scenarios*)
      (let* ((events (loop for entry in scenario
                           append (loop for member in '("left" "right")
                                        for address = (format nil "~A/~A" member (player.spec::event-entry-name entry))
                                        collect (if (consp entry) (cons address (cdr entry)) address))))
             (ensemble (make-ensemble cast :timed (player.cast::scene-timed-members cast events nil))))
        (play-scene-events ensemble events)
        (loop for member in '(left right)
              for initial in '(() ((alert . snore) (posture . sit)))
              do (let ((alone (make-controller (compile-spec 'peedy) :initial-state initial
                                                                     :timed (some #'consp scenario))))
                   (play-events alone scenario)
                   (is (equal (trace-of alone) (member-trace ensemble member))
                       "~A playing ~S differs from a lone run" member scenario)))))))

(test scene-members-move-as-they-would-alone
  ;; The poses of a member's body, frame by frame, are those of a lone
  ;; simulation; only the root stands at the member's place.
  (let* ((cast (duet))
         (scene (simulate-scene cast :events '("all/ev-search") :fps 4))
         (alone (player::simulate 'peedy :events '("ev-search") :fps 4)))
    (let ((member (scene-simulation-member scene 'left)))
      (is (= (player::controller-clock (player.performance::simulation-controller alone)) (player::controller-clock (player.performance::simulation-controller member))))
      (is (= (player.performance::simulation-end scene) (player.performance::simulation-end member)
             (player::controller-clock (player.performance::simulation-controller (scene-simulation-member scene 'right))))
          "the scene ends with its last member, and every member's frames cover it")
      (is (equal (mapcar #'trace-line-string (trace-lines (player.performance::simulation-presenter alone)))
                 (mapcar #'trace-line-string (trace-lines (player.performance::simulation-presenter member)))))
      (dolist (time '(0 0.5 1.25 2.5 3))
        (let ((lone-pose (copy-seq (player::body-pose (find-object
                                                       (player::performance-frame (player.performance::simulation-performance alone) time)
                                                       'peedy)))))
          (simulation-scene-at scene time)
          (let ((body (player.performance::simulation-body member)))
            (is (< (reduce #'max (map 'vector (lambda (a b) (abs (- a b))) lone-pose (player::body-pose body)))
                   1d-6)
                "left's pose at ~A s differs by ~A degrees" time
                (reduce #'max (map 'vector (lambda (a b) (abs (- a b))) lone-pose (player::body-pose body))))
            (is (< (abs (- -0.4d0 (player.body::vec3-x (player::object-world-position body)))) 1d-12))))))
    ;; A frame of the scene holds both bodies, and no camera: one framing them all is used.
    (let ((objects (scene-objects (simulation-scene-at scene 1))))
      (is (equal '("LEFT" "RIGHT") (mapcar (lambda (o) (symbol-name (object-name o)))
                                           (remove :body objects :key #'object-kind :test-not #'eq))))
      ;; One set (issue 27): one camera, the first member's, not one a member.
      (is (= 1 (count :camera objects :key #'object-kind))))))

;;;# Errors

(defun scene-error-text (thunk)
  "The report of the scene error THUNK signals (failing the test when none is signalled), and its class."
  (handler-case (progn (funcall thunk) (fail "no error signalled") (values nil nil))
    (player-error (condition) (values (princ-to-string condition) (class-name (class-of condition))))))

(test scene-errors-are-clear
  (load-peedy)
  (multiple-value-bind (text class) (scene-error-text (lambda () (define-cast 'bad '((peedyy :as a)))))
    (is (eq 'missing-member-spec-error class))
    (is (search "member a plays spec peedyy, which is not defined" text) "~A" text))
  (multiple-value-bind (text class) (scene-error-text (lambda () (define-cast 'bad '((peedy :as a) (peedy :as a)))))
    (is (eq 'duplicate-member-error class))
    (is (search "two members are called a" text) "~A" text))
  (multiple-value-bind (text class) (scene-error-text (lambda () (define-cast 'bad '((peedy) (peedy)))))
    (is (eq 'duplicate-member-error class) "members default to the spec's name: ~A" text))
  (multiple-value-bind (text class) (scene-error-text (lambda () (define-cast 'bad '((peedy :as all)))))
    (is (eq 'scene-error class))
    (is (search "not ALL" text) "~A" text))
  (multiple-value-bind (text class) (scene-error-text (lambda () (define-cast 'bad '((peedy :as a :at (1 2))))))
    (is (eq 'scene-error class))
    (is (search ":at takes (X Y Z)" text) "~A" text))
  (multiple-value-bind (text class) (scene-error-text (lambda () (define-cast 'bad '((peedy :as a) (event e (a/ev-search :later 1))))))
    (is (eq 'scene-error class))
    (is (search "an address is MEMBER/EVENT or (MEMBER/EVENT :after SECONDS)" text) "~A" text))
  (multiple-value-bind (text class) (scene-error-text (lambda () (define-cast 'bad '((peedy :as a) (event e b/ev-search)))))
    (is (eq 'unknown-member-error class))
    (is (search "names member b, which the scene does not have (members: a)" text) "~A" text))
  (let ((ensemble (make-ensemble (duet))))
    (multiple-value-bind (text class) (scene-error-text (lambda () (send-scene-event ensemble "middle/ev-search")))
      (is (eq 'unknown-member-error class))
      (is (search "names member middle, which the scene does not have (members: left, right)" text) "~A" text))
    (multiple-value-bind (text class) (scene-error-text (lambda () (send-scene-event ensemble 'ev-search)))
      (is (eq 'unknown-member-error class))
      (is (search "event ev-search names no member" text) "~A" text))
    (multiple-value-bind (text class) (scene-error-text (lambda () (play-scene-events ensemble '("left/ev-search" "right/ev-nope"))))
      (is (eq 'unknown-event class) "~A" text))
    (is (null (member-trace ensemble 'left)) "a bad address plays nothing, not even the events before it")
    ;; Arguments of the wrong kind are ARGUMENT-ERRORs, before anything is sent.
    (signals argument-error (send-scene-event ensemble "all/ev-search" :at "soon"))
    (signals argument-error (send-scene-event ensemble "all/ev-search" :when-busy :sometimes))
    (signals argument-error (play-scene-events ensemble "all/ev-search"))
    (is (null (member-trace ensemble 'left)))
    (signals argument-error (send-scene-event 42 "all/ev-search"))
    (signals argument-error (make-ensemble 42))
    (signals argument-error (make-ensemble (duet) :timed 3))
    (signals argument-error (simulation-scene-at 42 0))
    (signals argument-error (replicate-cast 'peedy 0))
    (signals argument-error (load-scene-file 42))))

(test scene-file-errors-name-file-and-line
  (multiple-value-bind (text class)
      (scene-error-text (lambda () (load-scene-file (scene-file "missing.lisp" (format nil "(defscene s~%  (peedy :as a)~%  (parrot :as b))~%")))))
    (is (eq 'missing-member-spec-error class))
    (is (search "missing.lisp:3: scene s: member b plays spec parrot, which is not defined and not in a file parrot.lisp beside the scene's" text)
        "~A" text))
  (multiple-value-bind (text class)
      (scene-error-text (lambda () (load-scene-file (scene-file "twice.lisp" (format nil ";; two of a name~%(defscene s~%  (peedy :as a)~%  (peedy :as b)~%  (peedy :as a))~%")))))
    (is (eq 'duplicate-member-error class))
    (is (search "twice.lisp:5: scene s: two members are called a" text) "~A" text))
  ;; Data, never code: #. is refused, and so is any other form.
  (let ((path (scene-file "eval.lisp" "(defscene s (peedy :as #.(error \"ran\")))")))
    (multiple-value-bind (text class) (scene-error-text (lambda () (load-scene-file path)))
      (is (eq 'spec-reader-error class))
      (is (not (search "ran" (subseq text 0 (min 20 (length text))))) "~A" text)))
  (multiple-value-bind (text class)
      (scene-error-text (lambda () (load-scene-file (scene-file "form.lisp" "(defscene s (peedy :as a)) (print 1)"))))
    (is (eq 'spec-syntax-error class))
    (is (search "a scene file holds only in-package, defspec and defscene forms" text) "~A" text)))

(test scene-files-load-their-members-specs
  (remove-spec 'peedy)
  (multiple-value-bind (casts specs) (load-scene-file (checkout-file "specs/two-peedys.lisp"))
    (is (null specs) "peedy comes from peedy.lisp beside it, not from the scene file")
    (is (find-spec 'peedy nil))
    (is (equal '(two-peedys) (mapcar (lambda (c) (intern (symbol-name (cast-name c)) :player-tests)) casts)))
    (is (equal '((-0.2d0 0d0 0d0) (0.5d0 0d0 0d0))
               (mapcar #'cast-member-position (cast-members (first casts)))))))

;;;# The command line

(test cli-runs-scenes
  (multiple-value-bind (out err code)
      (player-command "run" "specs/two-peedys.lisp" "--events" "left/ev-search@0,right/ev-hop@1,duet-hop@8")
    (is (= 0 code) "~A" err)
    (let ((lines (lines out)))
      (is (equal "left: (:event ev-search :time 0)" (first lines)))
      (is (every (lambda (l) (or (eql 0 (search "left: " l)) (eql 0 (search "right: " l)))) lines))
      (is (find "right: (:event ev-hop :time 1)" lines :test #'string=))
      (is (find "left: (:event ev-hop :time 8)" lines :test #'string=) "duet-hop@8 staggers its members")
      (is (find "right: (:event ev-hop :time 8.5)" lines :test #'string=))
      (is (= 1 (count-if (lambda (l) (search "left: (:event ev-hop" l)) lines)))))
  (multiple-value-bind (out err code)
      (player-command "run" "specs/peedy.lisp" "--cast" "peedy:2" "--events" "peedy2/ev-search,all/ev-hop")
    (is (= 0 code) "~A" err)
    (let ((lines (lines out)))
      (is (equal "peedy1: (:event ev-hop :time 0)" (first lines)))
      (is (find "peedy2: (:event ev-hop :time 3)" lines :test #'string=))))
  (multiple-value-bind (out err code) (player-command "run" "specs/two-peedys.lisp" "--events" "middle/ev-search")
    (is (= 1 code))
    (is (string= "" out))
    (is (search "player: error: event address middle/ev-search names member middle" err) "~A" err))
  (multiple-value-bind (out err code) (player-command "run" "specs/peedy.lisp" "--cast" "peedy:0")
    (declare (ignore out))
    (is (= 2 code))
    (is (search "--cast takes SPEC:N" err) "~A" err))
  ;; check takes a scene file: each spec once, under a line naming its members.
  (multiple-value-bind (out err code) (player-command "check" "specs/two-peedys.lisp")
    (is (= 0 code) "~A" err)
    (is (eql 0 (search "; peedy (left, right)" out)) "~A" out))
  ;; A command for one spec says what a scene file is.
  (multiple-value-bind (out err code) (player-command "plans" "specs/two-peedys.lisp")
    (declare (ignore out))
    (is (= 1 code))
    (is (search "two-peedys.lisp:10: a spec file holds only in-package and defspec forms" err) "~A" err)
    (is (search "a file with a defscene is a scene file" err) "~A" err)))

(test scenes-mix-specs
  ;; Members of different specs each get their spec's machine; Newton's cradle
  ;; swings beside a Peedy.
  (load-peedy)
  (load-spec (checkout-file "specs/newtons-cradle.lisp"))
  (let* ((cast (define-cast 'mixed '((peedy :as bird) (newtons-cradle :as toy))))
         (ensemble (make-ensemble cast)))
    (is (= 2 (length (player.cast::ensemble-machines ensemble))))
    (is-true (send-scene-event ensemble "toy/ev-lift-two-left"))
    (is-true (send-scene-event ensemble "bird/ev-search"))
    (is (find-if (lambda (l) (search "(:event ev-lift-two-left" l)) (member-trace ensemble 'toy)))
    (is (notany (lambda (l) (search "ev-lift" l)) (member-trace ensemble 'bird)))
    (multiple-value-bind (text class) (scene-error-text (lambda () (send-scene-event ensemble "all/ev-search")))
      (is (eq 'unknown-event class) "the cradle has no ev-search: ~A" text))
    (is (= 1 (count-if (lambda (l) (search "(:event ev-search" l)) (member-trace ensemble 'bird)))
        "a refused address sends nothing, even to the members that know the event")))

(test cli-simulate-writes-one-bvh-per-body
  (let ((directory (temp-path "scene-bvh/")))
    (multiple-value-bind (out err code)
        (player-command "simulate" "specs/two-peedys.lisp" "--events" "left/ev-search" "--fps" "5" "--bvh" directory)
      (is (= 0 code) "~A" err)
      (is (search "; left: peedy at (-0.2 0 0)" out))
      (loop for (member x) in '(("left" -0.2d0) ("right" 0.5d0))
            for path = (format nil "~A~A.bvh" directory member)
            do (is (search (format nil "; wrote ~A" path) out))
               (let ((parsed (read-bvh (alexandria:read-file-into-string path))))
                 (is (= 16 (length (getf parsed :frames))))
                 (is (< (abs (- x (aref (first (getf parsed :frames)) 0))) 1d-6)
                     "~A's root stands at x = ~A" member x))))))

;;;# Drawing

(test a-drawn-scene-shows-every-member
  ;; The pixels the bodies cover, found by drawing a frame with and without
  ;; them: the left member's in the left half, the right member's in the right.
  (let* ((scene (simulate-scene (duet) :fps 4))
         (width 200) (height 150))
    (call-with-renderer
     width height
     (lambda (renderer)
       (let* ((with (draw renderer (simulation-scene-at scene 0)))
              (without (progn (dolist (object (scene-objects (simulation-scene-at scene 0)))
                                (when (eq (object-kind object) :body)
                                  (setf (player::property-value object 'visible) nil)))
                              (draw renderer (simulation-scene-at scene 0))))
              (left 0) (right 0))
         (dotimes (i (* width height))
           (when (> (pixel-difference with without i) 24)
             (if (< (mod i width) (/ width 2)) (incf left) (incf right))))
         (is (> left 300) "left half: ~D body pixels" left)
         (is (> right 300) "right half: ~D body pixels" right)
         (is (< 1/3 (/ left (max 1 right)) 3) "about as many pixels each: ~D and ~D" left right))))))

(test view-plays-every-member
  ;; A key sends its all/EV to both; a typed address reaches only its member.
  (with-window-programs ()
    (let ((shot (temp-path "scene-view.png")))
      (multiple-value-bind (out err code)
          (view-command (list "specs/two-peedys.lisp" "--frames" "40" "--size" "160x120"
                              "--keys" "3@0" "--screenshot" shot))
        (is (= 0 code) "~A" err)
        (let ((lines (lines out)))
          (is (find "1 duet-search" lines :test #'string=) "the scene's own events come first in the key map")
          (is (find "2 duet-hop" lines :test #'string=))
          (is (find "3 all/ev-search" lines :test #'string=))
          (is (find-if (lambda (l) (eql 0 (search "left: (:event ev-search :time" l))) lines))
          (is (find-if (lambda (l) (eql 0 (search "right: (:event ev-search :time" l))) lines)))
        (is (probe-file shot))))
    (multiple-value-bind (out err code)
        (view-command (list "specs/two-peedys.lisp" "--frames" "30" "--size" "160x120")
                      :input (format nil "right/ev-hop~%middle/ev-hop~%"))
      (is (= 0 code) "~A" err)
      (let ((lines (lines out)))
        (is (find-if (lambda (l) (eql 0 (search "right: (:event ev-hop :time" l))) lines) "~A" out)
        (is (notany (lambda (l) (eql 0 (search "left: (:event ev-hop" l))) lines))
        (is (find "; no event middle/ev-hop: type one of the names above" lines :test #'string=))))))

;;;# The C++ backend: two instances in one program

(test c++-example-runs-two-instances
  ;; examples/embed-cpp-scene/main.cpp, compiled with Peedy's generated
  ;; controller (cached by content, as `run --backend c++` caches), runs two
  ;; independent Controllers; each address reaches only the members it names.
  (let ((main (alexandria:read-file-into-string (checkout-file "examples/embed-cpp-scene/main.cpp"))))
    (multiple-value-bind (header source) (player.cpp::c++-sources (compile-spec (load-peedy)) "peedy" "peedy")
      (let* ((directory (merge-pathnames (format nil "scene-example-~A/"
                                                 (player.cpp::content-key header source main player::*c++-flags*))
                                         (player.cpp::c++-cache-root)))
             (executable (merge-pathnames "peedy-scene" directory)))
        (unless (probe-file executable)
          (ensure-directories-exist directory)
          (loop for (name text) in `(("peedy.hpp" ,header) ("peedy.cpp" ,source) ("main.cpp" ,main))
                do (with-open-file (out (merge-pathnames name directory) :direction :output :if-exists :supersede)
                     (write-string text out)))
          (player.cpp::compile-c++ directory '("main.cpp" "peedy.cpp") "peedy-scene"))
        (multiple-value-bind (code out) (player.cpp::run-program-capturing (namestring executable) '())
          (is (eql 0 code))
          (let ((lines (lines out)))
            (is (find "left:   0.00  event ev-search" lines :test #'string=) "~A" out)
            (is (find "right:   0.00  event ev-thanks" lines :test #'string=))
            (is (notany (lambda (l) (search "right:   0.00  event ev-search" l)) lines)
                "left/ev-search reaches only left")
            (is (find "left:   3.00  event ev-hop" lines :test #'string=) "all/ev-hop reaches left ...")
            (is (find "right:  11.75  event ev-hop" lines :test #'string=) "... and right, each on its own clock")
            (is (search "right: (:state (holding-note . nil) (posture . stand) (alert . awake)" out))))))))
