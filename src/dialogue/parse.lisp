;;;; parse.lisp -- DEFDIALOGUE: a dialogue's forms into a DIALOGUE, checked.
;;;;   (defdialogue NAME [DOC] (:OPTION VALUE)... FORM...)
;;;; Options: (:player SPEC) the Player spec it animates (a spec file, relative
;;;; to the dialogue's file, or a spec's name), (:player-initial ALIST) its
;;;; initial state, (:catalogue FILE), (:initial STATE) (else the first state),
;;;; (:not-understood EVENT) the input when nothing matches, (:ignore-words
;;;; "please" ...).  Forms: (state NAME [DOC]); (input NAME [DOC] [:query
;;;; (ACTION...)]); (phrases NAME "words"...); (utterance EVENT ELEMENT...);
;;;; (animation NAME PLAYER-EVENT...); (template CATEGORY PROBABILITY "TEXT"
;;;; [:if EXPRESSION] [:limit :conversation|:user]); (on STATE EVENT [:if
;;;; EXPRESSION] [:to STATE] [:do (ACTION...)]), STATE * for any state;
;;;; (synonyms "CANONICAL" "PHRASE"...) and (fillers "PHRASE"...), the
;;;; vocabulary sentences are rewritten with before they are matched;
;;;; (cd ...) catalogue entries.  Declarations are read first, so forms may
;;;; name what is defined after them.

