;;;; test-fuzz.lisp -- the fuzzer in `make test`: the generator is deterministic
;;;; and reaches every kind of mutation, the harness tells a PLAYER-ERROR from an
;;;; escape and sees every side effect, the unmutated bases are accepted, and
;;;; 2,000 mutated specs and script libraries each end in a PLAYER-ERROR or in
;;;; acceptance, with nothing run, written or registered behind our back.
;;;; `make fuzz` (fuzz-main.lisp) runs 50,000 cases and the command line.

(in-package #:player-tests)

(def-suite* fuzz :in player-tests)

(defun fuzz-environment-integer (name default)
  "The integer in environment variable NAME, or DEFAULT."
  (let ((value (sb-ext:posix-getenv name)))
    (or (and value (ignore-errors (parse-integer value))) default)))

(defparameter *fuzz-test-seed* (fuzz-environment-integer "FUZZ_SEED" 11)
  "The seed `make test` fuzzes with (FUZZ_SEED overrides it).")

(defparameter *fuzz-test-cases* (fuzz-environment-integer "FUZZ_TEST_CASES" (sweep-count 2000 200))
  "How many cases `make test` runs, 200 in the fast tier (FUZZ_TEST_CASES overrides both).")

(defparameter *fuzz-test-timeout* 10
  "Seconds a case may take before it counts as a hang.")

(defvar *fuzz-test-summary* nil "The summary of the last fuzzing run of the suite.")

(test fuzz-generator-is-deterministic
  (fz-prepare)
  (dolist (seed '(11 12345))
    (loop for index from 0 below 60
          for a = (fz-generate seed index)
          for b = (fz-generate seed index)
          do (is (equal (fzc-kinds a) (fzc-kinds b)))
             (is (equal (fzc-notes a) (fzc-notes b)) "seed ~D case ~D: notes differ" seed index)
             (is (equal (fzc-text a) (fzc-text b)) "seed ~D case ~D: texts differ" seed index)
             (when (eq (fzc-mode a) :memory)
               (is (string= (fz-bounded-text (fzc-forms a) :length 1000 :level 60 :limit 10000000)
                            (fz-bounded-text (fzc-forms b) :length 1000 :level 60 :limit 10000000))))))
  (is (not (equal (loop for i below 20 collect (fuzz-case-text 1 i))
                  (loop for i below 20 collect (fuzz-case-text 2 i))))))

(test fuzz-prng-is-our-own
  (let ((a (make-fz-prng 7 3)) (b (make-fz-prng 7 3)) (c (make-fz-prng 7 4)))
    (let ((xs (loop repeat 100 collect (fz-next a))))
      (is (equal xs (loop repeat 100 collect (fz-next b))))
      (is (not (equal xs (loop repeat 100 collect (fz-next c)))))
      (is (every (lambda (x) (typep x '(unsigned-byte 64))) xs)))
    (is (equal '(3 4 1 1 1) (let ((p (make-fz-prng 1))) (loop repeat 5 collect (fz-below p 5))))
        "the xorshift64* output changed: every recorded seed now names different cases")))

(test fuzz-generator-reaches-every-mutation-kind
  (fz-prepare)
  (let ((seen (make-hash-table)) (modes (make-hash-table)) (targets (make-hash-table)) (bases (make-hash-table :test 'equal)))
    (loop for index below 1500
          for case = (fz-generate 11 index)
          do (dolist (kind (fzc-kinds case)) (setf (gethash kind seen) t))
             (setf (gethash (fzc-mode case) modes) t (gethash (fzc-target case) targets) t
                   (gethash (if (eql 0 (search "random-" (fzc-base case))) "random" (fzc-base case)) bases) t))
    (dolist (kind (append (mapcar #'cdr *fz-form-kinds*) (mapcar #'cdr *fz-text-kinds*) '(:special-float)))
      (is (gethash kind seen) "no case of the first 1,500 of seed 11 has mutation kind ~S" kind))
    (dolist (mode '(:text :form-file :memory)) (is (gethash mode modes) "no ~S case" mode))
    (dolist (target '(:spec :library)) (is (gethash target targets) "no ~S case" target))
    (dolist (base (append (mapcar #'first *fz-spec-files*) (mapcar #'first *fz-library-files*) '("random")))
      (is (gethash base bases) "no case starts from ~A" base))))

(test fuzz-hostile-material-is-as-promised
  (let ((prng (make-fz-prng 5)))
    (is (= 401 (length (string-left-trim "-" (fz-huge-integer-text prng)))))
    (is (= 10000 (length (fz-long-name prng))))
    (is (= 15000 (count #\( (fz-deep-text :not 15000 "x"))))
    (let ((deep (fz-deep-form :not 15000 'x)))
      (is (= 15000 (loop for form = deep then (second form) while (consp form) count t)))))
  (is (find-if (lambda (x) (and (floatp x) (sb-ext:float-nan-p x))) (fz-special-floats)))
  (is (member sb-ext:double-float-positive-infinity (fz-special-floats)))
  (is (every (lambda (payload) (search *fz-marker-placeholder* payload))
             (remove-if (lambda (p) (or (search "payload" p) (search "error" p))) (fz-read-eval-payloads))))
  ;; Printing forms back: circular structure as #n=, spliced text verbatim.
  (let* ((cell (list 'a 'b)) (splice (make-symbol "FZSPLICE0")))
    (setf (cdr (last cell)) cell)
    (let ((text (fz-print-forms (list (list 'op cell splice)) (list (cons splice "#.(x)")))))
      (is (search "#1=" text))
      (is (search "#.(x)" text))))
  ;; The minimizer's spans: balanced forms, the longest first, strings skipped.
  (is (equal '((0 . 13) (3 . 6)) (fz-balanced-spans "(a (b) \"(\" c) )")))
  (is (= 15000 (length (fz-balanced-spans (fz-deep-text :list 15000 "x") :limit 20000))))
  ;; A rename cannot blow a text up: a long name put in many places stops growing.
  (let ((text (format nil "~{~A~^ ~}" (loop repeat 1000 collect "a"))))
    (is (< (length (fz-replace-token text "a" (make-string 10000 :initial-element #\b)))
           (+ (length text) *fz-max-growth* 10001))))
  ;; Raw bytes reach the file as bytes.
  (let ((path (format nil "/tmp/player-fuzz-bytes-~D.lisp" (sb-posix:getpid))))
    (unwind-protect
         (progn (fz-write-case-file (concatenate 'string "é" (fz-raw-bytes '(#xFF #xC3))) path)
                (with-open-file (in path :element-type '(unsigned-byte 8))
                  (let ((octets (make-array 4 :element-type '(unsigned-byte 8))))
                    (is (= 4 (read-sequence octets in)))
                    (is (equalp #(#xC3 #xA9 #xFF #xC3) octets)))))
      (ignore-errors (delete-file path)))))

(test fuzz-harness-tells-player-errors-from-escapes
  (flet ((outcome (thunk &optional (timeout 5))
           (multiple-value-bind (outcome condition) (fz-protected thunk timeout)
             (list outcome (and condition (typep condition 'condition) (type-of condition))))))
    (is (equal '(:ok nil) (outcome (lambda () nil))))
    (is (eq :player-error (first (outcome (lambda () (find-spec 'fuzz-no-such-spec))))))
    (is (equal '(:escaped simple-error) (outcome (lambda () (error "raw")))))
    (is (equal '(:escaped type-error) (outcome (lambda () (error 'type-error :datum 1 :expected-type 'string)))))
    ;; A warning given to ERROR reaches the debugger: an escape, not a pass.
    (is (equal '(:escaped warning) (outcome (lambda () (error 'warning)))))
    (is (eq :escaped (first (outcome (lambda () (invoke-debugger (make-condition 'simple-condition)))))))
    (is (eq :escaped (first (outcome (lambda () (labels ((down (n) (1+ (down (1+ n))))) (down 0)))))))
    (is (eq :timeout (first (outcome (lambda () (loop (sleep 0.01))) 0.3))))
    ;; A plain warning is muffled and counted, and the work goes on.
    (let ((*fz-warnings* 0))
      (is (equal '(:ok nil) (outcome (lambda () (warn "careful") nil))))
      (is (= 1 *fz-warnings*)))
    ;; Nothing reaches the terminal.
    (is (equal '(:ok nil) (outcome (lambda () (print 'noise) (format *error-output* "noise") (read-line *standard-input* nil) nil))))))

(test fuzz-harness-sees-side-effects
  (fz-prepare)
  (let ((run (fz-open-run)))
    (unwind-protect
         (let ((case (make-fz-case :seed 0 :index 0 :target :spec :mode :text :text "")))
           (is (null (fz-side-effects run case)))
           (with-open-file (out (fzrun-marker run) :direction :output) (write-line "x" out))
           (setf (symbol-value (intern "*FUZZ-PAYLOAD-VAR*" '#:player-user)) t)
           (with-open-file (out (merge-pathnames "stray.hpp" (fzrun-directory run)) :direction :output)
             (write-line "x" out))
           (let ((found (fz-side-effects run case)))
             (is (= 3 (length found)) "found ~S" found))
           (is (null (fz-side-effects run case)) "side effects are undone once reported")
           ;; The registry: a spec the case's file did not define is reported and removed.
           (let ((before (fz-registry)))
             (define-spec 'fuzz-intruder '((state-variable x boolean false)) :package (find-package '#:player-user))
             (is (= 1 (length (fz-restore-registry before case (fz-case-file case run)))))
             (is (null (find-spec 'fuzz-intruder nil)))))
      (fz-close-run run))))

(test fuzz-isolation-survives-dying-and-silent-children
  "A case that kills its process, or stops it answering, is reported as such,
and the run goes on with the next case in a new process."
  (fz-prepare)
  (let* ((parent (sb-posix:getpid))
         (run (fz-open-run))
         (results '())
         (make-case (lambda (index)
                      (when (/= (sb-posix:getpid) parent)     ; only in the child
                        (case index
                          (1 (sb-ext:exit :code 7 :abort t))
                          (3 (loop (sleep 1)))))
                      (make-fz-case :seed 0 :index index :target :spec :mode :text :base "test"
                                    :text "(in-package :player-user)" :base-text ""))))
    ;; Long enough for a forked child to answer a trivial case, even on a busy machine.
    (setf (fzrun-patience run) (sweep-count 3 2))
    (unwind-protect (fz-run-forked run make-case 0 5 (lambda (result) (push result results)))
      (fz-close-run run))
    (setf results (reverse results))
    (is (equal '(0 1 2 3 4) (mapcar #'fzr-index results)))
    (is (equal '(:accepted :crashed :accepted :hung :accepted) (mapcar #'fzr-outcome results))
        "outcomes ~S (fork refused? threads: ~S)" (mapcar #'fzr-outcome results)
        (mapcar #'sb-thread:thread-name (sb-thread:list-all-threads)))
    (is (search "status 7" (or (fzr-message (second results)) "")))))

(defun fuzz-unmutated (base-name &key (mode :text))
  "Run base BASE-NAME unmutated (in MODE) through the harness; its FZ-RESULT."
  (let* ((base (fz-base base-name))
         (run (fz-open-run :emit-every 1 :play-every 1))
         (case (make-fz-case :seed 0 :index 0 :target (fzb-target base) :mode mode :base base-name
                             :text (fzb-text base) :base-text (fzb-text base) :companion (fzb-companion base)
                             :forms (and (eq mode :memory)
                                         (if (eq (fzb-target base) :spec)
                                             (rest (find-if #'fz-defspec-form-p (copy-tree (fzb-forms base))))
                                             (copy-tree (fzb-forms base)))))))
    (unwind-protect (fz-execute case run)
      (fz-close-run run))))

(test fuzz-bases-are-accepted-unmutated
  (fz-prepare)
  (dolist (name '("peedy" "mini" "anim" "anim-missing" "no-spec" "peedy-scripts" "anim-scripts"))
    (dolist (mode (if (string= name "no-spec") '(:text) '(:text :memory)))
      (let ((result (fuzz-unmutated name :mode mode)))
        (is (eq :accepted (fzr-outcome result)) "base ~A (~(~A~)): ~A" name mode result)
        (is (null (fzr-violations result)) "base ~A: ~A" name (fzr-violations result)))))
  (is (eq 'type-error-in-spec (fzr-condition-type (fuzz-unmutated "bad-initial"))))
  (is (eq 'spec-reader-error (fzr-condition-type (fuzz-unmutated "unreadable")))))

(test fuzz-cases-end-in-player-errors-or-acceptance
  "The fuzzer proper: every case must end in a PLAYER-ERROR or in acceptance,
and leave nothing behind. Each kind of failure is one failed check, with a
reproducer: (player-tests::fuzz-case SEED N)."
  (let* ((summary (fuzz-run :seed *fuzz-test-seed* :cases *fuzz-test-cases* :timeout *fuzz-test-timeout*))
         (failures (reverse (fzs-failures summary)))
         (outcomes (fzs-outcomes summary)))
    (setf *fuzz-test-summary* summary)
    (format t "~&; fuzz: seed ~D, ~:D cases in ~,1F s: ~:D accepted, ~:D player-errors, ~:D failing~%"
            (fzs-seed summary) (fzs-cases summary) (fzs-seconds summary)
            (gethash "accepted" outcomes 0)
            (loop for label being the hash-keys of outcomes using (hash-value count)
                  when (eql 0 (search "player-error" label)) sum count)
            (length failures))
    (is (= *fuzz-test-cases* (fzs-cases summary)))
    (is (plusp (gethash "accepted" outcomes 0)) "no case was accepted: the mutations are too harsh to test anything")
    (if failures
        (dolist (group (fz-failure-groups failures))
          (fail "~A" (with-output-to-string (out) (fz-write-group group out))))
        (pass))))
