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
                                    (chain 0.7) (max-depth 16))
  "The synthetic spec of N boolean variables drawn with SEED: its ops, goals
and DEFSPEC body."
  (let ((*random-state* (sb-ext:seed-random-state seed))
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
                               :duration 0.5)))
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
       ,@(loop for i below n collect `(player-user::state-variable ,(synth-var i) player-user::boolean player-user::false))
       ,@(mapcar #'synth-op-form ops)
       ,@(nreverse event-forms)))))

(defun define-synthetic-spec (family)
  "Define FAMILY's spec in Player; return it."
  (player:define-spec (intern (format nil "SYNTHETIC-~D" (synth-family-n family)) '#:player-user)
                      (synth-family-body family)
                      :package (find-package '#:player-user)))
