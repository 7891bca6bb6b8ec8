;;;; test-script-check.lisp -- CHECK finds, before anything plays, every error
;;;; playing a spec's script library would meet (src/performance/
;;;; script-check.lisp): Peedy checks clean; each of six authoring mistakes in
;;;; a copy of Peedy's library gives exactly one error naming the script and
;;;; the file and line, and simulating an op that plays it fails as CHECK
;;;; said; bin/player check's output and exit status.

(in-package #:player-tests)

(def-suite* script-check :in player-tests)

;;;# Cases: Peedy's library plus one bad form, and a spec playing it

(defparameter *script-check-cases*
  ;; (NAME SCRIPT KIND FORM-TEXT ITEM-LINE-OFFSET FRAGMENT)
  ;; ITEM-LINE-OFFSET: the reported line, counted from the bad form's first line:
  ;; the line of the item or step at fault, whether the library reader or CHECK finds it.
  '((unknown-pose bad-pose :motor-call
     "(defscript bad-pose (:duration 1)
  (:at 0.2 :motor (:pose :name no-such-pose)))"
     1 "has no pose no-such-pose")
    (past-limit bad-angle :motor-call
     "(defscript bad-angle (:duration 1)
  (:at 0 :motor (:keyframe :keys ((0.2 ((neck x 10)))
                                  (0.35 ((l_ankle x -124)))))))"
     2 "DOF x of joint l_ankle: -124 degrees is outside its limits -120 to 0")
    (unknown-parameter bad-param :script-library
     "(defscript bad-param (:duration 1)
  (:at 0 :motor (:gaze :target (:object user) :sped 2)))"
     1 "motor function :gaze has no parameter :sped")
    (wrong-type bad-type :script-library
     "(defscript bad-type (:duration 1)
  (:at 0 :motor (:head :action :nod :count \"two\")))"
     1 "motor function :head: :count must be")
    (unknown-joint bad-joint :motor-call
     "(defscript bad-joint (:duration 1)
  (:at 0 :motor (:keyframe :keys ((0.5 ((l_elbo x 10)))))))"
     1 "skeleton parrot has no joint l_elbo")
    (unknown-script bad-director :script-library
     "(defdirector bad-director
  (:start nod)
  (:start no-such-script))"
     2 "no-such-script is not a script of the library")
    (unknown-attach-joint bad-attach :scene-name
     "(defscript bad-attach (:duration 1)
  (:at 0 :play nod)
  (:at 0.5 :attach note :to (:self l_elbo)))"
     2 "has no joint or role l_elbo"))
  "Authoring mistakes CHECK must report, each as one error diagnostic.")

(defun script-check-directory (name)
  "A fresh directory for case NAME, with a copy of Peedy's pose library."
  (let ((directory (format nil "/tmp/player-tests-~D/script-check/~(~A~)/" (sb-posix:getpid) name)))
    (ensure-directories-exist directory)
    (alexandria:copy-file (checkout-file "specs/peedy-poses.lisp")
                          (merge-pathnames "peedy-poses.lisp" directory))
    directory))

