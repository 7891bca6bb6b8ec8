;;;; fuzz-main.lisp -- `make fuzz`: the long run of the fuzzer in fuzz.lisp.
;;;;
;;;;   1. FUZZ_CASES (50,000) mutated specs and script libraries through the
;;;;      Lisp API, as in `make test` (each ends in a PLAYER-ERROR or in
;;;;      acceptance, runs nothing, writes nothing outside the emit directory);
;;;;   2. FUZZ_CLI_CASES (400) mutated files through bin/player run, plans,
;;;;      check and emit-c++ (and check --scripts for libraries): each must exit
;;;;      0, 1 or 2 and print on stderr nothing or exactly one line
;;;;      "player: error: ...", never a backtrace or the debugger;
;;;;   3. FUZZ_MODEL_CASES (300) mutated .gltf, .glb and .x files through
;;;;      bin/player model (fuzz-models.lisp): each must exit 0, or 1 with one
;;;;      "player: error: ..." line naming the file; never a signal, a memory
;;;;      fault, SBCL's fatal error, a Lisp object printed or a hang (20 s);
;;;;   4. when g++ is installed, the C++ emitted for up to FUZZ_GXX_CASES (40)
;;;;      accepted specs with hostile names, compiled with -fsyntax-only and the
;;;;      project's warnings as errors;
;;;;   5. FUZZ_BOUNDS_CASES (200) hostile but short inputs (fuzz-bounds.lisp:
;;;;      huge reader forms, fast clocks, fan-out, exponential phrases, odd
;;;;      WAVs, control-character names) through bin/player, each finishing or
;;;;      giving its one error line within 10 s and 2 GB of resident memory.
;;;; It prints the tables and every kind of failure with one reproducer, made
;;;; smaller by FZ-MINIMIZE and written to /tmp/player-fuzz-repro-SEED/ (unless
;;;; FUZZ_MINIMIZE=0), and exits 1 when anything failed. FUZZ_SEED (1) picks the
;;;; cases.
;;;; Loaded after the player/tests system:
;;;;   sbcl ... --load t/fuzz-main.lisp --eval '(player-tests::fuzz-main)'

