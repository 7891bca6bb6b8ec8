;;;; code-sites.lisp -- where a spec holds code: :code forms (Lisp, evaluated
;;;; when they run) and :c++ text (copied into the generated C++).  A spec
;;;; from an untrusted source can be refused when it has any (--no-code).
;;;; Each :code form's place is kept, so an error found when it is compiled
;;;; (an undefined function) names its file and line.

(in-package #:player.spec)

(defun directive-code-sites (directives owner)
  "The code in parsed DIRECTIVES of OWNER (a description such as \"event ev\"),
as (DESCRIPTION ...) strings, :if bodies included."
  (loop for directive in directives
        append (case (first directive)
                 (:code (list (format nil "~A: :code ~A" owner (bounded-lisp-text (second directive) 60))))
                 (:c++ (list (format nil "~A: :c++" owner)))
                 (:if (directive-code-sites (third directive) owner)))))

(defun spec-code-sites (spec)
  "Every place SPEC holds code, described for a message: ops with :code or
:c++, and :code and :c++ directives of events and macro-ops."
  (append (loop for op in (spec-ops spec)
                for owner = (format nil "~:[op~;macro-op~] ~A" (eq (op-kind op) :macro)
                                    (lisp-text (op-name op)))
                when (eq (op-kind op) :code) collect (format nil "~A: :code" owner)
                when (op-c++ op) collect (format nil "~A: :c++" owner)
                append (directive-code-sites (op-seq op) owner))
          (loop for event in (spec-events spec)
                append (directive-code-sites (event-directives event)
                                             (format nil "event ~A" (lisp-text (event-name event)))))))

(defun refuse-code (spec)
  "Signal an UNTRUSTED-CODE-ERROR when SPEC holds any code."
  (let ((sites (spec-code-sites spec)))
    (when sites
      (spec-fail 'untrusted-code-error nil
                 "code refused: the spec holds ~{~A~^; ~}~@[ and ~D more~] (run without --no-code only if you trust it)"
                 (subseq sites 0 (min 3 (length sites))) (and (> (length sites) 3) (- (length sites) 3))))))

;;;# Where each :code form is written

(defun note-code-form (form)
  "Remember where the :code FORM of the spec being parsed is written (its
own place when the file's sub-forms are known, else its spec form's) and
the label of the form holding it; return FORM."
  (when *spec*
    (setf (gethash form (spec-code-places *spec*))
          (cons (or (and *sub-form-places* (consp form) (values (gethash form *sub-form-places*)))
                    *source-position*)
                *current-form-label*)))
  form)

(defun directive-code-forms (directives)
  "The :code forms of parsed DIRECTIVES, :if bodies included."
  (loop for directive in directives
        append (case (first directive)
                 (:code (list (second directive)))
                 (:if (directive-code-forms (third directive))))))

(defun spec-code-forms (spec)
  "Every :code form of SPEC: its ops' (:code FORM), and the :code directives
of its macro-ops and events, in definition order."
  (append (loop for op in (spec-ops spec)
                when (eq (op-kind op) :code) collect (op-code op)
                append (directive-code-forms (op-seq op)))
          (loop for event in (spec-events spec)
                append (directive-code-forms (event-directives event)))))

(defun code-condition (spec form control &rest arguments)
  "A CODE-ERROR about the :code FORM of SPEC, naming the file, line and form
it is written in, with a message from CONTROL and ARGUMENTS; not signalled."
  (destructuring-bind (&optional place . label) (gethash form (spec-code-places spec))
    (make-condition 'code-error :form form :position place :label label :spec (spec-name spec)
                                :message (apply #'format nil control arguments))))

(defun code-fail (spec form control &rest arguments)
  "Signal a CODE-ERROR about the :code FORM of SPEC (see CODE-CONDITION)."
  (error (apply #'code-condition spec form control arguments)))
