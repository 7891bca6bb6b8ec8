;;;; strips.lisp -- the planner at scale on classic STRIPS families (issue 13):
;;;; blocks world and a gripper-like transport domain, from
;;;; t/strips-families.lisp, compiled in the reachable regime (and, where
;;;; the product space allows, in the full one). Answers the CHI'95 paper's
;;;; question, "the realistic maximum specification size and state space
;;;; complexity": compile time and memory against reachable states and
;;;; against variables. STRIPS-SCALE-TABLE prints the README's table.

(in-package #:player-bench)

(load (merge-pathnames "../t/strips-families.lisp" *bench-directory*))

(defun retained-bytes (thunk)
  "(VALUES RESULT BYTES SECONDS): THUNK's result, the bytes of heap it still
holds after a full GC (what keeping the result costs), and the CPU seconds it
took (the machine is shared: wall-clock time would count the others' work)."
  (sb-ext:gc :full t)
  (let* ((before (sb-kernel:dynamic-usage))
         (t0 (get-internal-run-time))
         (result (funcall thunk))
         (seconds (/ (- (get-internal-run-time) t0) (float internal-time-units-per-second 1d0))))
    (sb-ext:gc :full t)
    (values result (max 0 (- (sb-kernel:dynamic-usage) before)) seconds)))

(defun compile-strips (problem &key (state-space :reachable) (max-depth 40))
  "(VALUES MACHINE SECONDS BYTES): PROBLEM compiled under (:state-space
STATE-SPACE), its compile time (CPU seconds) and the heap its machine holds."
  (let ((spec (player:define-spec (player-strips:strips-problem-name problem)
                  (player-strips:strips-spec-forms problem :state-space state-space :max-depth max-depth)
                :package (find-package '#:player-user))))
    (multiple-value-bind (machine bytes seconds) (retained-bytes (lambda () (player:compile-spec spec)))
      (player:remove-spec (player:spec-name spec))
      (values machine seconds bytes))))

(defun format-bytes (bytes)
  "BYTES in MB (or kB below 1 MB)."
  (if (< bytes 1000000)
      (format nil "~D kB" (round bytes 1000))
      (format nil "~,1F MB" (/ bytes 1d6))))

(defun space-text (machine)
  "MACHINE's product space as 2^N when it is a power of two, else N."
  (let ((size (player.planner::layout-space-size (player.planner::machine-layout machine))))
    (if (= size (ash 1 (1- (integer-length size))))
        (format nil "2^~D" (1- (integer-length size)))
        (format nil "~,1E" (float size 1d0)))))

(defun bench-strips (label problem &key (state-space :reachable) target (max-depth 40))
  "One row: PROBLEM compiled under STATE-SPACE (the median of three when quick)."
  (multiple-value-bind (machine seconds bytes) (compile-strips problem :state-space state-space :max-depth max-depth)
    (let ((times (list seconds)))
      (when (< seconds 2)
        (dotimes (i 2) (push (nth-value 1 (compile-strips problem :state-space state-space :max-depth max-depth)) times)))
      (row (format nil "2. ~A ~(~A~): ~D of ~A states, ~D vars, ~D plans, ~A held"
                   label state-space (player:machine-state-count machine) (space-text machine)
                   (length (player.spec::plannable-variables (player:machine-spec machine)))
                   (machine-plan-count machine) (format-bytes bytes))
           (format-seconds (median times))
           (if target (format nil "< ~A" (format-seconds target)) "")
           (if target (< (median times) target) ""))
      (note "~A ~(~A~): compile ~{~A~^, ~}" label state-space (mapcar #'format-seconds times)))))

(defun bench-strips-families ()
  "The rows of `make bench`: blocks-5 reachable (issue 13: under 1 s), blocks-6, gripper-8."
  (bench-strips "blocks-5" (player-strips:blocks-world 5) :target 1)
  (bench-strips "blocks-6" (player-strips:blocks-world 6))
  (bench-strips "gripper-8" (player-strips:gripper 8)))

;;; The README's table

(defparameter *strips-scale-cases*
  `(("blocks-4" ,(lambda () (player-strips:blocks-world 4)) :full)
    ("blocks-4" ,(lambda () (player-strips:blocks-world 4)) :reachable)
    ("blocks-5" ,(lambda () (player-strips:blocks-world 5)) :reachable)
    ("blocks-6" ,(lambda () (player-strips:blocks-world 6)) :reachable)
    ("blocks-7" ,(lambda () (player-strips:blocks-world 7)) :reachable)
    ("gripper-4" ,(lambda () (player-strips:gripper 4)) :full)
    ("gripper-4" ,(lambda () (player-strips:gripper 4)) :reachable)
    ("gripper-8" ,(lambda () (player-strips:gripper 8)) :reachable)
    ("gripper-9" ,(lambda () (player-strips:gripper 9)) :reachable)
    ("gripper-10" ,(lambda () (player-strips:gripper 10)) :reachable)
    ("gripper-11" ,(lambda () (player-strips:gripper 11)) :reachable)
    ("gripper-2, 20 rooms" ,(lambda () (player-strips:gripper 2 :rooms 20)) :reachable 80)
    ("gripper-2, 42 rooms" ,(lambda () (player-strips:gripper 2 :rooms 42)) :reachable 120)
    ("gripper-1, 64 rooms" ,(lambda () (player-strips:gripper 1 :rooms 64)) :reachable 160)
    ("gripper-1, 84 rooms" ,(lambda () (player-strips:gripper 1 :rooms 84)) :reachable 200))
  "(LABEL PROBLEM-THUNK STATE-SPACE [MAX-DEPTH]) of the README's table.")

(defun strips-scale-table (&optional (cases *strips-scale-cases*))
  "Print the README's table: for each case, variables, product space,
planned states, plans, compile time and heap held, as Markdown rows; with
the planning budget lifted, as the largest cases pass it."
  (format t "~&| spec | regime | variables | product space | planned states | plans | compile | memory held |~%")
  (format t "|---|---|---|---|---|---|---|---|~%")
  (let ((player:*planning-budget* nil))   ; blocks-7, gripper-11, ... pass it
    (loop for (label thunk state-space max-depth) in cases
          do (multiple-value-bind (machine seconds bytes)
                 (compile-strips (funcall thunk) :state-space state-space :max-depth (or max-depth 40))
               (format t "| ~A | ~(~A~) | ~D | ~A | ~:D | ~:D | ~A | ~A |~%"
                       label state-space (length (player.spec::plannable-variables (player:machine-spec machine)))
                       (space-text machine) (player:machine-state-count machine) (machine-plan-count machine)
                       (format-seconds seconds) (format-bytes bytes))
               (finish-output)))))
