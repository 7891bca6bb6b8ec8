;;;; test-simulate.lisp -- `bin/player simulate` and `check` with a script
;;;; library: the trace, the BVH and frames files, and every bad input.

(in-package #:player-tests)

(def-suite* simulate :in player-tests)

(defun temp-path (name)
  "A fresh path NAME under a temporary directory for this test run."
  (let ((directory (format nil "/tmp/player-tests-~D/" (sb-posix:getpid))))
    (ensure-directories-exist directory)
    (concatenate 'string directory name)))

(defun read-lines-as-forms (path)
  "Every line of PATH read as one Lisp form."
  (with-open-file (in path)
    (let ((*read-eval* nil) (*package* (find-package '#:player-user)))
      (loop for line = (read-line in nil) while line collect (read-from-string line)))))

(test simulate-writes-trace-bvh-and-frames
  (let ((bvh (temp-path "anim.bvh"))
        (frames (temp-path "anim.frames")))
    (multiple-value-bind (out err code)
        (player-command "simulate" (fixture "anim.lisp") "--events" "ev-pick,ev-wave,ev-pan,ev-drop"
                        "--fps" "20" "--bvh" bvh "--frames" frames)
      (is (= 0 code) "exit 0 (stderr: ~A)" err)
      (is (string= "" err))
      (let ((lines (lines out)))
        (is (equal "(:event ev-pick :time 0)" (first lines)))
        (is (find "(:op pan :script pan :start 2.5 :end 4.5)" lines :test #'string=)
            "ops last as long as their scripts (pan declares 3 s, its script 2)")
        (is (find (format nil "; wrote ~A" bvh) lines :test #'string=))
        (is (find "; 117 frames at 20 fps over 5.8 s" lines :test #'string=)))
      (let* ((parsed (read-bvh (alexandria:read-file-into-string bvh)))
             (forms (read-lines-as-forms frames)))
        (is (= 117 (length (getf parsed :frames))))
        (is (= 117 (length forms)))
        (is (< (abs (- 0.05 (getf parsed :frame-time))) 1d-9))
        (is (= (length (player::skeleton-joints (player::load-skeleton 'humanoid)))
               (length (getf parsed :nodes))))
        (flet ((ball-parent (form) (getf (rest (assoc 'ball (getf form :objects) :test #'string-equal))
                                         :parent)))
          (is (null (ball-parent (nth 9 forms))) "the ball lies free before the grab at 0.5 s")
          (is (equalp '("anim" "r_wrist") (mapcar #'string-downcase (mapcar #'string (ball-parent (nth 11 forms)))))
              "and hangs from the right hand after it")
          (is (null (ball-parent (nth 110 forms))) "put-down lets it go"))))))

(test simulate-is-deterministic
  (let ((a (temp-path "a.frames")) (b (temp-path "b.frames")))
    (player-command "simulate" (fixture "anim.lisp") "--events" "ev-pick,ev-wave" "--frames" a "--seed" "3")
    (player-command "simulate" (fixture "anim.lisp") "--events" "ev-pick,ev-wave" "--frames" b "--seed" "3")
    (is (string= (alexandria:read-file-into-string a) (alexandria:read-file-into-string b)))))

(test check-reports-script-durations-and-missing-scripts
  (multiple-value-bind (out err code) (player-command "check" (fixture "anim.lisp"))
    (declare (ignore err))
    (is (= 0 code))
    (is (search "warning: op pan declares :duration 3 but its script pan lasts 2 s" out)))
  ;; Scripts the library lacks play placeholder gestures (issue 27), so check
  ;; warns of them and the spec still passes.
  (multiple-value-bind (out err code) (player-command "check" (fixture "anim-missing.lisp"))
    (is (= 0 code) "~A" err)
    (is (search "warning: the script library lacks juggle, deep-bow: they play placeholder gestures" out) "~A" out)))

(test missing-scripts-play-placeholder-gestures
  ;; anim-scripts.lisp has pick-up but neither juggle nor deep-bow: they play
  ;; placeholders, lasting their ops, beside the library's own scripts.
  (multiple-value-bind (out err code)
      (player-command "simulate" (fixture "anim-missing.lisp") "--events" "ev-juggle")
    (is (= 0 code) "~A" err)
    (is (search "(:op juggle :script juggle :start 0 :end 2)" out) "~A" out))
  (let* ((spec (first (player::load-spec (fixture "anim-missing.lisp"))))
         (library (player.performance::spec-script-library spec))
         (filled (player.performance::library-with-placeholders
                  library spec (player:load-skeleton 'humanoid))))
    (is (player:find-script filled 'pick-up) "the library's own script stays")
    (is (eq (player:find-script filled 'pick-up) (player:find-script library 'pick-up)))
    (is (player:find-script filled 'juggle))
    (is (player:find-script filled 'deep-bow))
    (is (null (player:find-script library 'juggle)) "the library read is not changed")
    (is (= 2 (player.performance::script-duration (player:find-script filled 'juggle))) "a placeholder lasts its op")))

(defun simulate-error (&rest arguments)
  "Run simulate with ARGUMENTS; return its stderr and exit code."
  (multiple-value-bind (out err code) (apply #'player-command "simulate" arguments)
    (declare (ignore out))
    (values err code)))

(test simulate-rejects-bad-input
  (flet ((fails (expected-code expected-text &rest arguments)
           (multiple-value-bind (err code) (apply #'simulate-error arguments)
             (is (= expected-code code) "~A: exit ~D, wanted ~D" arguments code expected-code)
             (is (= 1 (length (lines err))) "one line: ~A" err)
             (is (search "player: error:" err))
             (is (search expected-text err) "~S in ~A" expected-text err))))
    (fails 1 "unknown skeleton robot" (fixture "anim.lisp") "--events" "ev-pick" "--body" "robot")
    (fails 1 "no script library file" (fixture "anim.lisp") "--events" "ev-pick" "--scripts" "/nonexistent/lib.lisp")
    (fails 1 "cannot write the BVH file" (fixture "anim.lisp") "--events" "ev-pick" "--bvh" "/proc/no/x.bvh")
    (fails 2 "--fps takes" (fixture "anim.lisp") "--events" "ev-pick" "--fps" "-3")
    (fails 2 "--seed takes" (fixture "anim.lisp") "--events" "ev-pick" "--seed" "x")
    (fails 1 "unknown event" (fixture "anim.lisp") "--events" "ev-nothing")))

(test your-pose-library-keeps-the-shipped-poses
  ;; Yours override the skeleton's shipped poses by name; the others stay.
  (let* ((skeleton (player:load-skeleton 'humanoid))
         (shipped (player.body:shipped-pose-library skeleton))
         (path (temp-path "my-poses.lisp")))
    (with-open-file (out path :direction :output :if-exists :supersede)
      (format out "(defpose arms-raised \"Mine: one arm up.\" (l_shoulder z 90))~%(defpose salute (r_shoulder z -80) (:include bow-down))~%"))
    (let ((mine (player.body::load-pose-library path :skeleton skeleton :fallback shipped)))
      (is (search "Mine" (player.body::pose-definition-documentation (player.body:find-pose mine 'arms-raised)))
          "my arms-raised overrides the shipped one")
      (is (player.body:find-pose mine 'salute))
      (is (eq (player.body:find-pose mine 'bow-down) (player.body:find-pose shipped 'bow-down)) "the shipped bow-down stays")
      (is (not (search "Mine" (or (player.body::pose-definition-documentation (player.body:find-pose shipped 'arms-raised)) "")))
          "the shipped library is not changed")
      (is (member "BOW-DOWN" (mapcar #'string (player.body::pose-library-names mine)) :test #'string-equal)))))
