;;;; validate.lisp -- checks that need the whole spec: class cycles, macro
;;;; recursion, and the events time variables listen to.

(in-package #:player.spec)

(defun validate-spec (spec)
  "Signal a SPEC-ERROR for whole-spec inconsistencies in SPEC."
  (check-class-cycles spec)
  (check-macro-cycles spec)
  (link-time-variables spec)
  spec)

(defun macro-sub-ops (op)
  "The ops a macro-op's :SEQ runs directly."
  (loop for directive in (op-seq op)
        when (eq (first directive) :op) collect (second directive)))

(defparameter *max-macro-expansion* 10000
  "The most primitive ops one macro-op may run, its sub-macros expanded: a
chain of macro-ops each running the next twice doubles at every link.")

(defparameter *max-macro-depth* 100
  "The deepest macro-ops may nest (a macro-op running one that runs one ...):
whatever walks a macro recurses once per level.")

(defun check-macro-cycles (spec)
  "Signal SPEC-SYNTAX-ERROR when a macro-op's :SEQ runs itself, directly or
not, runs more than *MAX-MACRO-EXPANSION* primitive ops (naming the chain
that multiplies them), or nests more than *MAX-MACRO-DEPTH* macro-ops deep.
Each op is visited once: its expansion and depth are remembered."
  (let ((sizes (make-hash-table :test 'eq)) (depths (make-hash-table :test 'eq)))
    (labels ((chain (op)
               ;; OP, then the sub-op of largest expansion, down to a primitive op.
               (loop for o = op then (let ((subs (macro-sub-ops o)))
                                       (and subs (reduce (lambda (a b) (if (>= (size a '()) (size b '())) a b))
                                                         subs)))
                     while o collect (lisp-text (op-name o))))
             (too-deep (op path)
               (spec-fail 'spec-syntax-error (op-form op) "nests macro-ops more than ~D deep, through ~{~A~^ -> ~} ..."
                          *max-macro-depth*
                          (mapcar (lambda (o) (lisp-text (op-name o))) (subseq path 0 (min 5 (length path))))))
             (size (op path)
               (when (> (length path) *max-macro-depth*)
                 (too-deep op (reverse path)))
               (when (member op path)
                 (spec-fail 'spec-syntax-error (op-form op) "macro-op ~A runs itself through ~{~A~^ -> ~}"
                            (lisp-text (op-name op))
                            (mapcar (lambda (o) (lisp-text (op-name o))) (reverse (cons op path)))))
               (or (gethash op sizes)
                   (setf (gethash op sizes)
                         (if (eq (op-kind op) :macro)
                             (let ((total (loop for sub in (macro-sub-ops op)
                                                sum (size sub (cons op path)))))
                               (when (> total *max-macro-expansion*)
                                 (setf (gethash op sizes) total)
                                 (spec-fail 'spec-syntax-error (op-form op)
                                            "runs ~:D ops through ~{~A~^ -> ~}; at most ~:D"
                                            total (chain op) *max-macro-expansion*))
                               (let ((depth (1+ (loop for sub in (macro-sub-ops op)
                                                      maximize (gethash sub depths 0)))))
                                 (setf (gethash op depths) depth)
                                 (when (> depth *max-macro-depth*)
                                   (too-deep op (cons op (macro-sub-ops op)))))
                               (max 1 total))
                             1)))))
      (dolist (op (spec-ops spec))
        (when (eq (op-kind op) :macro)
          (size op '()))))))

(defun link-time-variables (spec)
  "Tell each event which time variables it sets; unknown events are errors."
  (dolist (var (spec-variables spec))
    (when (eq (var-kind var) :time)
      (dolist (name (var-events var))
        (let ((event (find-event-named name)))
          (unless event
            (spec-fail 'unknown-name-error (var-form var) "unknown event ~A" (lisp-text name)))
          (pushnew var (event-time-variables event)))))))
