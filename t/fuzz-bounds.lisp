;;;; fuzz-bounds.lisp -- hostile but short inputs for the bounds of issue 31:
;;;; huge-but-short reader forms, fast clocks, fan-out (macro-ops, :play,
;;;; pose :include), exponential phrases, odd WAVs, control-character
;;;; names, exact macro-ops whose proof splits their start states finely, and
;;;; wide or large-domain specs whose planning passes its budget.
;;;; Each case is a small file run through bin/player under a time and
;;;; memory watch: it must finish or give its one "player: error: ..." line
;;;; within *FZB-SECONDS* seconds and *FZB-MEGABYTES* MB of resident memory.
;;;; `make fuzz` runs FUZZ_BOUNDS_CASES (200) of them (fuzz-main.lisp); the
;;;; suite `bounds` a few.

(in-package #:player-tests)

(in-suite bounds)

(defparameter *fzb-seconds* 10 "The longest a bounds case may run.")
(defparameter *fzb-megabytes* 2048 "The most resident memory a bounds case may use.")

(defun fzb-pick (state list) "An element of LIST drawn with STATE." (nth (random (length list) state) list))

(defun fzb-spec (value)
  "A spec file's text whose state variable X starts at VALUE (text)."
  (format nil "(defspec fz (state-variable x boolean ~A) (op o :add x) (event ev :op o))~%" value))

(defun fzb-reader-form (state)
  "A short text asking the reader for much: a count, rank, token or chain."
  (let ((n (expt 10 (+ 3 (random 8 state)))))
    (fzb-spec
     (ecase (random 9 state)
       (0 (format nil "#~DA()" n))
       (1 (format nil "#~D*1" n))
       (2 (format nil "#~D(1)" n))
       (3 (make-string (+ 1000 (random 300000 state)) :initial-element #\7))
       (4 (format nil "#36r~A" (make-string (+ 1000 (random 300000 state)) :initial-element #\Z)))
       (5 (format nil "~A/3" (make-string (+ 1000 (random 300000 state)) :initial-element #\9)))
       (6 (format nil "~Ax" (repeated (+ 50 (random 50000 state)) "#+sbcl ")))
       (7 (format nil "~Ax" (repeated (+ 50 (random 50000 state)) (fzb-pick state '("'" "#'" "`" "#." "#p")))))
       (8 (with-output-to-string (s)
            (format s "(#1=(x x) ")
            (loop for i from 2 to (+ 10 (random 50 state)) do (format s "#~D=(#~D# #~D#) " i (1- i) (1- i)))
            (format s ")")))))))

(defun fzb-fast-clock (state)
  "A spec whose timer ticks (or a script whose blink fires) absurdly often."
  (let ((period (fzb-pick state '("1d-9" "1d-12" "1/1000000" "0.0009" "5d-324" "1d-3"))))
    (if (zerop (random 2 state))
        (format nil "(defspec fz (state-variable x boolean false) (event ev) (timer tick :after ~A :event ev :repeat t))~%"
                period)
        (format nil "(defspec fz (:scripts \"fz-scripts.lisp\") (:body parrot) (state-variable x boolean false)
  (op blinky :duration 2 :add x) (event ev :op blinky))~%;;; fz-scripts.lisp~%(defscript blinky (:duration 2) (:at 0 :motor (:blink :mean-interval ~A)))~%"
                period))))

(defun fzb-fan-out (state)
  "A chain of macro-ops (or scripts) each running the one before twice."
  (let ((levels (+ 8 (random 40 state))))
    (if (zerop (random 2 state))
        (doubling-macro-spec levels)
        (format nil "(defspec fz (:scripts \"fz-scripts.lisp\") (:body parrot) (state-variable x boolean false)
  (op s~D :duration 1 :add x) (event ev :op s~:*~D))~%;;; fz-scripts.lisp~%~A"
                levels (doubling-play-library levels)))))

(defun fzb-control-name (state)
  "A spec naming an op with a control character in it."
  (let ((char (code-char (fzb-pick state '(0 7 8 10 13 27 127 155 #x2028)))))
    (format nil "(defspec fz (state-variable x boolean false) (op |go~A(:op fake)| :add x) (event ev :op |go~A(:op fake)|))~%"
            char char)))

(defun fzb-odd-wav (state)
  "The bytes of a WAV file with odd header fields."
  (wav-octets :rate (fzb-pick state '(0 1 7999 96001 4294967295 8000))
              :channels (fzb-pick state '(0 1 2 3 65535))
              :bits (fzb-pick state '(8 16))
              :data (loop repeat (* 2 (random 20 state)) collect (random 256 state))))

(defun fzb-proof (state)
  "A spec whose exact macro-op's proof splits its start states VALUES ways at
each of STEPS sub-ops, then may walk a long :seq (SPLITTING-MACRO-SPEC).  Its
states times ops stay under 5 x 10^8, so planning it is quick and the proof
does the work (planning takes about a nanosecond per state and op)."
  (let* ((steps (+ 2 (random 5 state)))
         (most (loop for v from 2
                     while (< (* (expt (* 2 v) steps) 16 (* steps (1+ v))) 500000000)
                     finally (return (1- v))))
         (values (+ 2 (random (max 1 (1- most)) state))))
    (splitting-macro-spec steps values :name "fz" :semantics (fzb-pick state '(:exact :exact :declared))
                                       :tail (fzb-pick state '(0 0 10 1000 5000))
                                       :copies (fzb-pick state '(1 1 2 5))
                                       :wrappers (zerop (random 2 state)))))

(defun token-ring-spec (count &key (name "ring") option)
  "A spec of COUNT booleans, a token moving around them, and an event
achieving each: COUNT goals over COUNT reachable states of 2 x COUNT bits, so
its planning work grows as COUNT cubed (PLANNING-STEP-COST grows with COUNT).
OPTION, a string, is put in the defspec's head."
  (with-output-to-string (s)
    (format s "(defspec ~A (:state-space :reachable)~@[ ~A~]~%  (state-variable b0 boolean true)~%" name option)
    (loop for i from 1 below count do (format s "  (state-variable b~D boolean false)~%" i))
    (loop for i below count do (format s "  (op mv~D :precond b~D :sub b~D :add b~D)~%" i i i (mod (1+ i) count)))
    (loop for i below count do (format s "  (event e~D :state b~D)~%" i i))
    (format s ")~%")))

(defun domain-grid-spec (values variables)
  "A spec of VARIABLES variables of VALUES values each, an op per value moving
each along its values, and up to 40 events each achieving one value of all:
large domains, so wide states with few variables."
  (with-output-to-string (s)
    (format s "(defspec fz~%")
    (loop for k below variables
          do (format s "  (state-variable a~D string v0 (~{v~D~^ ~}))~%" k (loop for v below values collect v))
             (loop for v below values
                   do (format s "  (op set~D-~D :precond a~D.v~D :add a~D.v~D)~%" k v k (mod (1+ v) values) k v)))
    (loop for v below values by (max 1 (floor values 40))
          do (format s "  (event e~D :state (and~{ a~D.v~D~}))~%" v (loop for k below variables append (list k v))))
    (format s ")~%")))

(defun fzb-planning (state)
  "A spec whose planning is long: a token ring of up to 600 booleans (the
reachable regime, its work growing as the cube of its size), or 1 to 3
variables of up to 4,000 values (wide states, the full space)."
  (if (zerop (random 2 state))
      (token-ring-spec (+ 50 (random 550 state)) :name "fz")
      (let ((variables (+ 1 (random 3 state))))
        (domain-grid-spec (+ 20 (random (ecase variables (1 4000) (2 400) (3 60)) state)) variables))))

(defun fzb-case (seed index)
  "Case INDEX of SEED: (VALUES KIND FILES ARGUMENTS INPUT), FILES an alist of a
file name to its text or octets, ARGUMENTS bin/player's (FILE names relative
to the case's folder), INPUT standard input's text or NIL."
  (let* ((state (sb-ext:seed-random-state (+ (* seed 1000003) index)))
         (kind (fzb-pick state '(:reader :clock :fan-out :phrases :wav :name :proof :planning))))
    (flet ((spec-case (text arguments)
             ;; A ;;; fz-scripts.lisp line splits a spec from its script library.
             (let ((split (search ";;; fz-scripts.lisp" text)))
               (values kind
                       (if split
                           (list (cons "fz.lisp" (subseq text 0 split))
                                 (cons "fz-scripts.lisp" (subseq text (+ split (length ";;; fz-scripts.lisp")))))
                           (list (cons "fz.lisp" text)))
                       arguments nil))))
      (ecase kind
        (:reader (spec-case (fzb-reader-form state) (list (fzb-pick state '("check" "run" "plans")) "fz.lisp")))
        (:clock (spec-case (fzb-fast-clock state)
                           (list "run" "fz.lisp" "--events" "ev@0" "--at" (fzb-pick state '("1" "10" "100")))))
        (:fan-out (spec-case (fzb-fan-out state) (list (fzb-pick state '("check" "plans")) "fz.lisp")))
        (:proof (spec-case (fzb-proof state) (list (fzb-pick state '("check" "plans")) "fz.lisp")))
        (:planning (spec-case (fzb-planning state) (list (fzb-pick state '("check" "plans")) "fz.lisp")))
        (:name (spec-case (fzb-control-name state) (list "run" "fz.lisp" "--events" "ev")))
        (:wav (values kind (list (cons "fz.wav" (coerce (fzb-odd-wav state) '(vector (unsigned-byte 8)))))
                      (list "chat" (namestring (checkout-file "specs/peedy-dialogue.lisp")) "--wav" "fz.wav") nil))
        (:phrases
         (let ((count (+ 10 (random 40 state))))
           (values kind '() (list "chat" :peedy-dialogue
                                  (format nil "(utterance evThanks \"many\" ~A)"
                                          (repeated count "(:optional timeref)" " ")))
                   (format nil "many~A~%" (repeated (+ 5 (random 20 state)) " next later")))))))))

(defun fzb-run (arguments directory input)
  "Run bin/player ARGUMENTS in DIRECTORY under /usr/bin/time and a timeout:
(VALUES EXIT STDERR SECONDS MEGABYTES), EXIT :TIMEOUT when it ran too long."
  (ensure-player-core)
  (let* ((err (make-string-output-stream))
         (start (get-internal-real-time))
         (process (sb-ext:run-program "/usr/bin/timeout"
                                      (list* "-s" "KILL" (princ-to-string (* 2 *fzb-seconds*))
                                             "/usr/bin/time" "-f" "fzb-rss %M"
                                             (namestring (checkout-file "bin/player")) arguments)
                                      :input (and input (make-string-input-stream input))
                                      :output nil :error err :search nil :directory directory))
         (seconds (/ (- (get-internal-real-time) start) internal-time-units-per-second))
         (text (get-output-stream-string err))
         (rss-at (search "fzb-rss " text :from-end t))
         (megabytes (and rss-at (/ (or (parse-integer text :start (+ rss-at 8) :junk-allowed t) 0) 1024.0)))
         (stderr (string-right-trim '(#\Newline) (subseq text 0 (or rss-at (length text)))))
         ;; /usr/bin/time reports a signal on a line of its own.
         (stderr (let ((lines (remove-if (lambda (l) (eql 0 (search "Command " l))) (lines stderr))))
                   (format nil "~{~A~^~%~}" lines)))
         (exit (sb-ext:process-exit-code process)))
    (values (if (or (= exit 137) (> seconds (* 2 *fzb-seconds*))) :timeout exit) stderr seconds megabytes)))

(defun fzb-problems (exit stderr seconds megabytes)
  "What is wrong with a bounds case that ended so."
  (let ((lines (lines stderr)) (problems '()))
    (unless (member exit '(0 1 2)) (push (format nil "exit ~A" exit) problems))
    (when (> seconds *fzb-seconds*) (push (format nil "took ~,1F s" seconds) problems))
    (when (and megabytes (> megabytes *fzb-megabytes*)) (push (format nil "used ~,0F MB" megabytes) problems))
    (cond ((rest lines) (push "stderr has more than one line" problems))
          ((and lines (not (eql 0 (search "player: error: " (first lines)))))
           (push "stderr line is not \"player: error: ...\"" problems)))
    (nreverse problems)))

(defun fuzz-bounds (&key (seed 1) (cases 200) progress)
  "Run CASES bounds cases of SEED; a list of (INDEX KIND ARGUMENTS PROBLEMS SECONDS MEGABYTES), worst last."
  (let ((results '()))
    (dotimes (index cases (nreverse results))
      (multiple-value-bind (kind files arguments input) (fzb-case seed index)
        (let ((directory (format nil "/tmp/player-fuzz-bounds-~D-~D/" (sb-posix:getpid) index)))
          (ensure-directories-exist directory)
          (unwind-protect
               (let ((arguments
                       (if (eq (second arguments) :peedy-dialogue)
                           (list "chat" (scratch-peedy-dialogue (third arguments)))
                           arguments)))
                 (loop for (name . content) in files
                       do (if (stringp content)
                              (alexandria:write-string-into-file content (concatenate 'string directory name)
                                                                 :if-exists :supersede :external-format :utf-8)
                              (alexandria:write-byte-vector-into-file content (concatenate 'string directory name)
                                                                      :if-exists :supersede)))
                 (multiple-value-bind (exit stderr seconds megabytes) (fzb-run arguments directory input)
                   (push (list index kind arguments (fzb-problems exit stderr seconds megabytes) seconds megabytes
                               (subseq stderr 0 (min 200 (length stderr))))
                         results)))
            (uiop:delete-directory-tree (pathname directory) :validate t :if-does-not-exist :ignore))
          (when progress (write-char #\. progress) (force-output progress)))))))

(defun fuzz-bounds-report (results &optional (stream *standard-output*))
  "Print RESULTS of FUZZ-BOUNDS by kind, the slowest and largest, and every failure; the number of failures."
  (format stream "~&~%Bounds: ~D hostile short inputs~%  ~10A ~6@A ~8@A ~10@A ~8@A~%" (length results)
          "kind" "cases" "failed" "slowest s" "most MB")
  (dolist (kind '(:reader :clock :fan-out :phrases :wav :name :proof :planning))
    (let ((mine (remove kind results :key #'second :test-not #'eq)))
      (when mine
        (format stream "  ~10A ~6D ~8D ~10,1F ~8,0F~%" (string-downcase kind) (length mine)
                (count-if #'fourth mine) (reduce #'max mine :key #'fifth)
                (reduce #'max mine :key (lambda (r) (or (sixth r) 0)))))))
  (let ((failed (remove-if-not #'fourth results)))
    (dolist (result failed)
      (destructuring-bind (index kind arguments problems seconds megabytes stderr) result
        (format stream "  case ~D (~(~A~)): ~{~A~^; ~} (~,1F s, ~,0F MB)~%    bin/player ~{~A~^ ~}~%    ~A~%"
                index kind problems seconds (or megabytes 0) (mapcar #'fz-visible arguments) (fz-visible stderr))))
    (length failed)))

(test bounds-fuzz-sample
  ;; A few cases of `make fuzz`'s bounds run: each within its time and memory.
  (let ((results (fuzz-bounds :seed 31 :cases (sweep-count 6 3))))
    (dolist (result results)
      (is (null (fourth result)) "case ~D (~A): ~{~A~^; ~} -- ~A" (first result) (second result)
          (fourth result) (seventh result)))))