(in-package #:player-tests)

;;; ---------------------------------------------------------------------------
;;; The command line

(defstruct (fz-cli-result (:conc-name fzcli-))
  "One command-line case: COMMAND (a string), EXIT (a code or :TIMEOUT),
PROBLEMS (strings; none means it passed), STDERR (made visible, cut short)."
  seed index command arguments exit stderr (problems '()) excerpt notes base target mode)

(defun fz-cli-problems (exit stderr)
  "What is wrong with a run of bin/player that ended with EXIT and printed STDERR."
  (let* ((lines (remove-if (lambda (line) (or (string= line "") (eql 0 (search *fz-build-line* line))))
                           (fz-split-lines stderr)))
         (problems '()))
    (cond ((eq exit :timeout) (push "timeout" problems))
          ((not (member exit '(0 1 2))) (push (format nil "exit code ~A" exit) problems)))
    (when (or (search "debugger" stderr :test #'char-equal) (search "backtrace" stderr :test #'char-equal))
      (push "backtrace or debugger on stderr" problems))
    (cond ((null lines))
          ((rest lines) (push "stderr has more than one line" problems))
          ((not (eql 0 (search "player: error: " (first lines))))
           (push "stderr line is not \"player: error: ...\"" problems)))
    (nreverse problems)))

(defun fz-cli-command (case directory file index)
  "The bin/player arguments for CASE, whose file is FILE in DIRECTORY."
  (let ((file (file-namestring file)))
    (if (eq (fzc-target case) :library)
        (list "check" (format nil "~A.lisp" (fzc-companion case)) "--scripts" file)
        (ecase (mod index 4)
          (0 (append (list "run" file)
                     (when (fzc-events case)
                       (list "--events" (format nil "~{~A~^,~}"
                                                (subseq (fzc-events case) 0 (min 3 (length (fzc-events case)))))))))
          (1 (list "plans" file))
          (2 (list "check" file))
          (3 (list "emit-c++" file "--out" (namestring (merge-pathnames "out/" directory))))))))

(defun fuzz-cli (&key (seed 1) (cases 400) (timeout 120) progress)
  "Run CASES mutated files through bin/player; a list of FZ-CLI-RESULTs.
Cases are numbered from 1,000,000, so they differ from FUZZ-RUN's; each uses
only the file modes. TIMEOUT covers a rebuild of bin/player's core."
  (fz-prepare)
  (let* ((player (namestring (checkout-file "bin/player")))
         (directory (fz-make-directory "player-fuzz-cli"))
         (run (make-fz-run :directory directory :marker (merge-pathnames "marker" directory)))
         (results '()))
    ;; The companions, and the library bases' specs for check --scripts.
    (dolist (path *fz-companion-files*)
      (alexandria:copy-file (checkout-file path) (merge-pathnames (file-namestring path) directory)))
    (dolist (entry *fz-library-files*)
      (alexandria:write-string-into-file (fzb-text (fz-base (third entry)))
                                         (merge-pathnames (format nil "~A.lisp" (third entry)) directory)
                                         :external-format :utf-8 :if-exists :supersede))
    (let ((expected (mapcar #'namestring (directory (merge-pathnames "*.*" directory)))))
      (unwind-protect
           (progn
             (fz-run-process player '("help") directory timeout)
             (dotimes (i cases)
               (let* ((index (+ 1000000 i))
                      (case (fz-generate seed index :modes '(:text :form-file)))
                      (file (fz-case-file case run))
                      (text (fz-case-file-text case run))
                      (arguments (fz-cli-command case directory file i)))
                 (fz-write-case-file text file)
                 (multiple-value-bind (exit stdout stderr) (fz-run-process player arguments directory timeout)
                   (declare (ignore stdout))
                   (let ((problems (fz-cli-problems exit stderr)))
                     (when (probe-file (fzrun-marker run))
                       (push "marker file created" problems)
                       (delete-file (fzrun-marker run)))
                     (fz-delete-tree (merge-pathnames "out/" directory))
                     (dolist (path (directory (merge-pathnames "**/*.*" directory) :resolve-symlinks nil))
                       (when (and (pathname-name path)
                                  (not (member (namestring path) (list* (namestring file) expected) :test #'string=)))
                         (push (format nil "file outside --out: ~A" (fz-visible (namestring path))) problems)
                         (ignore-errors (delete-file path))))
                     (push (make-fz-cli-result
                            :seed seed :index index :command (first arguments) :arguments arguments :exit exit
                            :stderr (fz-clip stderr 400)
                            :problems problems :notes (fzc-notes case) :base (fzc-base case)
                            :target (fzc-target case) :mode (fzc-mode case)
                            :excerpt (fz-excerpt text (fzc-base-text case)))
                           results)))
                 (ignore-errors (delete-file file))
                 (when (and progress (zerop (mod (1+ i) 50)))
                   (write-char #\. progress) (force-output progress)))))
        (fz-delete-tree directory)))
    (nreverse results)))

(defun fz-cli-report (results seconds &optional (stream *standard-output*))
  "Print the command-line cases: by command and outcome, then each kind of problem once."
  (format stream "~&~%Command line: ~:D cases in ~,1F s~%~%  ~10A ~8@A ~8@A ~8@A ~8@A~%"
          (length results) seconds "command" "exit 0" "exit 1" "exit 2" "failed")
  (dolist (command (remove-duplicates (mapcar #'fzcli-command results) :test #'string= :from-end t))
    (let ((mine (remove command results :key #'fzcli-command :test-not #'string=)))
      (format stream "  ~10A ~8:D ~8:D ~8:D ~8:D~%" command
              (count 0 mine :key #'fzcli-exit) (count 1 mine :key #'fzcli-exit) (count 2 mine :key #'fzcli-exit)
              (count-if #'fzcli-problems mine))))
  (let ((groups '()))
    (dolist (result results)
      (dolist (problem (fzcli-problems result))
        (let* ((label (subseq problem 0 (or (search ": " problem) (length problem))))
               (entry (assoc label groups :test #'string=)))
          (if entry
              (incf (second entry))
              (setf groups (append groups (list (list label 1 result))))))))
    (if groups
        (progn
          (format stream "~%Command-line failures, by kind (one reproducer each):~%")
          (loop for (label count result) in groups
                do (format stream "~A: ~D case~:P~%    seed ~D case ~D: ~(~A ~A, base ~A~)~%    bin/player ~{~A~^ ~}~%    exit ~A; stderr: ~A~%    mutations: ~{~A~^; ~}~%    input: ~A~%    the file: (player-tests::fuzz-case-text ~D ~D)~%"
                           label count (fzcli-seed result) (fzcli-index result) (fzcli-mode result)
                           (fzcli-target result) (fzcli-base result)
                           (mapcar #'fz-visible (fzcli-arguments result))
                           (fzcli-exit result) (fzcli-stderr result) (fzcli-notes result)
                           (fzcli-excerpt result) (fzcli-seed result) (fzcli-index result))))
        (format stream "~%No command-line failures.~%"))
    (length groups)))

;;; ---------------------------------------------------------------------------
;;; g++ on the C++ of accepted specs with hostile names

(defun fz-code-in-case-p (case)
  "Does CASE's input mention :c++ or :code (text pasted or run verbatim, which
g++ may rightly reject)?"
  (if (fzc-text case)
      (or (search ":c++" (fzc-text case) :test #'char-equal) (search ":code" (fzc-text case) :test #'char-equal))
      (find-if (lambda (site) (member (car (fz-site-cell site)) '(:c++ :code)))
               (fz-sites (fz-holder (fzc-forms case))))))

(defun fz-gxx-keeper (directory limit)
  "An emit hook keeping, in DIRECTORY/CASE/, the C++ of up to LIMIT cases with
hostile names (it runs in the fuzzing children, so it counts on the disk)."
  (lambda (case files)
    (when (and (intersection (fzc-kinds case) '(:rename-c++ :collide :c++-token :rename-unicode :unicode-token
                                               :rename-long :long-token))
               (not (fz-code-in-case-p case))
               (< (length (directory (merge-pathnames "*/" directory))) limit))
      (let ((to (merge-pathnames (format nil "~D/" (fzc-index case)) directory)))
        (ensure-directories-exist to)
        (dolist (file files)
          (alexandria:copy-file file (merge-pathnames (file-namestring file) to)))))))

(defun fz-gxx-check (directory seed)
  "Compile every kept case's C++ in DIRECTORY with g++ -fsyntax-only; a list of
(INDEX FIRST-ERROR-LINES) for those g++ rejected, and how many it compiled."
  (let ((failures '()) (count 0))
    (dolist (case-directory (sort (directory (merge-pathnames "*/" directory)) #'string< :key #'namestring))
      (dolist (source (directory (merge-pathnames "*.cpp" case-directory)))
        (incf count)
        (multiple-value-bind (exit stdout stderr)
            (fz-run-process "/usr/bin/g++" (list "-std=c++17" "-fsyntax-only" "-Wall" "-Wextra" "-Werror" "-pedantic"
                                                 (file-namestring source))
                            case-directory 120)
          (declare (ignore stdout))
          (unless (eql exit 0)
            (push (list seed (parse-integer (car (last (pathname-directory case-directory))))
                        (fz-visible (format nil "~{~A~^ | ~}"
                                            (let ((lines (remove-if-not (lambda (l) (search "error" l))
                                                                        (fz-split-lines stderr))))
                                              (subseq lines 0 (min 2 (length lines)))))))
                  failures)))))
    (values (nreverse failures) count)))

;;; ---------------------------------------------------------------------------
;;; Minimized reproducers

(defun fz-minimize-failures (summary &key (stream *standard-output*) (seconds 60))
  "Minimize the example of every failure group of SUMMARY that has a file, write
each to /tmp/player-fuzz-repro-SEED/N.lisp (the marker file named
/tmp/player-fuzz-marker) and print it."
  (let ((groups (fz-failure-groups (fzs-failures summary)))
        (directory (pathname (format nil "/tmp/player-fuzz-repro-~D/" (fzs-seed summary)))))
    (when groups
      (ensure-directories-exist directory)
      (dolist (old (directory (merge-pathnames "*.lisp" directory)))  ; an earlier run's
        (delete-file old))
      (format stream "~%Minimized reproducers (~A):~%" (namestring directory))
      (loop for (label nil nil example) in groups
            for k from 1
            do (if (and (fzr-seed example) (member (fzr-mode example) '(:text :form-file)))
                   (let ((case (fz-generate (fzr-seed example) (fzr-index example))))
                     (multiple-value-bind (text runs) (fz-minimize case label :seconds seconds)
                       (let* ((file (merge-pathnames (format nil "~D.lisp" k) directory))
                              (final (fz-replace-all text *fz-marker-placeholder* "/tmp/player-fuzz-marker")))
                         (fz-write-case-file final file)
                         (format stream "~A~%    seed ~D case ~D, ~:D characters (from ~:D; ~D runs): ~A~%    ~A~%"
                                 label (fzr-seed example) (fzr-index example) (length final)
                                 (length (fzc-text case)) runs (namestring file)
                                 (let ((visible (fz-visible final)))
                                   (if (> (length visible) 600)
                                       (concatenate 'string (subseq visible 0 597) "...")
                                       visible))))))
                   (format stream "~A~%    (only in memory: replay with (player-tests::fuzz-case ~A ~A))~%"
                           label (fzr-seed example) (fzr-index example)))))))

;;; ---------------------------------------------------------------------------
;;; The entry point

(defun fuzz-main ()
  "`make fuzz`: run everything, print the tables, exit 0 when nothing failed, else 1."
  (let* ((seed (fuzz-environment-integer "FUZZ_SEED" 1))
         (cases (fuzz-environment-integer "FUZZ_CASES" 50000))
         (cli-cases (fuzz-environment-integer "FUZZ_CLI_CASES" 400))
         (model-cases (fuzz-environment-integer "FUZZ_MODEL_CASES" 300))
         (gxx-cases (if (probe-file "/usr/bin/g++") (fuzz-environment-integer "FUZZ_GXX_CASES" 40) 0))
         (bounds-cases (fuzz-environment-integer "FUZZ_BOUNDS_CASES" 200))
         (gxx-directory (fz-make-directory "player-fuzz-gxx"))
         (failed 0))
    (format t "~&Fuzzing Player with seed ~D: ~:D cases through the Lisp API, ~:D through bin/player, ~:D models~@[, g++ on up to ~D~].~%(FUZZ_SEED, FUZZ_CASES, FUZZ_CLI_CASES, FUZZ_MODEL_CASES and FUZZ_GXX_CASES change that.)~%"
            seed cases cli-cases model-cases (and (plusp gxx-cases) gxx-cases))
    (unwind-protect
         (progn
           (let ((summary (fuzz-run :seed seed :cases cases :progress *standard-output*
                                    :emit-hook (and (plusp gxx-cases) (fz-gxx-keeper gxx-directory gxx-cases)))))
             (fz-report summary)
             (when (and (fzs-failures summary) (/= 0 (fuzz-environment-integer "FUZZ_MINIMIZE" 1)))
               (fz-minimize-failures summary))
             (incf failed (length (fzs-failures summary))))
           (when (plusp cli-cases)
             (let* ((start (get-internal-real-time))
                    (results (fuzz-cli :seed seed :cases cli-cases :progress *standard-output*))
                    (seconds (/ (- (get-internal-real-time) start) internal-time-units-per-second)))
               (fz-cli-report results seconds)
               (incf failed (count-if #'fzcli-problems results))))
           (when (plusp model-cases)
             (let* ((start (get-internal-real-time))
                    (results (fuzz-models :seed seed :cases model-cases :progress *standard-output*))
                    (seconds (/ (- (get-internal-real-time) start) internal-time-units-per-second)))
               (if results
                   (incf failed (fzm-report results seconds))
                   (format t "~%Models not fuzzed: Assimp's test models are not installed (Debian assimp-testmodels).~%"))))
           (when (plusp bounds-cases)
             (incf failed (fuzz-bounds-report (fuzz-bounds :seed seed :cases bounds-cases :progress *standard-output*))))
           (when (plusp gxx-cases)
             (multiple-value-bind (failures count) (fz-gxx-check gxx-directory seed)
               (format t "~%g++ -fsyntax-only on the C++ of ~D accepted spec~:P with hostile names: ~D rejected~%"
                       count (length failures))
               (loop for (seed index message) in failures
                     do (format t "  seed ~D case ~D: ~A~%    replay: (player-tests::fuzz-case ~D ~D)~%"
                                seed index message seed index))
               (incf failed (length failures)))))
      (fz-delete-tree gxx-directory))
    (format t "~%~:[No failures.~;~:*~:D failing case~:P.~]~%" (and (plusp failed) failed))
    (finish-output)
    (sb-ext:exit :code (if (plusp failed) 1 0))))
