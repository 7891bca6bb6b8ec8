;;;; test-bounds-agree.lisp -- issue 31 continued: backends that agree (C++
;;;; names clear of the headers' macros, mixed --events lists, --at inside a
;;;; macro-op), the smaller ones (--body paths, scene events, MBROLA, one-joint
;;;; skeletons) and loading many objects, ops or states in bounded time.
;;;; Helpers are test-bounds.lisp's.

(in-package #:player-tests)

(in-suite bounds)

;;;# C++ names clear of the headers' macros

(test c++-names-are-mangled-clear-of-c-macros
  (is (player.cpp::c-macro-p "EOF"))
  (is (player.cpp::c-macro-p "math_errhandling"))
  (is (not (player.cpp:c++-identifier-text-p "INT64_MAX")))
  (is (not (player.cpp:c++-identifier-text-p "alloca")))
  (is (player.cpp:c++-identifier-text-p "peedy"))
  (check-bounded-cli-error 2 "not \"EOF\"" "emit-c++" (fixture "mini.lisp") "--out" "/tmp" "--name" "EOF")
  (let ((spec (scratch-spec "(defspec alloca
  (state-variable math_errhandling boolean false)
  (state-variable |EOF| string errno (errno stdin INT64_MAX))
  (op assert :add math_errhandling)
  (op |INT64_MAX| :precond math_errhandling :add |EOF|.stdin)
  (event alloca :op assert :op |INT64_MAX|))")))
    (multiple-value-bind (lisp-out lisp-err) (player-command "run" spec "--events" "alloca")
      (multiple-value-bind (c++-out c++-err c++-status) (player-command "run" spec "--events" "alloca" "--backend" "c++")
        (is (string= "" lisp-err))
        (is (= 0 c++-status) "~A" c++-err)
        (is (string= lisp-out c++-out))
        (is (search "(:op int64_max :script int64_max :start 1 :end 2)" c++-out))))))

;;;# Backends that agree

(test mixed-event-lists-are-checked-as-a-whole
  (check-bounded-cli-error 2 "--events: ev-sit@0.2 follows ev-hop, which is sent when the events before it have ended"
                           "run" (namestring (checkout-file "specs/peedy.lisp")) "--events" "ev-hop@0,ev-hop,ev-sit@0.2")
  (check-bounded-cli-error 2 "ev-sit@0.2 follows ev-hop"
                           "run" (namestring (checkout-file "specs/peedy.lisp")) "--events" "ev-hop@0,ev-hop,ev-sit@0.2"
                           "--backend" "c++")
  (multiple-value-bind (out err status)
      (player-command "run" (namestring (checkout-file "specs/peedy.lisp")) "--events" "ev-hop@0,ev-sit@0.2,ev-hop")
    (declare (ignore out))
    (is (= 0 status) "~A" err)))

(test at-inside-a-macro-op-agrees-across-backends
  (let ((arguments (list "run" (namestring (checkout-file "specs/peedy.lisp")) "--initial" "alert=snore"
                         "--events" "ev-search@0" "--at" "1")))
    (multiple-value-bind (lisp-out lisp-err) (apply #'player-command arguments)
      (multiple-value-bind (c++-out c++-err) (apply #'player-command (append arguments (list "--backend" "c++")))
        (is (string= "" lisp-err))
        (is (string= "" c++-err))
        (is (string= lisp-out c++-out) "Lisp:~%~A~%C++:~%~A" lisp-out c++-out)
        (is (search "(:op snort :script snort :start 0 :end 1)" lisp-out))
        (is (search "(:op hard-wake :script hard-wake :start 0" lisp-out))))))

;;;# Smaller ones

(test body-takes-a-skeleton-files-path
  (let ((skeleton (scratch-file (alexandria:read-file-into-string (checkout-file "src/body/skeletons/parrot.lisp"))
                                :name "mine")))
    (multiple-value-bind (out err status)
        (player-command "simulate" (namestring (checkout-file "specs/peedy.lisp")) "--events" "ev-hop"
                        "--body" skeleton)
      (is (= 0 status) "~A" err)
      (is (search "frames at 30 fps" out))))
  (check-bounded-cli-error 1 "there is no skeleton file /tmp/no-such-player.skel"
                           "simulate" (namestring (checkout-file "specs/peedy.lisp")) "--events" "ev-hop"
                           "--body" "/tmp/no-such-player.skel"))

(test check-catches-unknown-scene-events
  (let* ((text (alexandria:read-file-into-string (checkout-file "specs/two-peedys.lisp")))
         (dialogue (scratch-peedy-dialogue ""))   ; a folder holding copies of specs/peedy*.lisp
         (scene (merge-pathnames "bad-scene.lisp" dialogue)))
    (with-open-file (out scene :direction :output :if-exists :supersede)
      (write-string (let ((at (search "(right/ev-hop :after 0.5)" text)))
                      (concatenate 'string (subseq text 0 at) "(right/ev-nope :after 0.5)"
                                   (subseq text (+ at (length "(right/ev-hop :after 0.5)")))))
                    out))
    (check-bounded-cli-error 1 "scene event duet-hop: member right plays spec peedy, which has no event ev-nope"
                             "check" (namestring scene))))

(test scene-members-resolve-only-beside-the-scene
  (let* ((folder (format nil "/tmp/player-bounds-scene-~D/" (sb-posix:getpid)))
         (inner (format nil "~Ainner/" folder)))
    (ensure-directories-exist inner)
    ;; Were it read, this file's unreadable text would be the error.
    (with-open-file (out (format nil "~Asecret.lisp" folder) :direction :output :if-exists :supersede)
      (write-string "(defspec secret  TOP-SECRET-TOKEN" out))
    (with-open-file (out (format nil "~Ascene.lisp" inner) :direction :output :if-exists :supersede)
      (write-string "(defscene s (|../secret| :as a))" out))
    (multiple-value-bind (out err status) (player-command "check" (format nil "~Ascene.lisp" inner))
      (declare (ignore out))
      (is (= 1 status))
      (is (search "member a plays spec ../secret, which is not defined" err) "~A" err)
      (is (not (search "secret.lisp:" err)) "~A" err)
      (is (not (search "TOP-SECRET" err)) "~A" err))))

(test errors-quote-nothing-of-files-that-are-not-player-data
  (dolist (secret '("SECRETTOKEN123 more words" "hunter2:pass (x)" "  ; a comment
SECRETTOKEN123"))
    (let* ((file (scratch-file secret :name "secret"))
           (spec (scratch-spec (format nil "(defspec q (:scripts ~S) (:body parrot) (state-variable x boolean false) (op o :add x) (event ev :op o))" file))))
      (dolist (arguments (list (list "check" spec) (list "run" file)))
        (multiple-value-bind (out err) (apply #'player-command arguments)
          (is (search "is not Player data" (concatenate 'string out err)) "~A ~A" out err)
          (dolist (word '("SECRET" "secret123" "hunter" "HUNTER" "pass"))
            (is (not (search word (concatenate 'string out err))) "~S leaks in ~A ~A" word out err))))))
  (check-load-error spec-reader-error "a symbol names a package that does not exist"
    "(defspec q (state-variable x boolean nosuch::thing))"))

(test many-objects-load-in-linear-time
  (let ((forms (cons '(defscript s0 (:duration 0.5) (:at 0 :motor (:blink)))
                     (loop for i below 20000
                           collect (if (zerop i)
                                       '(defobject o0 :position (0 0 0))
                                       `(defobject ,(intern (format nil "O~D" i) :player-user)
                                          :parent ,(intern (format nil "O~D" (1- i)) :player-user)
                                          :position (0 0 0))))))
        (start (get-internal-real-time)))
    (finishes (player.performance::parse-script-library-forms forms))
    (is (< (- (get-internal-real-time) start) (* 5 internal-time-units-per-second)))
    (signals player-error
      (player.performance::parse-script-library-forms
       (append forms '((defobject o0 :position (1 0 0))))))))

(test check-counts-unreachable-states-only-when-few
  ;; 2^23 states: check visited each of them, for minutes.
  (let ((spec (scratch-spec
               (with-output-to-string (s)
                 (format s "(defspec big~%")
                 (dotimes (i 23) (format s "  (state-variable v~D boolean false)~%" i))
                 (dotimes (i 23) (format s "  (op o~D :precond (not v~D) :add v~D :sub v~D)~%" i i i (mod (1+ i) 23)))
                 (dotimes (i 23) (format s "  (event e~D :add v~D :add v~D)~%" i i (mod (+ i 5) 23)))
                 (format s ")~%")))))
    (ensure-player-core)
    (let ((start (get-internal-real-time)))
      (multiple-value-bind (out err status) (player-command "check" spec)
        (is (member status '(0 1)) "~A" err)
        (is (search "were not counted: 8,388,608 states are more than check visits one by one" out) "~A" out))
      (is (< (- (get-internal-real-time) start) (* 10 internal-time-units-per-second))))))

(test an-mbrola-voice-is-one-line
  (check-bounded-cli-error 1 "mb-en1 is an MBROLA voice, which Player does not use"
                           "speak" "hello" "--voice" "mb-en1" "--out" "/tmp/player-bounds-never.wav"))

(test a-one-joint-skeleton-renders
  (let ((skeleton (scratch-file "(skeleton one (:joint root :parent nil :center (0 1 0)))" :name "one"))
        (spec (scratch-spec "(defspec d (state-variable x boolean false) (op o :add x :duration 1) (event ev :op o))"))
        (out (format nil "/tmp/player-bounds-one-~D/" (sb-posix:getpid))))
    (multiple-value-bind (stdout err status)
        (player-command "render" spec "--events" "ev" "--body" skeleton "--out" out "--fps" "2" "--size" "64x48")
      (is (= 0 status) "~A" err)
      (is (search "frame-0001.png" stdout)))
    (uiop:delete-directory-tree (pathname out) :validate t :if-does-not-exist :ignore)))

(test macro-nesting-is-capped-and-many-ops-load-fast
  ;; 15,000 macro-ops each running the one before: SBCL's control stack ran out.
  (let ((text (with-output-to-string (s)
                (format s "(defspec chain (state-variable x boolean false) (state-variable y boolean false)~%  (op base :add y)~%")
                (loop for i from 1 to 15000
                      do (format s "  (macro-op m~D :precond (not x) :add x :seq (:op ~A))~%"
                                 i (if (= i 1) "base" (format nil "m~D" (1- i)))))
                (format s "  (event ev :op m15000))~%"))))
    (check-quick-load-error 8 spec-syntax-error "macro-op m101: nests macro-ops more than 100 deep, through m101 -> m100" text))
  (is (null (load-error (with-output-to-string (s)
                          (format s "(defspec many (state-variable x boolean false)~%")
                          (dotimes (i 20000) (format s "  (op o~D :add x)~%" i))
                          (format s "  (event ev :op o19999))~%"))))))

(test run-at-a-million-seconds-with-idle-timers-finishes
  (ensure-player-core)
  (let ((start (get-internal-real-time)))
    (multiple-value-bind (out err status)
        (player-command "run" (namestring (checkout-file "specs/peedy.lisp")) "--at" "1e6")
      (is (= 0 status) "~A" err)
      (is (search "(:state " out)))
    (is (< (- (get-internal-real-time) start) (* 10 internal-time-units-per-second)))))

(test long-work-prints-one-progress-line-on-a-terminal
  (let ((out (make-string-output-stream)))
    (let ((thread (player.cli::start-progress-note '("check" "x.lisp") :delay 0.05 :stream out :interactive t)))
      (sb-thread:join-thread thread))
    (is (string= (format nil "player: check is still working (0.05 s)...~%") (get-output-stream-string out))))
  (is (null (player.cli::start-progress-note '("check") :interactive nil))))

(test simulate-at-inside-a-macro-op-shows-the-ops-started
  (multiple-value-bind (out err status)
      (player-command "simulate" (namestring (checkout-file "specs/peedy.lisp")) "--initial" "alert=snore"
                      "--events" "ev-search@0" "--at" "1")
    (is (= 0 status) "~A" err)
    (is (search "(:op snort :script snort :start 0 :end 1)" out) "~A" out)))
