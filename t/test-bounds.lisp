;;;; test-bounds.lisp -- small hostile inputs ask for unbounded work or memory
;;;; (issue 31, item 3): each is refused at load with one error naming what it
;;;; asked for, in bounded time, in process or through bin/player (with its
;;;; one error line); test-bounds-agree.lisp holds the rest of the issue's causes.

(in-package #:player-tests)

(def-suite* bounds :in player-tests)

(defun repeated (count text &optional (separator ""))
  "TEXT COUNT times, joined by SEPARATOR."
  (with-output-to-string (out)
    (dotimes (i count)
      (when (plusp i) (write-string separator out))
      (write-string text out))))

(defun spec-around (value)
  "A spec whose one state variable has initial VALUE (text)."
  (format nil "(defspec huge (state-variable x boolean ~A))" value))

(defmacro check-quick-load-error (seconds class fragment text)
  "Like CHECK-LOAD-ERROR, and the refusal takes less than SECONDS."
  (let ((start (gensym "START")))
    `(let ((,start (get-internal-real-time)))
       (check-load-error ,class ,fragment ,text)
       (is (< (/ (- (get-internal-real-time) ,start) internal-time-units-per-second) ,seconds)
           "refusing ~S took too long" (subseq ,text 0 (min 60 (length ,text)))))))

(test reader-counts-are-bounded-before-allocation
  (check-quick-load-error 2 spec-reader-error "reader count larger than 1,000,000"
    (spec-around "#100000000A()"))
  (check-quick-load-error 2 spec-reader-error "reader count larger than"
    (spec-around "#4000000000*1"))
  (check-quick-load-error 2 spec-reader-error "reader count larger than"
    (spec-around "#99999999999999999999999(1)"))
  (check-quick-load-error 2 spec-reader-error "an array of rank 9"
    (spec-around "#9A()"))
  ;; Within the limits the reader still reads them.
  (check-load-error spec-error "initial value" (spec-around "#3(1)")))

(test long-tokens-are-refused
  (dolist (token (list (make-string 200000 :initial-element #\7)
                       (format nil "~A/3" (make-string 200000 :initial-element #\7))
                       (format nil "#36r~A" (make-string 200000 :initial-element #\Z))
                       (format nil "#*~A" (make-string 200000 :initial-element #\1))
                       (make-string 5000 :initial-element #\a)))
    (check-quick-load-error 2 spec-reader-error "a token is longer than 4,096 characters"
      (spec-around token)))
  ;; Strings and |symbols| may be long.
  (check-load-error spec-error "initial value" (spec-around (format nil "~S" (make-string 10000 :initial-element #\a)))))

(test reader-chains-are-bounded
  (check-quick-load-error 2 spec-reader-error "more than 100 #+, #- and #N= in one form"
    (spec-around (format nil "~Ax" (repeated 50000 "#+sbcl "))))
  (check-quick-load-error 2 spec-reader-error "more than 100 #+, #- and #N= in one form"
    (spec-around (format nil "~Ax" (with-output-to-string (s) (dotimes (i 50000) (format s "#~D=" i))))))
  (dolist (chain '("'#'" "#'" "`#." "#p'" "#c'"))
    (check-quick-load-error 2 spec-reader-error "nests more than 1000 levels deep"
      (spec-around (format nil "~Ax" (repeated 20000 chain))))))

(test shared-structure-is-counted-at-every-use
  ;; #2=(#1# #1#) ... doubles the form at every label: 2^40 conses to walk.
  (check-quick-load-error 5 spec-reader-error "more than 2,000,000 elements"
    (format nil "(defspec d (state-variable x boolean false) (op o :add x :precond (#1=(x x) ~A)))"
            (with-output-to-string (s)
              (loop for i from 2 to 40 do (format s "#~D=(#~D# #~D#) " i (1- i) (1- i)))))))

;;;# Clocks have floors

(test clocks-have-floors
  (check-load-error type-error-in-spec ":after must be a positive number of seconds, at least 0.001"
    "(defspec t1 (state-variable x boolean false) (event ev) (timer fast :after 1d-9 :event ev :repeat t))")
  (check-load-error type-error-in-spec "not 1.0e-4"
    "(defspec t1 (state-variable x boolean false) (event ev) (timer fast :after 1/10000 :event ev))")
  (is (null (load-error "(defspec t1 (state-variable x boolean false) (event ev) (timer ok :after 0.001 :event ev :repeat t))")))
  (signals player.body::motor-error (player.body::parse-motor-frame '(:blink :mean-interval 1d-9)))
  (signals player.body::motor-error (player.body::parse-motor-frame '(:blink :duration 1d6)))
  (finishes (player.body::parse-motor-frame '(:blink :mean-interval 0.05 :duration 10))))

;;;# Through bin/player: one line, in bounded time

(defun scratch-spec (text &optional (name "bounds"))
  "A scratch spec file holding TEXT (see SCRATCH-FILE), its path."
  (scratch-file text :name name))

(defmacro check-bounded-cli-error (code fragment &rest arguments)
  "bin/player ARGUMENTS fails with exit CODE and exactly one stderr line, a
player: error: line holding FRAGMENT, within 10 seconds."
  (let ((start (gensym "START")))
    `(let ((,start (progn (ensure-player-core) (get-internal-real-time))))
       (multiple-value-bind (out err status) (player-command ,@arguments)
         (declare (ignore out))
         (is (eql ,code status) "exit ~A for ~S" status (list ,@arguments))
         (is (= 1 (length (lines err))) "stderr is not one line: ~S" (subseq err 0 (min 400 (length err))))
         (is (eql 0 (search "player: error: " err)) "stderr ~S" err)
         (is (search ,fragment err) "stderr ~S lacks ~S" err ,fragment))
       (is (< (/ (- (get-internal-real-time) ,start) internal-time-units-per-second) 10)
           "~S took more than 10 s" (list ,@arguments)))))

(test the-heap-is-a-budget-with-one-line
  (let ((hog (scratch-spec "(defspec hog (state-variable x boolean false)
  (op o :add x :duration 1 :code (let ((h (make-hash-table))) (loop for i from 0 do (setf (gethash i h) (list i i i)))))
  (event ev :op o))")))
    (check-bounded-cli-error 1 "ran out of memory (limit 256 MB" "run" hog "--events" "ev" "--max-memory" "256M")
    (check-bounded-cli-error 1 "ran out of memory (limit 300 MB" "run" hog "--events" "ev" "--max-memory=300MB"))
  (check-bounded-cli-error 2 "--max-memory takes a size of at least 256M" "run" (fixture "mini.lisp") "--max-memory" "10M")
  (multiple-value-bind (out err status)
      (player-command "run" (fixture "mini.lisp") "--events" "ev-search" "--max-memory" "512M")
    (is (= 0 status))
    (is (string= "" err))
    (is (search "(:event ev-search :time 0)" out))))

(test frames-and-body-time-are-budgeted-up-front
  (check-bounded-cli-error 2 "--at 100000 s is longer than a body performs in one command (at most 7,200 s)"
                           "simulate" (namestring (checkout-file "specs/peedy.lisp")) "--at" "100000" "--fps" "1")
  (check-bounded-cli-error 2 "is longer than a body performs"
                           "record" (namestring (checkout-file "specs/peedy.lisp")) "--at" "1e15" "--frames" "--out" "/tmp/player-bounds-never.trace")
  (check-bounded-cli-error 2 "--at 7000 at 10 fps is 70,001 frames; at most 36,000"
                           "simulate" (namestring (checkout-file "specs/peedy.lisp")) "--at" "7000" "--fps" "10"))

(test hostile-data-files-give-one-line
  (dolist (case '(("#100000000A()" "reader count larger than")
                  ("#4000000000*1" "reader count larger than")
                  ("#2=(#1=(x x) #1#)" "initial value")))
    (let ((file (scratch-spec (spec-around (first case)))))
      (check-bounded-cli-error 1 (second case) "check" file))))

;;;# Expansion counted at load

(defun doubling-macro-spec (levels)
  "A spec whose macro-ops M1..MLEVELS each run the one before twice."
  (with-output-to-string (s)
    (format s "(defspec dbl (state-variable x boolean false) (state-variable y boolean false)~%  (op base :add y :duration 1)~%")
    (loop for i from 1 to levels
          do (format s "  (macro-op m~D :precond (not x) :add x :seq (:op ~A :op ~:*~A))~%"
                     i (if (= i 1) "base" (format nil "m~D" (1- i)))))
    (format s "  (event ev :op m~D))~%" levels)))

(test macro-expansion-is-counted-and-capped
  (check-quick-load-error 2 spec-syntax-error "macro-op m14: runs 16,384 ops through m14 -> m13 -> m12"
    (doubling-macro-spec 40))
  (check-quick-load-error 2 spec-syntax-error "-> m1 -> base; at most 10,000"
    (doubling-macro-spec 40))
  ;; 2^13 = 8,192 ops is within the cap, and loads at once.
  (is (null (load-error (doubling-macro-spec 13))))
  (check-load-error spec-syntax-error "runs itself through"
    "(defspec c (state-variable x boolean false) (op b :add x) (macro-op m :precond (not x) :add x :seq (:op b :op n)) (macro-op n :precond (not x) :add x :seq (:op m)))"))

(defun doubling-play-library (levels)
  "A script library whose scripts S1..SLEVELS each play the one before twice."
  (with-output-to-string (s)
    (format s "(defscript s0 (:duration 0.5) (:at 0 :motor (:blink)))~%")
    (loop for i from 1 to levels
          do (format s "(defscript s~D () (:at 0 :play s~D) (:at 0.1 :play s~:*~D))~%" i (1- i)))))

(test play-expansion-is-counted-and-capped
  (let ((start (get-internal-real-time)))
    (multiple-value-bind (library error)
        (handler-case (values (player.performance::load-script-library
                               (scratch-file (doubling-play-library 40) :name "plays"))
                              nil)
          (player-error (e) (values nil (princ-to-string e))))
      (is (null library))
      (is (search "script s9: plays 1,534 items through s9 -> s8 -> s7" (or error "")) "~A" error)
      (is (search "-> s1 -> s0; at most 1,000" (or error "")) "~A" error))
    (is (< (- (get-internal-real-time) start) (* 2 internal-time-units-per-second))))
  (finishes (player.performance::load-script-library
             (scratch-file (doubling-play-library 8) :name "plays"))))

(test pose-include-fan-out-resolves-each-pose-once
  ;; p<i> includes p<i-1> twice: 2^60 inclusions unless each pose is resolved once.
  (let ((path (scratch-file
               (with-output-to-string (s)
                 (format s "(defpose p0 (l_elbow x -10))~%")
                 (loop for i from 1 to 60
                       do (format s "(defpose p~D (:include p~D) (:include p~:*~D) (:mirror p~:*~D))~%" i (1- i))))
               :name "poses"))
        (start (get-internal-real-time)))
    (let ((library (player.body::load-pose-library path :skeleton (player.body::load-skeleton 'humanoid))))
      (is (< (- (get-internal-real-time) start) (* 2 internal-time-units-per-second)))
      (is (equal (player.body::resolve-pose (player.body::find-pose library 'p60) (player.body::load-skeleton 'humanoid))
                 (player.body::resolve-pose (player.body::find-pose library 'p2) (player.body::load-skeleton 'humanoid)))))))

(test large-cradles-are-built-only-in-part
  (check-quick-load-error 2 spec-error "(newton-cradle 6) is built on demand: write (reachable (newton-cradle 6) NODE...)"
    "(defspec c (:graph (newton-cradle 6)))")
  (check-quick-load-error 2 spec-error "(cradle-stage N STAGE) takes N from 1 to 4"
    "(defspec c (:graph (cradle-stage 6 :g^n)))"))

;;;# The dialogue matcher

(defun scratch-peedy-dialogue (extra)
  "A copy of specs/peedy-dialogue.lisp with the utterance forms EXTRA (text)
added, in a fresh folder beside copies of the files it names; its path."
  (let ((folder (format nil "/tmp/player-bounds-~D-~D/" (sb-posix:getpid) (incf *scratch-counter*))))
    (ensure-directories-exist folder)
    (dolist (file (directory (checkout-file "specs/peedy*.lisp")))
      (uiop:copy-file file (merge-pathnames (file-namestring file) folder)))
    (let ((text (alexandria:read-file-into-string (checkout-file "specs/peedy-dialogue.lisp")))
          (path (merge-pathnames "peedy-dialogue.lisp" folder)))
      (with-open-file (out path :direction :output :if-exists :supersede)
        (let ((at (search "(utterance evHello" text)))
          (write-string (subseq text 0 at) out)
          (write-string extra out)
          (terpri out)
          (write-string "  " out)
          (write-string (subseq text at) out)))
      (namestring path))))

(test many-optional-slots-are-matched-in-bounded-time
  (let ((dialogue (scratch-peedy-dialogue
                   (format nil "(utterance evThanks \"many\" ~A)"
                           (repeated 40 "(:optional timeref)" " "))))
        (start (progn (ensure-player-core) (get-internal-real-time))))
    (multiple-value-bind (out err status)
        (let ((input (make-string-input-stream
                      (format nil "many next later afterwards next later next later next later next~%"))))
          (ensure-player-core)
          (let* ((o (make-string-output-stream)) (e (make-string-output-stream))
                 (process (sb-ext:run-program (namestring (checkout-file "bin/player")) (list "chat" dialogue)
                                              :input input :output o :error e :search nil)))
            (values (get-output-stream-string o) (get-output-stream-string e) (sb-ext:process-exit-code process))))
      (is (= 0 status) "~A" err)
      (is (search "input: evThanks" out) "~A" out))
    (is (< (- (get-internal-real-time) start) (* 10 internal-time-units-per-second)))))

;;;# WAVs are checked before decoding

(test odd-wavs-are-refused-before-decoding
  (loop for (octets fragment) in
        (list (list (wav-octets :rate 1 :data '(0 0 1 0)) "it declares 1 channel at 1 Hz; 1 or 2 channels at 8,000 to 96,000 Hz")
              (list (wav-octets :rate 4000000000 :data '(0 0)) "at 4,000,000,000 Hz")
              (list (wav-octets :channels 6 :data '(0 0 0 0 0 0 0 0 0 0 0 0)) "it declares 6 channels")
              (list (wav-octets :channels 0 :data '()) "it declares 0 channels"))
        for path = (speech-file "odd.wav")
        do (write-octets path octets)
           (let ((message (speech-error-text (lambda () (player::read-wav path)))))
             (is (search fragment (or message "")) "~S lacks ~S" message fragment))))

;;;# Names cannot forge output

(test names-with-control-characters-are-refused
  (check-load-error spec-reader-error "holds a control character"
    (format nil "(defspec f (state-variable x boolean false)~%  (op |go)~%(:op fake :script fake :start 0 :end 1| :add x)~%  (event ev :op x))"))
  (check-load-error spec-reader-error "go)\\x0A(:op fake"
    (format nil "(defspec f (state-variable x boolean false) (op |go)~%(:op fake| :add x))"))
  (check-load-error spec-reader-error "\\x1B"
    (format nil "(defspec f (state-variable |x~A| boolean false))" (code-char 27)))
  (check-load-error type-error-in-spec "holds a control character"
    (format nil "(defspec f (state-variable m string \"a\" (\"a\" \"b~Cc\")))" (code-char 27)))
  ;; Through the Lisp API too.
  (signals spec-error (define-spec (intern (format nil "F~%G") :player-user) '((state-variable x boolean false)))))

(test text-is-escaped-before-it-reaches-a-terminal
  (is (string= "\"a\\x1B]0;t\\x07b\"" (player.base:lisp-text (format nil "a~A]0;t~Ab" (code-char 27) (code-char 7)))))
  (is (string= "plain" (player.base:escaped-text "plain")))
  (is (string= "a\\x0Ab\\u2028" (player.base:escaped-text (format nil "a~%b~A" (code-char #x2028)))))
  (ensure-player-core)
  (let* ((input (make-string-input-stream (format nil "hello~A]0;PWNED~A there~%" (code-char 27) (code-char 7))))
         (out (make-string-output-stream)))
    (sb-ext:run-program (namestring (checkout-file "bin/player"))
                        (list "chat" (namestring (checkout-file "specs/peedy-dialogue.lisp")))
                        :input input :output out :error nil :search nil)
    (let ((text (get-output-stream-string out)))
      (is (search "you: hello\\x1B]0;PWNED\\x07 there" text) "~A" text)
      (is (notany (lambda (c) (and (player.base:control-character-p c) (char/= c #\Newline))) text)))))

(test verify-rejects-control-characters-and-reads-in-linear-time
  (let ((path (scratch-file (format nil "(:recording :spec mini :file ~S :initial () :events (ev-search) :at nil :when-busy nil :frames nil)~%(:event |ev~%(:op fake| :time 0)~%"
                                    (namestring (checkout-file "t/fixtures/mini.lisp")))
                            :name "forged")))
    (handler-case (progn (player.traces::read-recording path) (is nil "a forged recording was read"))
      (player-error (e) (is (search "holds a control character" (princ-to-string e)) "~A" e)))))

;;;# Trust

(test chat-no-code-refuses-the-dialogues-code
  (let* ((dialogue (scratch-peedy-dialogue ""))
         (spec (merge-pathnames "peedy.lisp" dialogue))
         (text (alexandria:read-file-into-string spec)))
    (with-open-file (out spec :direction :output :if-exists :supersede)
      (let ((at (search "  (event ev-search :op search)" text)))
        (write-string (subseq text 0 at) out)
        (format out "  (op evil-code :duration 1 :code (+ 1 2))~%")
        (write-string (subseq text at) out)))
    (check-bounded-cli-error 1 "code refused: the spec holds op evil-code: :code" "chat" dialogue "--no-code")))