(in-package #:player.dialogue)

(defparameter *dialogue-options*
  '(:player :player-initial :catalogue :initial :not-understood :ambiguous :ignore-words)
  "The (:KEY VALUE) options a DEFDIALOGUE may start with.")

(defmacro defdialogue (name &body body)
  "Define (or redefine) the dialogue NAME from BODY, as data; see DEFINE-DIALOGUE."
  `(define-dialogue ',name ',body))

(defun form-head-p (form name)
  "Is FORM a list whose first element is the symbol NAME (by name)?"
  (and (consp form) (symbolp (first form)) (same-name-p (first form) name)))

(defun form-properties (form start allowed)
  "The plist of FORM from its element START on, checked against the ALLOWED keys."
  (let ((plist (nthcdr start form)))
    (unless (and (alexandria:proper-list-p plist) (evenp (length plist)))
      (dialogue-fail form "expected :KEY VALUE pairs after ~A" (bounded-lisp-text (subseq form 0 (min start (length form))) 60)))
    (loop for (key) on plist by #'cddr
          unless (member key allowed)
            do (dialogue-fail form "unknown property ~A (allowed: ~{~(~S~)~^ ~})" (lisp-text key) allowed))
    plist))

(defun require-dialogue-name (thing form what)
  "THING if it names something (a non-keyword symbol), else a DIALOGUE-ERROR."
  (unless (and (symbolp thing) thing (not (keywordp thing)) (not (eq thing t)))
    (dialogue-fail form "~A must be a name, not ~A" what (bounded-lisp-text thing 60)))
  thing)

(defmacro with-form-label ((form) &body body)
  "Run BODY with FORM's label (\"on stGotCD\") as the current form's, for errors."
  `(with-spec-context (:form-label (dialogue-form-label ,form)
                       :source-position (or (and (consp ,form) (gethash ,form *form-places*))
                                            *source-position*))
     ,@body))

(defun define-dialogue (name body &key source-file form-positions)
  "Parse BODY, the forms after DEFDIALOGUE NAME, into a checked DIALOGUE and
register it under NAME (replacing a dialogue of that name); return it.
SOURCE-FILE is the file it comes from (relative :player and :catalogue files
are found beside it), FORM-POSITIONS BODY's forms' character positions there.
Signals a DIALOGUE-ERROR naming the offending form, with file and line."
  (let* ((name (require-dialogue-name name name "a dialogue name"))
         (*current-dialogue-name* name))
    (with-spec-context (:form-places (form-places body form-positions source-file))
      (let ((dialogue (%make-dialogue :name name :source-file source-file)))
        (unless (alexandria:proper-list-p body)
          (dialogue-fail nil "the body of a defdialogue must be a list of forms"))
        (let ((forms (parse-dialogue-header dialogue body)))
          (dolist (form forms) (with-form-label (form) (declare-dialogue-form dialogue form)))
          (finish-declarations dialogue)
          (dolist (form forms) (with-form-label (form) (define-dialogue-form dialogue form)))
          (setf (dialogue-utterances dialogue) (reverse (dialogue-utterances dialogue))
                (dialogue-transitions dialogue) (reverse (dialogue-transitions dialogue)))
          (check-input-queries dialogue)
          (setf (gethash (dialogue-key name) *dialogues*) dialogue))))))

;;;# The header

(defun parse-dialogue-header (dialogue body)
  "Read BODY's docstring and options into DIALOGUE; return the remaining forms."
  (when (stringp (first body))
    (setf (dialogue-documentation dialogue) (pop body)))
  (loop while (and (consp (first body)) (keywordp (first (first body))))
        do (let ((option (pop body)))
             (unless (and (alexandria:proper-list-p option) (member (first option) *dialogue-options*)
                          (or (= (length option) 2) (eq (first option) :ignore-words)))
               (dialogue-fail option "unknown or malformed dialogue option (allowed: ~{(~(~S~) VALUE)~^ ~})"
                              *dialogue-options*))
             (let ((value (second option)))
               (ecase (first option)
                 (:player (setf (dialogue-player-spec dialogue) (find-player-spec dialogue value option)))
                 (:player-initial
                  (unless (initial-state-p value)
                    (dialogue-fail option ":player-initial must be an alist ((VARIABLE . VALUE) ...)"))
                  (setf (dialogue-player-initial dialogue) value))
                 (:catalogue (alexandria:appendf (dialogue-catalogue dialogue)
                                                 (read-catalogue-file (dialogue-relative-file dialogue value option))))
                 (:initial (setf (dialogue-initial-state dialogue) (require-dialogue-name value option "the initial state")))
                 (:not-understood (setf (dialogue-not-understood dialogue)
                                        (require-dialogue-name value option "the not-understood event")))
                 (:ambiguous (setf (dialogue-ambiguous dialogue)
                                   (require-dialogue-name value option "the input asking which one")))
                 (:ignore-words
                  (unless (every #'stringp (rest option))
                    (dialogue-fail option ":ignore-words takes strings"))
                  (setf (dialogue-ignore-words dialogue) (mapcan #'text-words (rest option))))))))
  body)

(defun dialogue-relative-file (dialogue file form)
  "FILE (a string) beside DIALOGUE's source file, as a pathname."
  (unless (and (stringp file) (plusp (length file)))
    (dialogue-fail form "expected a file name string, not ~A" (bounded-lisp-text file 60)))
  (merge-pathnames file (or (dialogue-source-file dialogue) *default-pathname-defaults*)))

(defun find-player-spec (dialogue designator form)
  "The Player spec DESIGNATOR names: a spec file (its first spec) or a defined spec's name."
  (if (stringp designator)
      (let ((specs (load-spec (dialogue-relative-file dialogue designator form))))
        (or (first specs) (dialogue-fail form "~A defines no spec" designator)))
      (or (and (symbolp designator) designator (find-spec designator nil))
          (dialogue-fail form "no Player spec ~A is defined" (bounded-lisp-text designator 60)))))

(defun player-event-p (dialogue name)
  "Is NAME an event of DIALOGUE's Player spec?"
  (let ((spec (dialogue-player-spec dialogue)))
    (and spec (symbolp name)
         (find (dialogue-key name) (spec-events spec) :key (lambda (e) (dialogue-key (event-name e)))
                                                      :test #'string=))))

;;;# Declarations

(defun declare-once (table name form what)
  "Check NAME is not yet in TABLE (a declared WHAT)."
  (when (gethash (dialogue-key name) table)
    (dialogue-fail form "~A ~A is declared twice" what (display-name name))))

(defun declare-dialogue-form (dialogue form)
  "First pass: record FORM's declaration (states, inputs, phrases, animations,
templates, CDs) in DIALOGUE."
  (unless (and (alexandria:proper-list-p form) (symbolp (first form)) (first form))
    (dialogue-fail form "a dialogue form is (KIND NAME ...), not ~A" (bounded-lisp-text form 60)))
  (cond ((form-head-p form "state")
         (let ((name (require-dialogue-name (second form) form "a state")))
           (declare-once (dialogue-states dialogue) name form "state")
           (setf (gethash (dialogue-key name) (dialogue-states dialogue)) name)
           (push name (dialogue-state-order dialogue))))
        ((form-head-p form "input")
         (let* ((name (require-dialogue-name (second form) form "an input event"))
                (rest (cddr form))
                (doc (and (stringp (first rest)) (pop rest))))
           (declare-once (dialogue-inputs dialogue) name form "input event")
           (setf (gethash (dialogue-key name) (dialogue-inputs dialogue))
                 (make-input-def :name name :documentation doc :form form
                                 :query (getf (form-properties form (if doc 3 2) '(:query)) :query)))))
        ((form-head-p form "phrases")
         (let ((name (require-dialogue-name (second form) form "a phrases set")))
           (declare-once (dialogue-phrases dialogue) name form "phrases set")
           (unless (and (cddr form) (every (lambda (p) (and (stringp p) (text-words p))) (cddr form)))
             (dialogue-fail form "(phrases NAME \"words\" ...) needs strings of words"))
           (setf (gethash (dialogue-key name) (dialogue-phrases dialogue)) (cddr form))))
        ((form-head-p form "synonyms")
         (alexandria:appendf (dialogue-rewrites dialogue) (parse-synonyms-form form)))
        ((form-head-p form "fillers")
         (alexandria:appendf (dialogue-rewrites dialogue) (parse-fillers-form form)))
        ((form-head-p form "animation") (declare-animation dialogue form))
        ((form-head-p form "template") (declare-template dialogue form))
        ((catalogue-form-p form) (alexandria:appendf (dialogue-catalogue dialogue) (list (parse-cd form))))
        ((or (form-head-p form "utterance") (form-head-p form "on")))
        (t (dialogue-fail form "unknown dialogue form ~A (known: state input phrases synonyms fillers utterance animation template on cd)"
                          (display-name (first form))))))

(defun declare-animation (dialogue form)
  "Record (animation NAME PLAYER-EVENT...), each event one of the Player spec's."
  (let ((name (require-dialogue-name (second form) form "an animation")))
    (declare-once (dialogue-animations dialogue) name form "animation")
    (unless (cddr form)
      (dialogue-fail form "(animation NAME PLAYER-EVENT...) names no Player event"))
    (unless (dialogue-player-spec dialogue)
      (dialogue-fail form "an animation needs the dialogue's Player spec: give (:player SPEC)"))
    (dolist (event (cddr form))
      (unless (player-event-p dialogue event)
        (dialogue-fail form "~A is not an event of Player spec ~A"
                       (name-text event) (display-name (spec-name (dialogue-player-spec dialogue))))))
    (setf (gethash (dialogue-key name) (dialogue-animations dialogue))
          (make-animation :name name :events (cddr form) :form form))))

(defun declare-template (dialogue form)
  "Record (template CATEGORY PROBABILITY \"TEXT\" [:if E] [:limit SPAN])."
  (unless (and (>= (length form) 4) (stringp (fourth form)))
    (dialogue-fail form "expected (template CATEGORY PROBABILITY \"TEXT\" [:if EXPRESSION] [:limit :conversation|:user])"))
  (let ((category (require-dialogue-name (second form) form "a template category"))
        (probability (third form))
        (properties (form-properties form 4 '(:if :limit))))
    (unless (and (realp probability) (<= 0 probability 1))
      (dialogue-fail form "template probability ~A is outside 0..1" (bounded-lisp-text probability 40)))
    (unless (member (getf properties :limit) '(nil :conversation :user))
      (dialogue-fail form ":limit must be :conversation or :user, not ~A" (lisp-text (getf properties :limit))))
    (when (getf properties :if) (check-expression (getf properties :if) form))
    (let ((templates (gethash (dialogue-key category) (dialogue-templates dialogue))))
      (setf (gethash (dialogue-key category) (dialogue-templates dialogue))
            (append templates
                    (list (make-template :category category :probability probability :text (fourth form)
                                         :condition (getf properties :if) :limit (getf properties :limit)
                                         :index (1+ (length templates)) :form form)))))))

(defun finish-declarations (dialogue)
  "After the first pass: the initial state and the not-understood event exist;
the ignored words join the fillers, and the vocabulary is sorted longest first."
  (setf (dialogue-rewrites dialogue)
        (sort-rewrites (append (dialogue-rewrites dialogue)
                               (mapcar (lambda (word) (make-rewrite (list word) '() :filler))
                                       (dialogue-ignore-words dialogue)))))
  (unless (dialogue-state-order dialogue)
    (dialogue-fail nil "a dialogue needs at least one (state NAME)"))
  (let ((initial (or (dialogue-initial-state dialogue) (first (dialogue-state-names dialogue)))))
    (check-state dialogue initial nil)
    (setf (dialogue-initial-state dialogue) (gethash (dialogue-key initial) (dialogue-states dialogue))))
  (let ((event (dialogue-not-understood dialogue)))
    (when event (check-input dialogue event nil))))

(defun check-state (dialogue name form)
  "NAME, a conversational state of DIALOGUE; else a DIALOGUE-ERROR naming FORM."
  (or (and (symbolp name) (gethash (dialogue-key name) (dialogue-states dialogue)))
      (dialogue-fail form "unknown conversational state ~A (known: ~{~A~^, ~})" (name-text name)
                     (mapcar #'display-name (dialogue-state-names dialogue)))))

(defun check-input (dialogue name form)
  "NAME's input event of DIALOGUE; else a DIALOGUE-ERROR naming FORM."
  (or (and (symbolp name) (gethash (dialogue-key name) (dialogue-inputs dialogue)))
      (dialogue-fail form "unknown input event ~A (known: ~{~A~^, ~})" (name-text name)
                     (sort (mapcar #'display-name (dialogue-input-names dialogue)) #'string-lessp))))

;;;# Definitions

(defun define-dialogue-form (dialogue form)
  "Second pass: utterance patterns and transitions."
  (cond ((form-head-p form "utterance")
         (unless (and (cddr form) (alexandria:proper-list-p form))
           (dialogue-fail form "expected (utterance EVENT ELEMENT...)"))
         (let ((event (input-name (check-input dialogue (second form) form))))
           (push (make-utterance-pattern :event event :form form
                                 :elements (mapcar (lambda (e) (parse-pattern-element dialogue e form)) (cddr form)))
                 (dialogue-utterances dialogue))))
        ((form-head-p form "on") (push (parse-transition dialogue form) (dialogue-transitions dialogue)))))

(defun parse-transition (dialogue form)
  "The transition (on STATE EVENT [:if E] [:to STATE] [:do (ACTION...)]) describes."
  (unless (>= (length form) 3)
    (dialogue-fail form "expected (on STATE EVENT [:if EXPRESSION] [:to STATE] [:do (ACTION...)])"))
  (let* ((from (if (and (symbolp (second form)) (same-name-p (second form) "*"))
                   :any
                   (check-state dialogue (second form) form)))
         (event (input-name (check-input dialogue (third form) form)))
         (properties (form-properties form 3 '(:if :to :do)))
         (actions (getf properties :do)))
    (when (getf properties :if) (check-expression (getf properties :if) form))
    (unless (alexandria:proper-list-p actions)
      (dialogue-fail form ":do takes a list of actions"))
    (dolist (action actions) (check-action dialogue action form))
    (make-transition :from from :event event
                     :predicate (or (getf properties :if) t)
                     :to (and (getf properties :to) (check-state dialogue (getf properties :to) form))
                     :actions actions :form form)))

(defun check-input-queries (dialogue)
  "Last check: every input's query is made of known actions, called as they take."
  (loop for input being the hash-values of (dialogue-inputs dialogue)
        do (with-form-label ((input-form input))
             (unless (alexandria:proper-list-p (input-query input))
               (dialogue-fail (input-form input) ":query takes a list of actions"))
             (dolist (action (input-query input))
               (check-action dialogue action (input-form input))))))
