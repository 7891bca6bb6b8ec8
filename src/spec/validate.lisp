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

(defun check-macro-cycles (spec)
  "Signal SPEC-SYNTAX-ERROR when a macro-op's :SEQ runs itself, directly or not."
  (labels ((visit (op path)
             (when (member op path)
               (spec-fail 'spec-syntax-error (op-form op) "macro-op ~A runs itself through ~{~A~^ -> ~}"
                          (lisp-text (op-name op))
                          (mapcar (lambda (o) (lisp-text (op-name o))) (reverse (cons op path)))))
             (dolist (sub (macro-sub-ops op))
               (visit sub (cons op path)))))
    (dolist (op (spec-ops spec))
      (when (eq (op-kind op) :macro)
        (visit op '())))))

(defun link-time-variables (spec)
  "Tell each event which time variables it sets; unknown events are errors."
  (dolist (var (spec-variables spec))
    (when (eq (var-kind var) :time)
      (dolist (name (var-events var))
        (let ((event (find-event-named name)))
          (unless event
            (spec-fail 'unknown-name-error (var-form var) "unknown event ~A" (lisp-text name)))
          (pushnew var (event-time-variables event)))))))
