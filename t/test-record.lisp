;;;; test-record.lisp -- recorded traces as regression tests: `bin/player
;;;; record` then `verify` agree, the shipped recordings of Peedy's scenarios
;;;; (t/golden/*.trace) still verify, and a changed spec, a moved frame or a
;;;; corrupt recording is reported in plain words.
;;;;
;;;; After an intended change of Peedy's behaviour, regenerate the shipped
;;;; recordings with (player-tests::regenerate-golden-traces) and read the diff
;;;; before committing; each is the `bin/player record` command in *GOLDEN-TRACES*.

(in-package #:player-tests)

(def-suite* record :in player-tests)

(defparameter *golden-traces*
  '(("peedy-paper.trace" "--initial" "alert=snore,posture=sit"
     "--events" "ev-search,ev-search,ev-bad-speech,ev-thanks")
    ("peedy-fly-then-sit.trace" "--events" "ev-fly-to@0,ev-sit@2")
    ("peedy-applause-frames.trace" "--events" "ev-applause" "--frames" "--fps" "4"))
  "The shipped recordings under t/golden/: each file's name and the options
`bin/player record specs/peedy.lisp` makes it with.")

(defun golden-trace (name)
  "The path of the shipped recording NAME as a string."
  (namestring (checkout-file (format nil "t/golden/~A" name))))

(defun regenerate-golden-traces ()
  "Record every scenario of *GOLDEN-TRACES* again into t/golden/, through
`bin/player record`; returns the files written."
  (loop for (name . options) in *golden-traces*
        collect (multiple-value-bind (out err code)
                    (apply #'player-command "record" "specs/peedy.lisp"
                           (append options (list "--out" (format nil "t/golden/~A" name))))
                  (declare (ignore out))
                  (unless (= 0 code) (error "recording ~A failed: ~A" name err))
                  (golden-trace name))))

(defun temp-copy-with (source name old new)
  "Copy the file SOURCE to the temporary file NAME, its first OLD text replaced by NEW; the copy's path."
  (let* ((text (alexandria:read-file-into-string source))
         (at (search old text))
         (path (temp-path name)))
    (assert at () "~A not in ~A" old source)
    (alexandria:write-string-into-file (concatenate 'string (subseq text 0 at) new (subseq text (+ at (length old))))
                                       path :if-exists :supersede)
    path))

(defun mini-scenario ()
  "The command-line options of a small scenario of the mini fixture."
  '("--initial" "alert=snore,posture=sit" "--events" "ev-search,ev-search,ev-thanks"))

;;;# Round trip

(test record-then-verify-is-ok
  (let ((trace (temp-path "mini.trace")))
    (multiple-value-bind (out err code)
        (apply #'player-command "record" (fixture "mini.lisp") (append (mini-scenario) (list "--out" trace)))
      (is (= 0 code) "record: exit ~D (~A)" code err)
      (is (search "; recorded 19 trace lines in" out) "~A" out))
    (multiple-value-bind (out err code) (player-command "verify" (fixture "mini.lisp") trace)
      (is (= 0 code) "verify: exit ~D (~A)" code err)
      (is (string= (format nil "ok: 19 lines match~%") out)))
    (let ((recording (read-recording trace)))
      (is (equal (player::recording-lines recording)
                 (multiple-value-bind (out) (apply #'player-command "run" (fixture "mini.lisp") (mini-scenario))
                   (lines out)))
          "the recorded lines are what `run` prints")
      (let ((spec-file (player.traces::recording-spec-file recording)))
        ;; Relative to the recording when they share more than /, else absolute.
        (is (equal (truename (fixture "mini.lisp"))
                   (truename (merge-pathnames spec-file (directory-namestring (pathname trace)))))
            "the header names the spec file, relative to the recording or absolute: ~A" spec-file))
      (is (verification-ok-p (verify-recording trace)) "the Lisp API finds the spec through the header"))))

(test record-in-lisp
  (with-spec (spec tiny (state-variable up boolean false)
                   (op rise :add up :duration 2) (op fall :sub up)
                   (event ev-rise :state up) (event ev-fall :state (not up)))
    (let* ((path (temp-path "tiny.trace"))
           (recording (record-scenario spec :events '(ev-rise (ev-fall . 1)) :when-busy :preempt :out path))
           (read (read-recording path)))
      (is (equal '("(:event ev-rise :time 0)" "(:op rise :script rise :start 0 :end 2)"
                   "(:cut rise :time 2 :by ev-fall :end 2)" "(:event ev-fall :time 2)")
                 (subseq (recording-lines recording) 0 4)))
      (is (equal (recording-lines recording) (recording-lines read)))
      (is (eq :preempt (player.traces::recording-when-busy read)))
      (is (null (player.traces::recording-spec-file read)) "a spec defined in Lisp has no file")
      (is (verification-ok-p (verify-recording recording :spec spec)))
      (is (string= (format nil "ok: ~D lines match" (length (recording-lines recording)))
                   (verification-message (verify-recording read :spec 'tiny))))
      (signals recording-error (verify-recording read)))))

;;;# The shipped recordings

(test golden-traces-verify
  (dolist (entry *golden-traces*)
    (let ((trace (golden-trace (first entry))))
      (is (probe-file trace) "~A is missing: run (player-tests::regenerate-golden-traces)" trace)
      (multiple-value-bind (out err code) (player-command "verify" "specs/peedy.lisp" trace)
        (is (= 0 code) "~A: exit ~D, ~A" (first entry) code err)
        (is (alexandria:starts-with-subseq "ok: " out) "~A" out)))))

(test golden-traces-hold-the-papers-scenarios
  (let ((paper (read-recording (golden-trace "peedy-paper.trace")))
        (timed (read-recording (golden-trace "peedy-fly-then-sit.trace")))
        (frames (read-recording (golden-trace "peedy-applause-frames.trace"))))
    (is (equal "(:op sit :script sit :start 19.25 :end 20.75)" (nth 22 (recording-lines paper))))
    (is (equal "../../specs/peedy.lisp" (player.traces::recording-spec-file paper))
        "the spec file is recorded relative to the recording")
    (is (find "(:cut fly-loop :time 2 :by ev-sit :end 2)" (recording-lines timed) :test #'string=))
    (is (equal '(("EV-FLY-TO" . 0d0) ("EV-SIT" . 2d0))
               (mapcar (lambda (e) (cons (symbol-name (car e)) (cdr e))) (player.traces::recording-events timed))))
    (is (< 1 (length (recording-frames frames)) 12) "a few frames: ~D" (length (recording-frames frames)))
    (is (verification-ok-p (verify-recording (golden-trace "peedy-applause-frames.trace")))
        "the Lisp API verifies frames, the spec found through the header")))

;;;# Differences

(test verify-catches-a-changed-spec
  (let ((trace (temp-path "mini-changed.trace"))
        (changed (temp-copy-with (fixture "mini.lisp") "mini-changed.lisp" ":duration 2.5" ":duration 3")))
    (apply #'player-command "record" (fixture "mini.lisp") (append (mini-scenario) (list "--out" trace)))
    (multiple-value-bind (out err code) (player-command "verify" changed trace)
      (is (= 1 code))
      (is (string= "" out))
      (is (string= (format nil "player: error: ~A: trace line 9 (file line 24): expected (:op search :script stream :start 4 :end 6.5), got (:op search :script stream :start 4 :end 7)~%" trace)
                   err)))))

(test verify-catches-changed-lines-and-counts
  (let ((trace (temp-path "mini-short.trace"))
        (changed (temp-copy-with (fixture "mini.lisp") "mini-short.lisp"
                                 "(event ev-search :op search)" "(event ev-search :state holding-note)")))
    (apply #'player-command "record" (fixture "mini.lisp") (append (mini-scenario) (list "--out" trace)))
    (let* ((verification (verify-recording trace :spec-file changed))
           (difference (verification-difference verification)))
      (is (not (verification-ok-p verification)))
      (is (eq :line (recording-difference-kind difference)))
      (is (alexandria:starts-with-subseq
           "trace line 12 (file line 27): expected (:op drop-note :script drop-note :start 6.5 :end 7.5), got (:state (holding-note . t) "
           (verification-message verification))
          "~A" (verification-message verification)))
    (let* ((recording (read-recording trace))
           (longer (progn (setf (player::recording-lines recording)
                                (append (player::recording-lines recording) (list "(:event ev-extra :time 99)")))
                          (verify-recording recording :spec-file (fixture "mini.lisp")))))
      (is (string= "the recording has 20 trace lines, the replay 19; the first missing is line 20: (:event ev-extra :time 99)"
                   (verification-message longer))))))

(defun perturbed-frames-recording (delta)
  "The shipped frames recording with frame 2's neck's first DOF moved by DELTA, as a RECORDING."
  (let* ((recording (read-recording (golden-trace "peedy-applause-frames.trace")))
         (frame (nth 2 (recording-frames recording)))
         (peedy (first (getf frame :bodies)))
         (neck (find "NECK" (getf (rest peedy) :joints) :key (lambda (j) (symbol-name (first j))) :test #'string=))
         (dofs (getf (rest neck) :dofs)))
    (incf (second dofs) delta)
    recording))

(test verify-compares-frames-within-a-tolerance
  (let ((beyond (verify-recording (perturbed-frames-recording 0.01d0)))
        (within (verify-recording (perturbed-frames-recording 0.00001d0))))
    (is (not (verification-ok-p beyond)))
    (is (eq :frame (recording-difference-kind (verification-difference beyond))))
    (is (search "frame 2 at 0.6 s (file line " (verification-message beyond)) "~A" (verification-message beyond))
    (is (search "body peedy, joint neck, dof x: expected " (verification-message beyond)) "~A" (verification-message beyond))
    (is (search "(tolerance 0.0001)" (verification-message beyond)))
    (is (verification-ok-p within) "~A" (verification-message within))
    (is (verification-ok-p (verify-recording (perturbed-frames-recording 0.01d0) :tolerance 0.1))))
  ;; The same through the command line, on a perturbed copy of the file.
  (let ((trace (temp-path "frames-moved.trace")))
    (write-recording (perturbed-frames-recording 0.01d0) trace)
    (multiple-value-bind (out err code) (player-command "verify" "specs/peedy.lisp" trace)
      (declare (ignore out))
      (is (= 1 code))
      (is (search "frames-moved.trace: frame 2 at 0.6 s (file line " err) "~A" err)
      (is (search "joint neck, dof x" err) "~A" err))
    (multiple-value-bind (out err code) (player-command "verify" "specs/peedy.lisp" trace "--tolerance" "0.1")
      (is (= 0 code) "~A" err)
      (is (search "frames match (tolerance 0.1)" out) "~A" out))))

;;;# Corrupt recordings

(defun recording-error-text (text)
  "The message of the RECORDING-ERROR that reading a recording file holding TEXT signals, or NIL."
  (let ((path (temp-path "corrupt.trace")))
    (alexandria:write-string-into-file text path :if-exists :supersede)
    (handler-case (progn (read-recording path) nil)
      (recording-error (e) (princ-to-string e)))))

(test corrupt-recordings-are-clear-errors
  (let ((header (format nil "(:recording :version 1 :spec mini :events (ev-search))~%")))
    (flet ((fails (text expected)
             (let ((message (recording-error-text text)))
               (is (and message (search expected message)) "~S: ~A" expected message)
               (is (and message (alexandria:starts-with-subseq (temp-path "corrupt.trace") message))
                   "names the file: ~A" message))))
      (fails "" "the file is empty")
      (fails (format nil "(:event ev-search :time 0)~%") ":1: a recording begins with its header")
      (fails (format nil "~A(:event ev-search :time 0~%" header) ":2: cannot read form: the form is not finished")
      (fails (format nil "~A(:event #.(error \"x\") :time 0)~%" header) ":2: cannot read form")
      (fails (format nil "~A~%~%42~%" header) ":4: not a trace line such as (:event ev :time 0): 42")
      (fails (format nil "(:recording :version 1 :spec mini~% :at -1)~%") ":1: the header's :at must be NIL or a number of seconds from 0, not -1")
      (fails (format nil "(:recording :version 2 :spec mini)~%") ":1: the header's :version must be 1")
      (fails (format nil "(:recording :version 1 :spec mini :colour red)~%") "unknown field :colour")
      (fails (format nil "~A(:frame 0 :time 0)~%" header) ":2: a frame, but the header says :frames nil")))
  (multiple-value-bind (out err code) (player-command "verify" (fixture "mini.lisp") (fixture "mini.lisp"))
    (declare (ignore out))
    (is (= 1 code))
    (is (search "mini.lisp:1: a recording begins with its header (:recording :version 1 ...), not (in-package :player-user)" err) "~A" err)))
