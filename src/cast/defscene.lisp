;;;; defscene.lisp -- DEFSCENE: several characters in one scene.  A scene's
;;;; cast is a list of members, each naming a defined spec, placed somewhere
;;;; in the world; members of one spec share its compiled machine, each with
;;;; a controller of its own (the CHI'95 paper's "automatically duplicating
;;;; the name space ... to allow multiple identical agents to be controlled in
;;;; the same scene").  A scene may also define scene events, each sending
;;;; events to several members at once.
;;;;
;;;;   (defscene duet "Two Peedys."
;;;;     (peedy :as left :at (-0.3 0 0))
;;;;     (peedy :as right :at (0.3 0 0))
;;;;     (event ev-both-search left/ev-search right/ev-search)
;;;;     (event ev-wave (left/ev-hello :after 0) (right/ev-hello :after 0.5)))

(in-package #:player.cast)

(defparameter *member-spacing* 0.6d0
  "Metres between neighbouring members placed without :at: they stand in a
row along x, centred on the origin.")

(defstruct (cast-member (:constructor %make-cast-member))
  "One character of a scene: its NAME (a symbol, unique in the scene), the SPEC
it plays (a spec's name), its POSITION in the world (a vec3), the INITIAL
values its controller starts from (an alist, as for MAKE-CONTROLLER) and the
FORM it was written as.  EXPLICIT when the form places it (:at); else it
stands in a row, which playing moves clear of the set (placement.lisp)."
  name spec position initial form explicit)

(defstruct (cast (:constructor %make-cast))
  "A scene of several characters, as DEFSCENE defines it: its NAME, DOCUMENTATION,
MEMBERS (CAST-MEMBERs, in order), EVENTS (scene events, an alist from a name to
the event addresses it sends), the SOURCE-FILE it came from, if any, and the
script library whose objects make its SET (a pathname from a (set \"FILE\")
form), or NIL: then the set is the first member's library's."
  name documentation members events source-file (set nil))

;;; At the REPL, one line each, as specs and controllers print:
;;;   #<CAST two-peedys: left right, 2 events>   #<CAST-MEMBER left: peedy at (-0.35 0 0)>

(defmethod print-object ((cast cast) stream)
  (print-unreadable-object (cast stream :type t)
    (format stream "~A:~{ ~A~}~:[~;, ~:*~D event~:P~]" (lisp-text (cast-name cast))
            (mapcar (lambda (member) (lisp-text (cast-member-name member))) (cast-members cast))
            (and (cast-events cast) (length (cast-events cast))))))

(defmethod print-object ((member cast-member) stream)
  (print-unreadable-object (member stream :type t)
    (format stream "~A: ~A~@[ at (~{~A~^ ~})~]" (lisp-text (cast-member-name member))
            (lisp-text (cast-member-spec member))
            (mapcar #'format-number (cast-member-position member)))))

(defvar *casts* (make-hash-table :test 'equal)
  "Defined scenes, by name key.")

;;;# Member names

(defun member-name-p (name)
  "Can NAME be a member's name: a non-keyword symbol without / or +, other than ALL?"
  (and (symbolp name) name (not (keywordp name)) (not (eq name t))
       (not (find-if (lambda (c) (find c "/+@,")) (symbol-name name)))
       (string/= (symbol-name name) "ALL")))

(defun vec3-form-p (x)
  "Is X a list of three finite reals?"
  (and (alexandria:proper-list-p x) (= (length x) 3) (every #'finite-real-p x)))

;;;# Parsing

(defun scene-event-form-p (form)
  "Is FORM an (event NAME ADDRESS...) form of a scene?"
  (and (consp form) (symbolp (first form)) (string= (symbol-name (first form)) "EVENT")))

(defun scene-set-form-p (form)
  "Is FORM a (set \"FILE\") form of a scene, naming the library of its set?"
  (and (consp form) (symbolp (first form)) (string= (symbol-name (first form)) "SET")
       (consp (rest form)) (stringp (second form))))

(defun parse-scene-set (forms source-file)
  "The script library file the (set \"FILE\") form among FORMS names,
resolved against SOURCE-FILE, or NIL without one.  Signals a SCENE-ERROR for
two set forms, a malformed one, or a file that does not exist."
  (let ((sets (remove-if-not #'scene-set-form-p forms)))
    (when sets
      (with-spec-context (:source-position (or (form-place (first sets)) *source-position*))
        (cond ((rest sets) (scene-fail 'scene-error (second sets) "a scene has one set: (set \"FILE\") is given twice"))
              ((cddr (first sets))
               (scene-fail 'scene-error (first sets) "a scene's set is (set \"FILE\"), a script library's file, not ~A"
                           (bounded-lisp-text (first sets) 60))))
        (let ((path (merge-pathnames (second (first sets))
                                     (or source-file *default-pathname-defaults*))))
          (or (probe-file path)
              (scene-fail 'scene-error (first sets) "the scene's set ~A does not exist" (namestring path))))))))

(defun parse-cast-member (form)
  "The CAST-MEMBER a (SPEC [:as NAME] [:at (X Y Z)] [:initial ALIST]) FORM
declares, its POSITION NIL when FORM gives none.  Signals a SCENE-ERROR for a
malformed form, a MISSING-MEMBER-SPEC-ERROR when SPEC is not defined."
  (unless (and (alexandria:proper-list-p form) (symbolp (first form)) (first form)
               (evenp (length (rest form))))
    (scene-fail 'scene-error form "a member is (SPEC :as NAME [:at (X Y Z)] [:initial ((VAR . VALUE) ...)]), not ~A"
                (bounded-lisp-text form 80)))
  (let ((spec-name (first form)) (options (rest form)))
    (loop for key in options by #'cddr
          unless (member key '(:as :at :initial))
            do (scene-fail 'scene-error form "member ~A: unknown option ~A (known: :as :at :initial)"
                           (lisp-text spec-name) (bounded-lisp-text key 40)))
    (destructuring-bind (&key (as spec-name) at initial) options
      (unless (member-name-p as)
        (scene-fail 'scene-error form "a member's name must be a symbol without / + @ or , and not ALL, not ~A"
                    (bounded-lisp-text as 60)))
      (unless (or (null at) (vec3-form-p at))
        (scene-fail 'scene-error form "member ~A: :at takes (X Y Z), three numbers of metres, not ~A"
                    (lisp-text as) (bounded-lisp-text at 60)))
      (unless (initial-state-p initial)
        (scene-fail 'scene-error form "member ~A: :initial takes ((VAR . VALUE) ...), not ~A"
                    (lisp-text as) (bounded-lisp-text initial 60)))
      (unless (find-spec spec-name nil)
        (scene-fail 'missing-member-spec-error form "member ~A plays spec ~A, which is not defined~:[~*~; and not in a file ~A.lisp beside the scene's~]~@[ (defined: ~{~A~^, ~})~]"
                    (lisp-text as) (lisp-text spec-name) (car *source-position*) (lisp-text spec-name)
                    (mapcar #'lisp-text (list-specs))))
      (%make-cast-member :name as :spec (spec-name (find-spec spec-name))
                         :position (and at (mapcar (lambda (x) (float x 1d0)) at)) :explicit (and at t)
                         :initial initial :form form))))

(defun place-members (members)
  "Give each of MEMBERS without a position its place in a row along x, centred
on the origin, *MEMBER-SPACING* apart (counting every member, placed or not)."
  (let ((middle (/ (1- (length members)) 2)))
    (loop for member in members
          for k from 0
          unless (cast-member-position member)
            do (setf (cast-member-position member)
                     (list (* *member-spacing* (- k middle)) 0d0 0d0)))
    members))

(defun check-member-names (members)
  "Signal a DUPLICATE-MEMBER-ERROR, at the second's form, when two MEMBERS share a name."
  (loop for (member . rest) on members
        for twin = (find (cast-member-name member) rest :key #'cast-member-name :test #'string=)
        when twin
          do (with-spec-context (:source-position (or (form-place (cast-member-form twin)) *source-position*))
               (scene-fail 'duplicate-member-error (cast-member-form twin)
                           "two members are called ~A: give each its own name with :as"
                           (lisp-text (cast-member-name member))))))

(defvar *scene-form-places* nil
  "While a scene is parsed from a file: a table from its forms to their (FILE . POSITION).")

(defun form-place (form)
  "Where FORM was read, (FILE . POSITION), when a scene file is being read."
  (and *scene-form-places* (gethash form *scene-form-places*)))

(defun timed-address-p (x)
  "Is X a scene event's (ADDRESS :after SECONDS), SECONDS a finite number from 0?"
  (and (alexandria:proper-list-p x) (= (length x) 3) (eq (second x) :after)
       (finite-real-p (third x)) (<= 0 (third x) *max-seconds*)))

(defun parse-scene-event (form members)
  "(NAME . ADDRESSES) for the scene event FORM, (event NAME ADDRESS...), each
ADDRESS, or (ADDRESS :after SECONDS), checked against MEMBERS (see
PARSE-EVENT-ADDRESS)."
  (destructuring-bind (name &rest addresses) (rest form)
    (unless (and (symbolp name) name (not (find #\/ (symbol-name name))) addresses)
      (scene-fail 'scene-error form "a scene event is (event NAME MEMBER/EVENT ...), NAME without /, not ~A"
                  (bounded-lisp-text form 80)))
    (cons name (loop for address in addresses
                     do (when (and (consp address) (not (timed-address-p address)))
                          (scene-fail 'scene-error form "scene event ~A: an address is MEMBER/EVENT or (MEMBER/EVENT :after SECONDS), not ~A"
                                      (lisp-text name) (bounded-lisp-text address 60)))
                        (check-scene-event-address name (if (consp address) (first address) address) members form)
                     collect address))))

(defun check-scene-event-address (name address members form)
  "Check ADDRESS of the scene event NAME (in FORM) against MEMBERS: its members
exist (PARSE-EVENT-ADDRESS) and each one's spec defines its event, so `check`
catches an unknown event rather than the event failing when sent."
  (multiple-value-bind (addressed event) (parse-event-address address members)
    (dolist (member addressed)
      (let ((spec (find-spec (cast-member-spec member) nil)))
        (when (and spec (notany (lambda (e) (string-equal (symbol-name (event-name e)) (string event)))
                                (spec-events spec)))
          (scene-fail 'scene-error form "scene event ~A: member ~A plays spec ~A, which has no event ~A"
                      (lisp-text name) (lisp-text (cast-member-name member))
                      (lisp-text (cast-member-spec member)) (string-downcase (string event))))))))

(defun define-cast (name body &key source-file form-positions)
  "Parse BODY, ([DOCSTRING] MEMBER-OR-EVENT...), as the scene NAME, register it
\(replacing an older one of that name) and return the CAST.  FORM-POSITIONS,
the positions of BODY's forms in SOURCE-FILE, let errors name their lines.
Signals a SCENE-ERROR for a malformed form, a MISSING-MEMBER-SPEC-ERROR for
a member naming an undefined spec, a DUPLICATE-MEMBER-ERROR for two members
of one name, an UNKNOWN-MEMBER-ERROR for a scene event addressed to no member."
  (with-spec-context (:form-label (format nil "scene ~A" (lisp-text name)))
    (let ((*scene-form-places* (make-hash-table :test 'eq)))
      (check-form-structure (cons name body) :what "defscene form")
      (unless (member-name-p name)
        (scene-fail 'scene-error (list 'defscene name) "a scene's name must be a symbol, not ~A"
                    (bounded-lisp-text name 60)))
      (unless (alexandria:proper-list-p body)
        (scene-fail 'scene-error nil "the body of defscene ~A is not a proper list" (lisp-text name)))
      (when source-file
        (loop for form in body for position in form-positions
              do (setf (gethash form *scene-form-places*) (cons source-file position))))
      (let* ((documentation (and (stringp (first body)) (rest body) (first body)))
             (forms (if documentation (rest body) body))
             (members '()) (events '()))
        (dolist (form forms)
          (with-spec-context (:source-position (or (form-place form) *source-position*))
            (unless (or (scene-event-form-p form) (scene-set-form-p form))
              (push (parse-cast-member form) members))))
        (setf members (place-members (nreverse members)))
        (unless members
          (scene-fail 'scene-error (list 'defscene name) "scene ~A has no members: give (SPEC :as NAME ...) forms"
                      (lisp-text name)))
        (check-member-names members)
        (dolist (form forms)
          (with-spec-context (:source-position (or (form-place form) *source-position*))
            (when (scene-event-form-p form)
              (let ((event (parse-scene-event form members)))
                (when (assoc (car event) events :test #'string=)
                  (scene-fail 'scene-error form "scene event ~A is defined twice" (lisp-text (car event))))
                (push event events)))))
        (setf (gethash (name-key name) *casts*)
              (%make-cast :name name :documentation documentation :members members
                          :events (nreverse events) :source-file source-file
                          :set (parse-scene-set forms source-file)))))))

(defmacro defscene (&rest name-and-body)
  "Define (or, re-evaluated, redefine) the scene NAME of several characters:
  (defscene NAME [DOCSTRING] (SPEC [:as MEMBER] [:at (X Y Z)] [:initial ALIST]) ...
                             (event NAME MEMBER/EVENT ...) ... [(set \"LIBRARY-FILE\")])
Each member plays a defined spec; see DEFINE-CAST and doc/scenes.md.  A malformed
form is DEFINE-CAST's SCENE-ERROR, when it runs, not a macroexpansion error."
  `(define-cast ',(if (consp name-and-body) (car name-and-body) nil)
                ',(if (consp name-and-body) (cdr name-and-body) nil)
                :source-file ,(or (car *source-position*) *compile-file-truename* *load-truename*)))

(defun find-cast (name &optional (errorp t))
  "The scene named NAME (a symbol or string); with ERRORP, a SCENE-ERROR when there is none."
  (check-argument 'find-cast 'name name #'name-designator-p "a scene's name (a symbol or string)")
  (or (gethash (if (stringp name) (string-upcase name) (name-key name)) *casts*)
      (and errorp
           (scene-fail 'scene-error name "no scene named ~A is defined" (bounded-lisp-text name 80)))))

(defun list-casts ()
  "The names of every defined scene."
  (sort (loop for cast being the hash-values of *casts* collect (cast-name cast))
        #'string< :key #'symbol-name))

(defun remove-cast (name)
  "Forget the scene NAME; true when there was one."
  (check-argument 'remove-cast 'name name #'name-designator-p "a scene's name (a symbol or string)")
  (remhash (if (stringp name) (string-upcase name) (name-key name)) *casts*))

(defun replicate-cast (spec count &key name)
  "A scene (not registered) of COUNT members playing SPEC (a spec or its name),
called SPEC1, SPEC2 ... and placed in a row: what --cast SPEC:COUNT makes."
  (check-argument 'replicate-cast 'spec spec #'spec-designator-p *spec-designator*)
  (check-argument 'replicate-cast 'count count (lambda (x) (typep x '(integer 1 10000)))
                  "an integer from 1 to 10000")
  (let* ((spec (if (spec-p spec) spec (find-spec spec)))
         (package (or (symbol-package (spec-name spec)) (find-package '#:player-user))))
    (%make-cast :name (or name (spec-name spec))
                :members (place-members
                          (loop for k from 1 to count
                                for member = (intern (format nil "~A~D" (symbol-name (spec-name spec)) k) package)
                                collect (%make-cast-member :name member :spec (spec-name spec)
                                                           :form (list (spec-name spec) :as member)))))))

(defun cast-member-named (cast name)
  "CAST's member called NAME (compared by name), or NIL."
  (find (string name) (cast-members cast) :key (lambda (m) (symbol-name (cast-member-name m)))
                                          :test #'string-equal))
