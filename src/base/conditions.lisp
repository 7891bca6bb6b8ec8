;;;; conditions.lisp -- Player's one condition tree.
;;;; Every error a user can cause is a PLAYER-ERROR whose report reads as a
;;;; sentence and names the offending form; the CLI prints that report as one line.

(in-package #:player.base)

(define-condition player-error (error)
  ()
  (:documentation "Root of every error Player signals on purpose."))

(defvar *source-position* nil
  "While a spec file is loaded: (FILE . CHARACTER-POSITION) of the form being read.")

(defvar *sub-form-places* nil
  "While the forms of a data file (a spec, script library or pose library) are
parsed: an EQ table from each list inside them to its (FILE . CHARACTER-POSITION)
\(see SUB-FORM-PLACES), so an error about a sub-form -- an item, a key, a
clause -- names the sub-form's own line; or NIL.")

(defvar *current-spec-name* nil
  "While a spec is parsed: its name, so errors can say which spec they are in.")

(defvar *current-form-label* nil
  "While one of a spec's forms is parsed: its kind and name (\"op whistle\"),
so errors can say which form they are in.")

(define-condition spec-error (player-error)
  ((message :initarg :message :reader spec-error-message)
   (form :initarg :form :initform nil :reader spec-error-form
         :documentation "The offending form, as written.")
   (spec :initarg :spec :initform *current-spec-name* :reader spec-error-spec
         :documentation "The name of the spec being defined, or NIL.")
   (position :initarg :position :initform *source-position*
             :reader %spec-error-position
             :documentation "(FILE . CHARACTER-POSITION) of the form at fault (or of the
top-level form around it), or NIL.")
   (places :initform *sub-form-places* :reader spec-error-places
           :documentation "The *SUB-FORM-PLACES* when the error was made, where FORM's own place may be.")
   (label :initarg :label :initform *current-form-label* :reader spec-error-label
          :documentation "The kind and name of the spec form at fault, e.g. \"op whistle\", or NIL."))
  (:report report-spec-error)
  (:documentation "A spec is malformed or inconsistent. FORM is the offending form."))

(defun spec-error-position (condition)
  "(FILE . CHARACTER-POSITION) of CONDITION's offending form: the form's own
place in its file when it was read from one (*SUB-FORM-PLACES*), else the
place the error was given (the form around it), or NIL."
  (let ((form (spec-error-form condition))
        (places (spec-error-places condition)))
    (or (and places (consp form) (values (gethash form places)))
        (%spec-error-position condition))))

(defun report-spec-error (condition stream)
  "Write CONDITION as one sentence: where, which spec, what, and the form."
  (let ((position (spec-error-position condition))
        (spec (spec-error-spec condition))
        (form (spec-error-form condition)))
    (when position
      (format stream "~A:~@[~D: ~]" (file-namestring (car position))
              (and (cdr position) (position-line (car position) (cdr position)))))
    (let ((label (spec-error-label condition)))
      ;; With a file and line, the label names the form; without, the spec too.
      (cond ((and label position) (format stream "~A: " label))
            ((and label spec) (format stream "in spec ~A, ~A: " (lisp-text spec) label))
            (spec (format stream "in spec ~A: " (lisp-text spec)))))
    (write-string (spec-error-message condition) stream)
    ;; A name the message already gives, or the labelled form itself, is not repeated.
    (when (and form (not (and (symbolp form) (search (lisp-text form) (spec-error-message condition))))
               (not (and (consp form) (spec-error-label condition)
                         (equal (form-label form) (spec-error-label condition)))))
      (format stream " in ~A" (bounded-lisp-text form 160)))))

(defun position-line (file position)
  "The 1-based line of character POSITION in FILE, or NIL if FILE can't be read."
  (ignore-errors
   ;; A regular file only (files.lisp): a FIFO in an error's place must not hang it.
   (call-with-input-file
    file (lambda (in)
           (loop with line = 1
                 repeat position
                 for char = (read-char in nil nil)
                 while char
                 when (char= char #\Newline) do (incf line)
                 finally (return line)))
    :external-format '(:utf-8 :replacement #\Replacement_Character))))

(defun truncate-text (string limit)
  "STRING, cut to LIMIT characters with an ellipsis when longer."
  (if (> (length string) limit)
      (concatenate 'string (subseq string 0 (- limit 3)) "...")
      string))

(macrolet ((define-spec-errors (&rest names-and-docs)
             `(progn
                ,@(loop for (name doc) on names-and-docs by #'cddr
                        collect `(define-condition ,name (spec-error) ()
                                   (:documentation ,doc))))))
  (define-spec-errors
    spec-syntax-error "A form does not have the shape the language requires."
    unknown-name-error "A form names a variable, class, op, event or label that is not defined."
    domain-error "A value lies outside its variable's domain."
    type-error-in-spec "A value has the wrong type for its variable or argument."
    duplicate-definition "A name is defined twice in one spec."
    class-cycle-error "State classes inherit from each other in a cycle."
    label-error "A label is used before it is set."
    effect-error "An op's or event's effects are impossible or contradictory."
    goal-error "A goal or precondition mentions a runtime-only variable."
    spec-reader-error "The Lisp reader could not read a spec file."
    untrusted-code-error "A spec holds :code or :c++, and code was refused (--no-code)."
    code-error "A :code form does not compile cleanly: it calls an undefined function, names an undefined variable, or draws another compiler warning."
    inexact-macro-error "Under (:macros :exact), a macro-op's :seq leaves a state other than the one its declared effects promise the planner."))

(defvar *form-places* nil
  "While a spec is parsed: a table from each of its top-level forms to its
(FILE . POSITION), so an error about a whole form found later (when the spec
is validated) still names its line.")

(defun spec-fail (class form control &rest arguments)
  "Signal a spec error of CLASS about FORM, with a message from CONTROL and ARGUMENTS."
  (let ((place (and *form-places* (consp form) (gethash form *form-places*))))
    (if place
        (error class :form form :position place :label (form-label form)
                     :message (apply #'format nil control arguments))
        (error class :form form :message (apply #'format nil control arguments)))))

(define-condition unknown-event (player-error)
  ((name :initarg :name :reader unknown-event-name)
   (known :initarg :known :initform nil :reader unknown-event-known))
  (:report (lambda (condition stream)
             (format stream "unknown event ~A~@[ (known events: ~{~A~^, ~})~]"
                     (let ((name (unknown-event-name condition)))
                       (if (stringp name) name (lisp-text name)))
                     (mapcar #'lisp-text (unknown-event-known condition)))))
  (:documentation "SEND-EVENT was given an event the controller's spec does not define."))

(define-condition player-error-with-message (player-error)
  ((message :initarg :message :reader player-error-message))
  (:report (lambda (condition stream) (write-string (player-error-message condition) stream)))
  (:documentation "A PLAYER-ERROR that is just its message (tool failures such as g++'s)."))

(define-condition state-space-too-large (player-error)
  ((states :initarg :states :reader too-large-states)
   (limit :initarg :limit :reader too-large-limit))
  (:report (lambda (condition stream)
             (format stream "the plannable state space has ~:D states, over the planner's limit of ~:D"
                     (too-large-states condition) (too-large-limit condition))))
  (:documentation "The product of the plannable domains is too large to plan for."))

(define-condition reachable-space-too-large (player-error)
  ((limit :initarg :limit :reader too-large-limit))
  (:report (lambda (condition stream)
             (format stream "more than ~:D states are reachable from the initial state and the :start-states, over the reachable planner's limit"
                     (too-large-limit condition))))
  (:documentation "The reachable regime found more states than it plans for (*REACHABLE-STATE-LIMIT*)."))

(define-condition state-outside-planned-set (player-error)
  ((spec :initarg :spec :reader outside-spec
         :documentation "The name of the spec.")
   (state :initarg :state :reader outside-state
          :documentation "The state, as its text (var=value ...).")
   (goal :initarg :goal :initform nil :reader outside-goal
         :documentation "The goal being achieved, as written, or NIL."))
  (:report (lambda (condition stream)
             (format stream "spec ~A has no plans from the state ~A~@[ (achieving ~A)~]: it is not reachable from the initial state or the :start-states; add it with (:start-states EXPR), or let the controller search at run time with (:unplanned-states :search)"
                     (outside-spec condition) (outside-state condition) (outside-goal condition))))
  (:documentation "A controller of a spec planned for its reachable states only is in, or
is asked to start from, a state outside them, and may not search at run time."))

(define-condition state-transfer-error (player-error)
  ((message :initarg :message :reader state-transfer-message))
  (:report (lambda (condition stream)
             (write-string (state-transfer-message condition) stream)))
  (:documentation "RECOMPILE or :INITIAL-STATE cannot express a state in the new machine."))

(defvar *condition-places* (make-hash-table :test 'eq :weakness :key :synchronized t)
  "Conditions a spec's own code signalled (a :code form), each mapped to the
line that says where that code is written and what it signalled.  The
condition itself is left as it is, so the code's own handlers and the REPL
see what the code signalled; the CLI's one error line says where.")

(defun note-condition-place (condition line)
  "Remember LINE as what CONDITION-LINE says of CONDITION, unless a place is
already known (the innermost code, whose handler runs first, names it)."
  (unless (nth-value 1 (gethash condition *condition-places*))
    (setf (gethash condition *condition-places*) line)))

(defun condition-line (condition)
  "CONDITION's report on one line (as the CLI prints errors), or a plain
description when reporting it fails.  A condition a spec's :code signalled
is reported with the place of that code (NOTE-CONDITION-PLACE)."
  (or (values (gethash condition *condition-places*))
      (let ((text (handler-case (princ-to-string condition)
                    (error () (format nil "~(~A~)" (type-of condition))))))
        (substitute #\Space #\Newline (string-trim '(#\Space #\Newline) text)))))