(defun write-script-check-case (name script form-text)
  "Write case NAME: lib.lisp (Peedy's library, then FORM-TEXT) and spec.lisp,
a spec SC-NAME on the parrot whose op BAD plays SCRIPT on event EV-BAD (and
which has Peedy's posture, which the library's starting poses name).
Return the spec's path and the line FORM-TEXT starts on."
  (let* ((directory (script-check-directory name))
         (peedy (alexandria:read-file-into-string (checkout-file "specs/peedy-scripts.lisp")))
         (base (if (char= #\Newline (char peedy (1- (length peedy)))) peedy
                   (format nil "~A~%" peedy)))
         (spec-path (merge-pathnames "spec.lisp" directory)))
    (alexandria:write-string-into-file (format nil "~A~A~%" base form-text)
                                       (merge-pathnames "lib.lisp" directory) :if-exists :supersede)
    (alexandria:write-string-into-file
     (format nil "(in-package :player-user)
(defspec sc-~(~A~)
  (:scripts \"lib.lisp\")
  (:body parrot)
  (state-variable posture string stand (fly stand sit))
  (state-variable done boolean false)
  (op bad :script ~(~A~) :add done)
  (event ev-bad :op bad))
" name script)
     spec-path :if-exists :supersede)
    (values spec-path (1+ (count #\Newline base)))))

(defun load-case-spec (path)
  "The spec defined in the spec file PATH."
  (first (player::load-spec path)))

(defun error-diagnostics (diagnostics)
  "The errors among DIAGNOSTICS."
  (remove-if-not #'player.performance::diagnostic-error-p diagnostics))

(defun simulate-case (spec)
  "Simulate SPEC's event EV-BAD and evaluate every frame; the error that
stops it, or NIL when it plays through."
  (handler-case (progn (player::map-simulation-frames (lambda (index time scene)
                                                         (declare (ignore index time scene)))
                                                       (player:simulate spec :events '(ev-bad) :fps 10))
                       nil)
    (error (condition) condition)))

;;;# Peedy

(test peedy-checks-clean
  (let ((spec (load-case-spec (checkout-file "specs/peedy.lisp"))))
    (is (null (player.performance::script-diagnostics spec)) "Peedy's library: no findings at all"))
  (let ((spec (load-case-spec (checkout-file "t/fixtures/anim.lisp"))))
    (let ((diagnostics (player.performance::script-diagnostics spec)))
      (is (null (error-diagnostics diagnostics)))
      (is (equal '(:warning) (mapcar #'player.performance::diagnostic-severity diagnostics))
          "the :duration mismatch of pan is a warning"))))

;;;# Each mistake: one error, at its line; simulate fails as check said

(test each-mistake-is-one-error-at-its-line
  (loop for (name script kind form-text offset fragment) in *script-check-cases*
        do (multiple-value-bind (path form-line) (write-script-check-case name script form-text)
             (let* ((spec (load-case-spec path))
                    (diagnostics (player.performance::script-diagnostics spec))
                    (message (and diagnostics (player::diagnostic-message (first diagnostics)))))
               (is (= 1 (length diagnostics)) "~A: one diagnostic, not ~S" name diagnostics)
               (when diagnostics
                 (is (eq kind (player::diagnostic-kind (first diagnostics))) "~A: kind ~S" name
                     (player::diagnostic-kind (first diagnostics)))
                 (is (eq :error (player.performance::diagnostic-severity (first diagnostics))) "~A is an error" name)
                 (is (search (format nil "lib.lisp:~D:" (+ form-line offset)) message)
                     "~A: file and line ~D in ~S" name (+ form-line offset) message)
                 (is (search (string-downcase (string script)) message) "~A: names ~A in ~S" name script message)
                 (is (search fragment message) "~A: ~S in ~S" name fragment message)
                 (when (eq name 'past-limit)
                   (is (search "the key at 0.35 s: " message) "names the key: ~S" message)))
               ;; What check said is what playing meets.
               (let ((failure (simulate-case spec)))
                 (is (not (null failure)) "~A: simulate must fail as check said" name)
                 (when failure
                   (is (search fragment (princ-to-string failure))
                       "~A: simulate's error ~S, check's ~S" name (princ-to-string failure) fragment)))))))

(test a-valid-extra-script-checks-clean-and-plays
  (multiple-value-bind (path) (write-script-check-case 'good-extra 'good-extra
                                                       "(defscript good-extra (:duration 1)
  (:at 0 :motor (:keyframe :keys ((0.35 ((l_ankle x -120) (neck x 60))))))
  (:at 0 :play nod)
  (:at 0.5 :attach note :to (:self :right-hand))
  (:at 0.2 :motor (:gaze :target (:joint :self :tail))))")
    (let ((spec (load-case-spec path)))
      (is (null (player.performance::script-diagnostics spec)))
      (is (null (simulate-case spec)) "angles at the limits and known names play"))))

(test severities-of-the-existing-kinds
  (dolist (kind '(:unreachable-goal :unused-op :truncated :unreachable-states :shared-channel
                  :duration-mismatch))
    (is (eq :warning (player.performance::diagnostic-severity (player.planner::make-diagnostic kind "x")))))
  (dolist (kind '(:script-library :missing-scripts :motor-call :scene-name))
    (is (eq :error (player.performance::diagnostic-severity (player.planner::make-diagnostic kind "x"))))))

;;;# bin/player check

(test check-command-exit-codes
  (multiple-value-bind (out err code) (player-command "check" (namestring (checkout-file "specs/peedy.lisp")))
    (is (= 0 code) "Peedy: exit 0 (~A)" err)
    (is (string= "" err))
    (is (not (search "error:" out))))
  (loop for (name script nil form-text offset fragment) in (list (first *script-check-cases*)
                                                                  (third *script-check-cases*))
        do (multiple-value-bind (path form-line) (write-script-check-case name script form-text)
             (multiple-value-bind (out err code) (player-command "check" (namestring path))
               (is (= 1 code) "~A: exit 1" name)
               (is (= 1 (length (lines err))) "~A: one stderr line: ~S" name err)
               (is (search "player: error: check found 1 error in spec" err) "~S" err)
               (let ((line (find "error: " (lines out) :test (lambda (prefix line) (eql 0 (search prefix line))))))
                 (is (not (null line)) "~A: an error: line in ~S" name out)
                 (when line
                   (is (search (format nil "lib.lisp:~D:" (+ form-line offset)) line) "~S" line)
                   (is (search fragment line) "~S" line))))))
  (multiple-value-bind (out err code) (player-command "check" (fixture "anim.lisp"))
    (is (= 0 code) "warnings only: exit 0 (~A)" err)
    (is (search "warning: op pan declares" out))))
