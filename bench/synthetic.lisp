;;;; synthetic.lisp -- a seeded family of synthetic specs over N boolean
;;;; variables, in two forms built from one description: a DEFSPEC body for
;;;; Player, and an explicit-state encoding for the naive planner (naive.lisp).
;;;;
;;;; The family: variables X0..X(N-1) on a ring. Each variable but X0 has
;;;;   SET-i   :precond <literal on X(i-1)>            :add X(i)
;;;;   CLR-i   :precond <literal on X(i+1 mod N)>      :sub X(i)
;;;; with the literal's polarity drawn from the seed (a neighbour must be on,
;;;; or off); SET-0 and CLR-0 need nothing. Plus a few "token moves"
;;;;   MV-i    :precond (X(i) and (not X(i+1)))        :add X(i+1) :sub X(i)
;;;; Every op touches one or two variables and looks at one neighbour, so goal
;;;; regression stays a walk along the ring (tractable), while reaching a
;;;; conjunction of far-apart literals needs plans several ops long. Events ask
;;;; for conjunctions of 2-4 random literals (:state) and for ops (their
;;;; preconditions become goals too). Every one of the 2^N states is plannable.

(in-package #:player-bench)

(defstruct (synth-op (:constructor make-synth-op (name pre-mask pre-bits eff-mask eff-bits form)))
  "An op over an N-bit state S: applicable when (= (logand S PRE-MASK) PRE-BITS);
afterwards S is (logior (logandc2 S EFF-MASK) EFF-BITS)."
  name
  (pre-mask 0 :type fixnum) (pre-bits 0 :type fixnum)
  (eff-mask 0 :type fixnum) (eff-bits 0 :type fixnum)
  form)

(defstruct (synth-family (:constructor %make-synth-family (n ops goals body)))
  "One member of the family: N variables, SYNTH-OPs, goals as lists of
(MASK . BITS) cubes over the N-bit state, and the DEFSPEC body."
  n ops goals body)

(defun synth-var (i)
  (intern (format nil "X~D" i) '#:player-user))

(defun synth-literal-form (i value)
  (if value (synth-var i) (list 'not (synth-var i))))

(defun make-synthetic-family (n &key (seed 1995) (events 6) (moves (max 2 (floor n 4)))
                                    (chain 0.7) (max-depth 16) optimize)
  "The synthetic spec of N boolean variables drawn with SEED: its ops, goals
and DEFSPEC body. Every op lasts 0.5 s; with OPTIMIZE (:steps or :duration),
the body says (:optimize OPTIMIZE) and each op lasts 0.25, 0.5, 1 or 2 s,
drawn with a second seed so that the family is otherwise the same."
  (let ((*random-state* (sb-ext:seed-random-state seed))
        (durations (sb-ext:seed-random-state (1+ seed)))
        (ops '())
        (goals '())
        (event-forms '()))
    (flet ((op (name pre-lits effects)
             ;; PRE-LITS and EFFECTS are lists of (VAR-INDEX . BOOLEAN).
             (let ((pre-mask 0) (pre-bits 0) (eff-mask 0) (eff-bits 0))
               (loop for (i . v) in pre-lits
                     do (setf pre-mask (logior pre-mask (ash 1 i)))
                        (when v (setf pre-bits (logior pre-bits (ash 1 i)))))
               (loop for (i . v) in effects
                     do (setf eff-mask (logior eff-mask (ash 1 i)))
                        (when v (setf eff-bits (logior eff-bits (ash 1 i)))))
               (let* ((adds (loop for (i . v) in effects when v collect (synth-var i)))
                      (subs (loop for (i . v) in effects unless v collect (synth-var i)))
                      (form `(player-user::op ,name
                               ,@(when pre-lits
                                   `(:precond (and ,@(loop for (i . v) in pre-lits
                                                           collect (synth-literal-form i v)))))
                               ,@(when adds `(:add ,adds))
                               ,@(when subs `(:sub ,subs))
                               :duration ,(if optimize
                                              (nth (random 4 durations) '(0.25 0.5 1 2))
                                              0.5))))
                 (push (make-synth-op name pre-mask pre-bits eff-mask eff-bits form) ops)))))
      (dotimes (i n)
        ;; X0 is the free end of the ring: its ops need nothing.
        (let ((name (intern (format nil "SET-~D" i) '#:player-user)))
          (op name (if (zerop i) '() (list (cons (1- i) (< (random 1.0) chain)))) (list (cons i t))))
        (let ((name (intern (format nil "CLR-~D" i) '#:player-user)))
          (op name (if (zerop i) '() (list (cons (mod (1+ i) n) (>= (random 1.0) chain)))) (list (cons i nil)))))
      (loop for k below moves
            for i = (random n)
            for j = (mod (1+ i) n)
            do (op (intern (format nil "MV-~D-~D" i k) '#:player-user)
                   (list (cons i t) (cons j nil))
                   (list (cons i nil) (cons j t))))
      (setf ops (nreverse ops))
      (dotimes (e events)
        (let* ((size (+ 2 (random 3)))
               (vars (loop with chosen = '()
                           until (= (length chosen) size)
                           do (pushnew (random n) chosen)
                           finally (return chosen)))
               (lits (mapcar (lambda (i) (cons i (< (random 2) 1))) vars))
               (mask (reduce #'logior vars :key (lambda (i) (ash 1 i))))
               (bits (reduce #'logior lits :key (lambda (l) (if (cdr l) (ash 1 (car l)) 0))))
               (op (nth (random (length ops)) ops))
               (name (intern (format nil "EV-~D" e) '#:player-user)))
          (push (list (cons mask bits)) goals)
          (push (list (cons (synth-op-pre-mask op) (synth-op-pre-bits op))) goals)
          (push `(player-user::event ,name
                   :state (and ,@(loop for (i . v) in lits collect (synth-literal-form i v)))
                   :op ,(synth-op-name op))
                event-forms))))
    (%make-synth-family
     n ops (remove-duplicates (nreverse goals) :test #'equal)
     `(,(format nil "Synthetic family, ~D boolean variables." n)
       (:max-depth ,max-depth)
       ,@(when optimize `((:optimize ,optimize)))
       ,@(loop for i below n collect `(player-user::state-variable ,(synth-var i) player-user::boolean player-user::false))
       ,@(mapcar #'synth-op-form ops)
       ,@(nreverse event-forms)))))

(defun define-synthetic-spec (family)
  "Define FAMILY's spec in Player; return it."
  (player:define-spec (intern (format nil "SYNTHETIC-~D" (synth-family-n family)) '#:player-user)
                      (synth-family-body family)
                      :package (find-package '#:player-user)))

;;; A random wide family: N boolean variables and 2N ops, each op guarded by
;;; a conjunction of 1-3 random literals and setting 1-2 random variables;
;;; four events ask for conjunctions of 3-6 random literals. Unlike the ring
;;; above, regression fans out into tens of thousands of plans per goal at
;;; N = 26: the case that made the old ResultQ scan quadratic (issue 13).

(defun make-random-wide-body (n &key (seed 26) (ops (* 2 n)) (events 4) (max-depth 16) optimize)
  "The DEFSPEC body of the random wide spec of N booleans drawn with SEED
(with (:optimize OPTIMIZE) when given; every op then lasts 0.5 s times 1 to 4)."
  (let ((*random-state* (sb-ext:seed-random-state seed)))
    (labels ((between (low high) (+ low (random (1+ (- high low)))))
             (variables (count)
               (loop with chosen = '()
                     until (= (length chosen) count)
                     do (pushnew (random n) chosen)
                     finally (return chosen)))
             (literals (count)
               (mapcar (lambda (i) (synth-literal-form i (zerop (random 2)))) (variables count))))
      `(,(format nil "Random wide spec, ~D boolean variables, seed ~D." n seed)
        (:max-depth ,max-depth)
        ,@(when optimize `((:optimize ,optimize)))
        ,@(loop for i below n collect `(player-user::state-variable ,(synth-var i) player-user::boolean player-user::false))
        ,@(loop for k below ops
                collect (let ((guard (literals (between 1 3)))
                              (effects (mapcar (lambda (i) (cons i (zerop (random 2)))) (variables (between 1 2))))
                              (duration (* 0.5 (between 1 4))))
                          `(player-user::op ,(intern (format nil "W~D" k) '#:player-user)
                             :precond (and ,@guard)
                             ,@(let ((adds (loop for (i . v) in effects when v collect (synth-var i))))
                                 (when adds `(:add ,adds)))
                             ,@(let ((subs (loop for (i . v) in effects unless v collect (synth-var i))))
                                 (when subs `(:sub ,subs)))
                             :duration ,duration)))
        ,@(loop for k below events
                collect `(player-user::event ,(intern (format nil "EV-~D" k) '#:player-user)
                           :state (and ,@(literals (between 3 6)))))))))

(defun define-random-wide-spec (n &rest options)
  "Define the random wide spec of N booleans (MAKE-RANDOM-WIDE-BODY's OPTIONS) in Player; return it."
  (player:define-spec (intern (format nil "RANDOM-WIDE-~D" n) '#:player-user)
                      (apply #'make-random-wide-body n options)
                      :package (find-package '#:player-user)))
