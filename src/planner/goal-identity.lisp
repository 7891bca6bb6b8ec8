;;;; goal-identity.lisp -- when two goals are one: the same set of states.
;;;; A goal's canonical DNF (SIMPLIFY-CUBES) is canonical for the way it is
;;;; written, not for what it means: (or a b) and (or a (and (not a) b)) are
;;;; different cube lists for one set of states. Comparing the sets themselves
;;;; makes such goals one goal, planned once.
;;;;
;;;; Containment is decided on cubes, never by enumerating states, so it costs
;;;; the same for a spec of 2^26 states as for Peedy's 144: a cube lies inside
;;;; a disjunction when one of its cubes holds it, or else when every part of
;;;; it, split on a variable where the disjunction tells states apart, does
;;;; (the classic recursive cover test).

(in-package #:player.planner)

(defun cube-meets-p (a b spec)
  "True when cubes A and B share a state."
  (not (cube-empty-p (logand a b) spec)))

(defun splitting-variable (cube cubes spec)
  "A plannable variable on which CUBE allows several values and some cube of
CUBES allows only part of them: splitting CUBE on it makes progress."
  (find-if (lambda (var)
             (let* ((mask (var-field-mask var))
                    (field (logand cube mask)))
               (and (> (logcount field) 1)
                    (some (lambda (c) (/= field (logand field c))) cubes))))
           (plannable-variables spec)))

(defun split-cube (cube var)
  "CUBE split on VAR: one cube per value of VAR it allows."
  (let* ((mask (var-field-mask var))
         (field (logand cube mask))
         (rest (logandc2 cube mask)))
    (loop for bit = (logand field (- field))
          until (zerop field)
          collect (logior rest bit)
          do (setf field (logandc2 field bit)))))

(defun cube-covered-p (cube cubes spec)
  "True when every state of the non-empty CUBE lies in some cube of CUBES."
  (let ((meeting (remove-if-not (lambda (c) (cube-meets-p cube c spec)) cubes)))
    (cond ((null meeting) nil)
          ((some (lambda (c) (cube-subset-p cube c)) meeting) t)
          (t (let ((var (splitting-variable cube meeting spec)))
               ;; A cube no single cube holds differs from each somewhere with
               ;; more than one value left, so VAR exists.
               (every (lambda (part) (cube-covered-p part meeting spec))
                      (split-cube cube var)))))))

(defun dnf-subset-p (inner outer spec)
  "True when every state of the disjunction INNER lies in the disjunction OUTER."
  (every (lambda (cube) (cube-covered-p cube outer spec)) inner))

(defun dnf-hull (cubes)
  "The smallest cube holding every state of the disjunction CUBES (non-empty
cubes): for each variable, the values some cube allows."
  (reduce #'logior cubes :initial-value 0))

(defun dnf-equivalent-p (a b spec)
  "True when the disjunctions of cubes A and B hold exactly the same states.
The same states have the same hull, and a single cube is its own hull: that
settles most pairs without the cover test (which costs a pass over the
variables per cube, and made interning a spec's N goals cost N^2 passes)."
  (or (equal a b)
      (and (= (dnf-hull a) (dnf-hull b))
           (not (and (null (rest a)) (null (rest b))))
           (dnf-subset-p a b spec) (dnf-subset-p b a spec))))

(defun find-equivalent-goal (cubes goals spec)
  "The goal among GOALS whose cubes hold exactly the states CUBES hold, or NIL:
the same cubes first (cheap), then the same set written otherwise."
  (or (find-goal cubes goals)
      (find-if (lambda (goal) (dnf-equivalent-p cubes (goal-cubes goal) spec)) goals)))
