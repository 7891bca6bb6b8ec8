;;;; test-sub-form-lines.lisp -- issue 14, item 1: an error about a part of a
;;;; form -- a script's item, a director's step, a pose's clause, an op's
;;;; expression, an event's directive -- names the file and the line of that
;;;; part, not of the top-level form around it, and shows the part.  (A
;;;; :keyframe key that fails on the body is named at its line by CHECK: see
;;;; the past-limit case of test-script-check.lisp.)

(in-package #:player-tests)

(def-suite* sub-form-lines :in player-tests)

(defun error-report (function path)
  "The report of the PLAYER-ERROR FUNCTION signals when called with PATH, or NIL."
  (handler-case (progn (funcall function path) nil)
    (player:player-error (condition) (princ-to-string condition))))

(defparameter *sub-form-mistakes*
  ;; (FILE-NAME LOADER TEXT LINE FRAGMENTS): loading TEXT from FILE-NAME must
  ;; fail with a report starting FILE-NAME:LINE: and holding every FRAGMENT.
  '(("items.lisp" :scripts
     "(defscript wave (:duration 2)
  (:at 0 :motor (:head :action :nod))
  (:at 0.5 :motor (:gaze :target (:object user) :sped 2)))"
     3 ("script wave: motor function :gaze has no parameter :sped" "in (:at 0.5 :motor (:gaze"))
    ("late.lisp" :scripts
     "(defscript wave (:duration 2)
  (:at 0 :motor (:head :action :nod))
  (:at 1 :motor (:head :action :shake))
  (:at 3 :set (x y) 1))"
     4 ("script wave: the item starts at 3, after the script's duration 2" "in (:at 3 :set (x y) 1)"))
    ("critical.lisp" :scripts
     "(defscript wave (:duration 2 :critical ((stroke . 1)))
  (:at stroke :motor (:head :action :nod))
  (:at strok :motor (:head :action :shake)))"
     3 ("unknown critical time strok" "in (:at strok"))
    ("play.lisp" :scripts
     "(defscript nod (:duration 1))
(defscript wave ()
  (:at 0 :play nod)
  (:at 1 :play no-such-script))"
     4 ("script wave: no-such-script is not a script of the library" "in (:at 1 :play no-such-script)"))
    ("director.lisp" :scripts
     "(defscript nod (:duration 1))
(defdirector greet
  (:start nod :as n)
  (:start nod :at (:end n))
  (:start nope :at (:end n 0.5)))"
     5 ("director greet: nope is not a script of the library" "in (:start nope"))
    ("clause.lisp" :poses
     "(defpose wave-hello \"A wave.\"
  (r_shoulder z -150)
  (r_elbow q 10))"
     3 ("joint r_elbow" "q" "in (r_elbow q 10)"))
    ("expression.lisp" :spec
     "(in-package :player-user)
(defspec subform-expression
  (state-variable open boolean false)
  (op open-door
      :precond (not open open)
      :add open)
  (event ev-open :op open-door))"
     5 ("op open-door: NOT takes exactly one expression" "in (not open open)"))
    ("directive.lisp" :spec
     "(in-package :player-user)
(defspec subform-directive
  (state-variable open boolean false)
  (op open-door :add open)
  (event ev-open
    :op open-door
    :if ((and open) :op open-door)
    :state (not open open)))"
     8 ("event ev-open: NOT takes exactly one expression" "in (not open open)")))
  "Mistakes in a part of a form that spans lines, each named at its own line.")

(defun load-mistake (loader path)
  "Load PATH as LOADER says: a script library, a pose library (on the humanoid) or a spec file."
  (ecase loader
    (:scripts (player::load-script-library path))
    (:poses (player.body::load-pose-library path :skeleton (player::load-skeleton 'humanoid)))
    (:spec (load-spec path))))

(test errors-name-the-line-of-the-part-at-fault
  (loop for (name loader text line fragments) in *sub-form-mistakes*
        do (let ((path (temp-path name)))
             (alexandria:write-string-into-file text path :if-exists :supersede)
             (let ((report (error-report (lambda (p) (load-mistake loader p)) path)))
               (is (not (null report)) "~A: no error" name)
               (when report
                 (is (eql 0 (search (format nil "~A:~D: " name line) report))
                     "~A: not at line ~D: ~A" name line report)
                 (dolist (fragment fragments)
                   (is (search fragment report) "~A: ~S not in ~A" name fragment report)))))))

(test the-command-line-names-the-part-too
  ;; The same place reaches the one error line of the CLI.
  (let ((spec (temp-path "cli-item.lisp"))
        (library (temp-path "cli-item-scripts.lisp")))
    (alexandria:write-string-into-file
     "(in-package :player-user)
(defspec cli-item (:scripts \"cli-item-scripts.lisp\")
  (op wave)
  (event ev-wave :op wave))
" spec :if-exists :supersede)
    (alexandria:write-string-into-file
     "(defscript wave (:duration 2)
  (:at 0 :motor (:head :action :nod))
  (:at 0.5 :motor (:head :action :tilt)))
" library :if-exists :supersede)
    (multiple-value-bind (out err code) (player-command "simulate" spec "--events" "ev-wave")
      (declare (ignore out))
      (is (= 1 code))
      (is (eql 0 (search "player: error: cli-item-scripts.lisp:3: script wave: " err)) "~A" err)
      (is (search "(:at 0.5 :motor (:head :action :tilt))" err) "~A" err))))

(test places-match-the-text-or-are-left-out
  ;; Every list of a form maps to where its text starts; text the reader
  ;; rewrites (backquote) or shared structure leaves the form out.
  (let* ((text "(a (b 'c) #(d (e)) \"(x\" #\\( #'f () ; (y
  (g . h))")
         (form (with-standard-io-syntax (read-from-string text)))
         (places (player.spec::sub-form-places (list (list form 0)) text "f")))
    (is (= 6 (hash-table-count places)) "~A places" (hash-table-count places))
    (is (equal '("f" . 3) (gethash (second form) places)))
    (is (equal '("f" . 6) (gethash (second (second form)) places)) "'c is (quote c) at the quote")
    (is (equal '("f" . 14) (gethash (aref (third form) 1) places)) "(e) inside a vector")
    (is (equal '("f" . 42) (gethash (car (last form)) places)) "(g . h) after () and the comment"))
  (let* ((text "(a `(b ,c))")
         (form (with-standard-io-syntax (read-from-string text))))
    (is (zerop (hash-table-count (player.spec::sub-form-places (list (list form 0)) text "f")))))
  (let* ((text "(a #1=(b) #1#)")
         (form (with-standard-io-syntax (read-from-string text))))
    (is (zerop (hash-table-count (player.spec::sub-form-places (list (list form 0)) text "f"))))))
