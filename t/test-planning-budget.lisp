;;;; test-planning-budget.lisp -- planning one spec does a bounded amount of
;;;; work (src/planner/planning-budget.lisp, issue 31): past *PLANNING-BUDGET*
;;;; or the spec's (:planning-budget N) it stops with one error naming the
;;;; spec, its file and how far it got; the count is deterministic, and a
;;;; lifted budget plans as an unbudgeted run does.  (TOKEN-RING-SPEC is in
;;;; fuzz-bounds.lisp, whose :planning cases draw from it.)

(in-package #:player-tests)

(def-suite* planning-budget :in player-tests)

(defun planning-budget-file (text)
  "Write TEXT to a fresh spec file; its pathname."
  (let ((path (merge-pathnames (format nil "planning-budget-~D.lisp" (random 1000000000 (make-random-state t)))
                               (uiop:temporary-directory))))
    (alexandria:write-string-into-file text path :if-exists :supersede)
    path))

(defun plan-spec-text (text)
  "Load the spec of TEXT from a file and plan it afresh: (VALUES MACHINE FILE)."
  (let ((file (planning-budget-file text)))
    (unwind-protect
         (let ((player.planner::*reuse-plans* nil))
           (values (player:plan-spec (first (player:load-spec file))) file))
      (ignore-errors (delete-file file)))))

(defun machine-plan-text (machine)
  "Every plan of MACHINE, goal by goal, as (CONDITION OP-NAMES...) lists."
  (map 'list (lambda (goal)
               (map 'list (lambda (plan) (cons (player.planner:plan-condition plan)
                                               (mapcar #'player:op-name (player.planner:plan-ops plan))))
                    (player.planner::goal-plans goal)))
       (player.planner:machine-goal-table machine)))

(test planning-work-is-counted-deterministically
  ;; The same spec planned twice does the same work, in units, whatever the machine's load.
  (let* ((text (token-ring-spec 12))
         (first (player:machine-planning-work (plan-spec-text text)))
         (second (player:machine-planning-work (plan-spec-text text))))
    (is (plusp first))
    (is (= first second))
    ;; and more for a larger spec
    (is (< first (player:machine-planning-work (plan-spec-text (token-ring-spec 16)))))))

(test planning-past-the-budget-signals-the-named-error
  (let* ((text (token-ring-spec 14 :name "budgeted-ring"))
         (work (player:machine-planning-work (plan-spec-text text)))
         (condition (let ((player:*planning-budget* (floor work 2)))
                      (handler-case (progn (plan-spec-text text) nil)
                        (player:planning-budget-exceeded (c) c)))))
    (is (typep condition 'player:player-error))
    (when condition
      (let ((message (princ-to-string condition)))
        (is (search "budgeted-ring" message) "names the spec: ~A" message)
        (is (search "planning-budget-" message) "names the file: ~A" message)
        (is (search (format nil "~:D" (floor work 2)) message) "names the budget: ~A" message)
        (is (search "of 14 goals over 14 states" message) "says how far it got: ~A" message)
        (is (search "(:planning-budget N)" message) "says what to do: ~A" message)
        (is (search "make fewer states reachable" message) "reachable already: ~A" message)))
    ;; exactly at its work, the spec plans
    (let ((player:*planning-budget* work))
      (is (= work (player:machine-planning-work (plan-spec-text text)))))))

(test planning-budget-option-lifts-or-sets-the-budget
  ;; (:planning-budget :unlimited) plans under any default, with the plans of an unbudgeted run.
  (let* ((plain (token-ring-spec 14 :name "lifted-ring"))
         (lifted (token-ring-spec 14 :name "lifted-ring" :option "(:planning-budget :unlimited)"))
         (expected (let ((player:*planning-budget* nil)) (machine-plan-text (plan-spec-text plain)))))
    (let ((player:*planning-budget* 1000))
      (signals player:planning-budget-exceeded (plan-spec-text plain))
      (is (equal expected (machine-plan-text (plan-spec-text lifted))))
      ;; a number given by the spec is its budget
      (is (equal expected (machine-plan-text (plan-spec-text
                                               (token-ring-spec 14 :name "lifted-ring"
                                                                   :option "(:planning-budget 1000000000)"))))))
    (let ((player:*planning-budget* nil))
      (signals player:planning-budget-exceeded
        (plan-spec-text (token-ring-spec 14 :name "lifted-ring" :option "(:planning-budget 1000)"))))))

(test planning-budget-option-is-validated
  (dolist (value '("0" "-5" "\"many\"" "1.5" "lots" "(1)" "1000000000001"))
    (let ((file (planning-budget-file (format nil "(defspec bad-budget (:planning-budget ~A) (state-variable x boolean false) (op o :add x) (event ev :state x))~%" value))))
      (unwind-protect
           (signals player:type-error-in-spec (player:load-spec file))
        (ignore-errors (delete-file file))))))

(test shipped-specs-plan-unchanged-within-the-budget
  ;; Peedy plans the same with the default budget as without one, using a sliver of it.
  (let* ((file (checkout-file "specs/peedy.lisp"))
         (player.planner::*reuse-plans* nil)
         (budgeted (player:plan-spec (first (last (player:load-spec file)))))
         (free (let ((player:*planning-budget* nil)) (player:plan-spec (first (last (player:load-spec file)))))))
    (is (equal (machine-plan-text free) (machine-plan-text budgeted)))
    (is (< (* 1000 (player:machine-planning-work budgeted)) player:*planning-budget*))))

(test planning-past-the-budget-ends-the-cli-fast
  ;; Through bin/player: a spec just past the default budget (a 340-boolean
  ;; ring: about 2 x 10^9 units) gives its one error line, exit 1, within 10 s and 2 GB.
  (let* ((directory (merge-pathnames (format nil "planning-budget-~D/" (random 1000000000 (make-random-state t)))
                                     (uiop:temporary-directory)))
         (spec (merge-pathnames "ring.lisp" directory)))
    (ensure-directories-exist spec)
    (unwind-protect
         (progn
           (alexandria:write-string-into-file (token-ring-spec 340) spec :if-exists :supersede)
           (multiple-value-bind (exit stderr seconds megabytes)
               (fzb-run (list "check" "ring.lisp") (namestring directory) nil)
             (is (eql 1 exit) "exit ~A: ~A" exit stderr)
             (is (= 1 (length (lines stderr))) "one line: ~A" stderr)
             (is (search "player: error: spec ring (" stderr) "~A" stderr)
             (is (search "passed its planning budget" stderr) "~A" stderr)
             (is (< seconds 10) "took ~,1F s" seconds)
             (is (or (null megabytes) (< megabytes 2048)) "used ~,0F MB" megabytes)))
      (uiop:delete-directory-tree directory :validate t :if-does-not-exist :ignore))))

(test planning-budget-error-in-the-full-space-suggests-the-reachable-regime
  (let ((player:*planning-budget* 1000))
    (handler-case (progn (plan-spec-text (domain-grid-spec 30 2)) (fail "planned within 1,000 units"))
      (player:planning-budget-exceeded (c)
        (let ((message (princ-to-string c)))
          (is (search "over 900 states" message) "~A" message)
          (is (search "(:state-space :reachable) and (:unplanned-states :search)" message) "~A" message))))))
