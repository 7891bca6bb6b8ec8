;;;; script-library.lisp -- reading a script library file (DEFSCRIPT, DEFDIRECTOR,
;;;; DEFOBJECT and POSES forms; see the top of scripts.lisp) into a
;;;; SCRIPT-LIBRARY, and the checks that need the whole library: nested scripts
;;;; exist and form no cycle, durations, declared properties, director schedules.

(in-package #:player.performance)

;;; ---------------------------------------------------------------------------
;;; Data

(defstruct (script-library (:constructor %make-script-library (source)))
  "The scripts and directors of a library file by name (case-insensitive), its
declared scene objects in file order, the pose library's pathname (or NIL),
and the file it came from (or NIL)."
  (scripts (make-hash-table :test #'equalp) :type hash-table :read-only t)
  (directors (make-hash-table :test #'equalp) :type hash-table :read-only t)
  (objects '() :type list)
  (poses nil)
  (source nil :read-only t)
  (definitions '() :type list)          ; scripts and directors, in file order
  (pose-whens '() :type list)           ; (:pose-when ...) entries, in file order (pose-when.lisp)
  (skeleton nil)                        ; the skeleton of its (model "FILE" ...) form, or NIL (model-form.lisp)
  (idle t)                              ; NIL after (idle nil): characters get no idle life (idle-form.lisp)
  (places nil))                         ; the *SUB-FORM-PLACES* of its forms, or NIL

(defmethod print-object ((library script-library) stream)
  (print-unreadable-object (library stream :type t)
    (format stream "~@[~A, ~]~D scripts, ~D directors"
            (and (script-library-source library) (file-namestring (script-library-source library)))
            (hash-table-count (script-library-scripts library))
            (hash-table-count (script-library-directors library)))))

(defstruct (scene-object-spec (:constructor make-scene-object-spec
                                  (name kind parent position rotation properties
                                   documentation form &optional prop-model)))
  "A scene object a library declares: KIND (:prop :camera :light :group), PARENT
(NIL, an object's name or (OBJECT JOINT-OR-ROLE)), POSITION (VEC3, metres),
ROTATION (unit QUAT), PROPERTIES ((NAME TYPE VALUE) ...) with values parsed;
for a prop drawn as a model, PROP-MODEL (from MAKE-PROP-MODEL), else NIL."
  (name nil :type symbol :read-only t)
  (kind :prop :type keyword :read-only t)
  (parent nil :read-only t)
  (position (vec3) :type vec3 :read-only t)
  (rotation (quat) :type quat :read-only t)
  (properties '() :type list :read-only t)
  (documentation nil :type (or null string) :read-only t)
  (form nil :read-only t)
  (prop-model nil :read-only t))

(defun find-script (library name &optional errorp)
  "LIBRARY's script called NAME (a symbol or string, compared case-insensitively);
NIL when there is none, unless ERRORP, when a SCRIPT-ERROR lists the scripts."
  (check-argument 'find-script 'library library #'script-library-p "a script library (from load-script-library)")
  (check-argument 'find-script 'name name #'string-designator-p "a script's name (a symbol or string)")
  (or (gethash (string name) (script-library-scripts library))
      (and errorp (unknown-definition library name "script" #'script-library-scripts))))

(defun find-director (library name &optional errorp)
  "LIBRARY's director called NAME (a symbol or string, compared case-insensitively);
NIL when there is none, unless ERRORP, when a SCRIPT-ERROR lists the directors."
  (check-argument 'find-director 'library library #'script-library-p "a script library (from load-script-library)")
  (check-argument 'find-director 'name name #'string-designator-p "a director's name (a symbol or string)")
  (or (gethash (string name) (script-library-directors library))
      (and errorp (unknown-definition library name "director" #'script-library-directors))))

(defun unknown-definition (library name what table)
  "Signal a SCRIPT-ERROR: LIBRARY has no WHAT called NAME; list those in TABLE."
  (let ((*script-context* nil))
    (script-fail name "unknown ~A ~A (known: ~:[none~;~:*~{~A~^ ~}~])" what (lisp-text name)
                 (sort (mapcar #'string-downcase (hash-table-keys (funcall table library)))
                       #'string<))))

(defun missing-scripts (library names)
  "The NAMES (symbols or strings) that are neither scripts nor directors of
LIBRARY, each once, in order."
  (remove-duplicates (remove-if (lambda (name) (or (find-script library name)
                                                   (find-director library name)))
                                names)
                     :test #'name= :from-end t))

;;; ---------------------------------------------------------------------------
;;; Reading

(defun load-script-library (path)
  "Read the script library file PATH (as data, see READ-DATA-FILE) and return
a SCRIPT-LIBRARY.  Signals a SCRIPT-ERROR, naming the file and line, when the
file is missing, not a regular file or unreadable, or any form is malformed or
inconsistent; an ARGUMENT-ERROR when PATH is not a file's path."
  (check-argument 'load-script-library 'path path #'pathname-designator-p *path-phrase*)
  (multiple-value-bind (entries text) (read-data-file path :what "script library"
                                      :fail (lambda (position message kind)
                                              (with-spec-context (:source-position (and position (cons (probe-file path) position)))
                                                (case kind
                                                  (:missing (script-fail nil "there is no script library file ~A"
                                                                         (namestring path)))
                                                  (:read (script-fail nil "unreadable script library ~A: ~A"
                                                                      (namestring path) message))
                                                  (t (script-fail nil "~A" message))))))
    (build-script-library (mapcar (lambda (entry) (cons (first entry) (second entry))) entries)
                          (probe-file path)
                          ;; Errors about an item, step or clause name its own line.
                          (sub-form-places entries text (probe-file path)))))

(defun parse-script-library-forms (forms &key source)
  "A SCRIPT-LIBRARY from FORMS as if read from the file SOURCE (a pathname, for
resolving the pose file, or NIL).  Signals SCRIPT-ERROR as LOAD-SCRIPT-LIBRARY."
  (build-script-library (mapcar (lambda (form) (cons form nil)) forms) source))

(defvar *library-object-names* nil
  "While a library is built: its objects by name (an EQUALP table), so that
checking each new DEFOBJECT for a twin costs no walk of the ones before.")

(defun build-script-library (entries source &optional places)
  "The SCRIPT-LIBRARY of ENTRIES, each (FORM . POSITION-OR-NIL) from the file
SOURCE; PLACES, when given, is the *SUB-FORM-PLACES* of their lists."
  (let ((library (%make-script-library source))
        (*library-object-names* (make-hash-table :test 'equalp))
        (*library-directory* (and source (directory-pathname (make-pathname :name nil :type nil :version nil
                                                                            :defaults source)))))
    (with-spec-context (:spec-name nil :sub-form-places places)
      ;; Kept, so CHECK can name the line of a key that fails on a body.
      (setf (script-library-places library) places)
      (loop for (form . position) in entries
            do (with-spec-context (:source-position (and source position (cons source position)))
                 (add-library-form library form)))
      (setf (script-library-definitions library) (reverse (script-library-definitions library))
            (script-library-objects library) (reverse (script-library-objects library))
            (script-library-pose-whens library) (reverse (script-library-pose-whens library)))
      (check-script-library library)
      library)))

(defun add-library-form (library form)
  "Parse the top-level FORM into LIBRARY."
  (unless (bounded-form-p form)
    (script-fail nil "a script library form contains itself or is nested more than ~D levels deep"
                 *max-form-depth*))
  (let ((bad (out-of-range-number form)))
    (when bad
      (script-fail form "the number ~A is out of range: library numbers are 0 or between ~A and ~A in magnitude"
                   (argument-value-text bad) (first *library-number-range*) (second *library-number-range*))))
  (let ((head (and (consp form) (symbolp (first form)) (string-downcase (first form)))))
    (cond ((equal head "defscript")
           (add-definition library (parse-defscript form *source-position*)
                           #'script-name #'script-library-scripts "script" form))
          ((equal head "defdirector")
           (add-definition library (parse-defdirector form *source-position*)
                           #'director-name #'script-library-directors "director" form))
          ((equal head "defobject")
           (let ((object (parse-defobject form)))
             (when (if *library-object-names*
                       (gethash (string (scene-object-spec-name object)) *library-object-names*)
                       (find (scene-object-spec-name object) (script-library-objects library)
                             :key #'scene-object-spec-name :test #'name=))
               (script-fail form "object ~A is declared twice" (lisp-text (second form))))
             (when *library-object-names*
               (setf (gethash (string (scene-object-spec-name object)) *library-object-names*) object))
             (push object (script-library-objects library))))
          ((equal head "poses") (set-pose-library library form))
          ((equal head "pose-when") (push (parse-pose-when form) (script-library-pose-whens library)))
          ((equal head "model") (set-library-model library form))
          ((equal head "idle") (set-library-idle library form))
          (t (script-fail form "a script library may contain defscript, defdirector, defobject, ~
                                model, poses, idle and :pose-when forms, not ~:[this~;~:*a ~A form~]"
                          head)))))

(defun add-definition (library definition name-of table-of what form)
  "Add the script or director DEFINITION (WHAT) to LIBRARY, refusing a second
definition of its name as either."
  (let* ((name (funcall name-of definition))
         (key (string name)))
    (cond ((gethash key (funcall table-of library))
           (script-fail form "~A ~A is defined twice" what (lisp-text name)))
          ((or (find-script library key) (find-director library key))
           (script-fail form "~A is defined both as a script and as a director" (lisp-text name))))
    (setf (gethash key (funcall table-of library)) definition)
    (push definition (script-library-definitions library))))

(defun set-pose-library (library form)
  "Record the pose file of FORM, (poses \"FILE\"), resolved against LIBRARY's file."
  (unless (and (alexandria:proper-list-p form) (= (length form) 2) (stringp (second form)))
    (script-fail form "the pose library is named (poses \"FILE\")"))
  (when (script-library-poses library)
    (script-fail form "the pose library is named twice"))
  (let ((path (merge-pathnames (second form) (or (script-library-source library)
                                                 *default-pathname-defaults*))))
    (setf (script-library-poses library)
          (or (probe-file path) (script-fail form "there is no pose library file ~A" (namestring path))))))

;;; ---------------------------------------------------------------------------
;;; DEFOBJECT

(defparameter *declarable-object-kinds* '(:prop :camera :light :group)
  "The kinds of object a library may declare (bodies come from characters).")

(defparameter *defobject-options*
  '(:kind :parent :position :rotation :properties :documentation :model :texture :height :scale :up :dynamic)
  "The options of a (defobject NAME ...) form; :model to :up make a prop a model's
meshes, :dynamic T a prop the physics moves (src/performance/dynamic-props.lisp).")

(defun parse-defobject (form)
  "The SCENE-OBJECT-SPEC FORM, (defobject NAME &key ...), declares."
  (unless (and (alexandria:proper-list-p form) (usable-name-p (second form)))
    (script-fail form "an object is written (defobject NAME &key kind parent position rotation properties documentation model texture height scale up dynamic)"))
  (let ((*script-context* (format nil "object ~A" (lisp-text (second form))))
        (options (cddr form)))
    (check-options form options *defobject-options* "defobject")
    (destructuring-bind (&key (kind :prop) parent (position '(0 0 0)) rotation properties
                           documentation model texture height scale (up :y) dynamic)
        options
      (unless (member kind *declarable-object-kinds*)
        (script-fail form ":kind must be one of ~{~A~^ ~}, not ~A"
                     (mapcar #'lisp-text *declarable-object-kinds*) (lisp-text kind)))
      (unless (typep documentation '(or null string))
        (script-fail form ":documentation must be a string"))
      (when (and (not model) (or texture height scale (getf options :up)))
        (script-fail form ":texture, :height, :scale and :up belong to a prop drawn as a model: give :model \"FILE\""))
      (when (and model (not (eq kind :prop)))
        (script-fail form ":model draws a prop; a ~A has no meshes" (lisp-text kind)))
      (make-scene-object-spec (second form) kind (parse-object-parent form parent)
                              (parse-property-value :vector position form ":position")
                              (if rotation (parse-property-value :rotation rotation form ":rotation") (quat))
                              (dynamic-prop-properties (parse-declared-properties properties form)
                                                       dynamic kind form)
                              documentation form
                              (and model (parse-prop-model form model texture height scale up))))))

(defun parse-declared-properties (properties form)
  "PROPERTIES, ((NAME TYPE VALUE) ...), with each VALUE parsed by its TYPE."
  (unless (alexandria:proper-list-p properties)
    (script-fail form ":properties must be a list of (NAME TYPE VALUE)"))
  (loop for property in properties
        for (name type value) = (if (and (alexandria:proper-list-p property) (= (length property) 3))
                                    property
                                    (script-fail form "a property is written (NAME TYPE VALUE), not ~A"
                                                 (lisp-text property)))
        do (cond ((not (usable-name-p name))
                  (script-fail form "a property's name must be a symbol, not ~A" (lisp-text name)))
                 ((builtin-property-type name)
                  (script-fail form "every object has the property ~A already" (lisp-text name)))
                 ((find name parsed :key #'first :test #'name=)
                  (script-fail form "property ~A is declared twice" (lisp-text name)))
                 ((not (property-type-p type))
                  (script-fail form "property ~A: unknown type ~A (types: ~{~A~^ ~})" (lisp-text name)
                               (lisp-text type) (mapcar (lambda (e) (lisp-text (car e))) *property-types*))))
        collect (list name type (parse-property-value type value form (lisp-text name))) into parsed
        finally (return parsed)))

(defun parse-property-value (type value form what)
  "VALUE, written for a property of TYPE, as a stored value; WHAT names it in errors."
  (flet ((reals (count &optional (list value))
           (unless (and (alexandria:proper-list-p list) (= (length list) count)
                        (every #'finite-number-p list))
             (script-fail form "~A must be ~D numbers~:[~; after :euler~], not ~A"
                          what count (not (eq list value)) (argument-value-text value)))
           list))
    (ecase type
      (:number (if (finite-number-p value) (float value 1d0)
                   (script-fail form "~A must be a number, not ~A" what (argument-value-text value))))
      (:boolean (if (member value '(t nil)) value
                    (script-fail form "~A must be T or NIL, not ~A" what (lisp-text value))))
      (:vector (apply #'make-vec3 (reals 3)))
      (:colour (unless (every (lambda (x) (<= 0 x 1)) (reals 3))
                 (script-fail form "~A is a colour: each of red, green and blue must lie in [0, 1]" what))
       (apply #'make-vec3 value))
      (:rotation
       (if (and (consp value) (eq (first value) :euler))
           (apply #'quat-from-euler (mapcar (lambda (degrees) (* degrees (/ pi 180)))
                                            (reals 3 (rest value))))
           (let ((q (apply #'make-quat (reals 4))))
             (if (zerop (qnorm q))
                 (script-fail form "~A must be a nonzero quaternion (W X Y Z) or (:euler X Y Z)" what)
                 (qnormalize q))))))))

;;; ---------------------------------------------------------------------------
;;; Checks that need the whole library

(defmacro with-script-context ((script) &body body)
  "Run BODY with errors placed at SCRIPT's definition and prefixed by its name."
  (once-only (script)
    `(let ((*script-context* (format nil "script ~A" (lisp-text (script-name ,script)))))
       (with-spec-context (:source-position (script-source ,script))
         ,@body))))

(defun check-script-library (library)
  "Resolve and check what single forms cannot: nested scripts, durations,
declared objects and properties, director schedules."
  (let ((scripts (remove-if-not #'script-p (script-library-definitions library))))
    (dolist (script scripts)
      (with-script-context (script)
        (dolist (item (script-items script))
          (when (play-item-p item)
            (unless (find-script library (play-item-script item))
              (script-fail (script-item-form item) "~A is ~:[not a script of the library~;a director; :play takes scripts~]"
                           (lisp-text (play-item-script item))
                           (find-director library (play-item-script item))))))))
    (let ((checked (make-hash-table :test #'eq)))
      (dolist (script scripts)
        (check-play-cycles library script '() checked)))
    (check-play-expansion library scripts)
    (dolist (script scripts)
      (with-script-context (script)
        (check-clip-items library script)))
    (dolist (script scripts)
      (resolve-script-duration library script))
    (check-object-parents library)
    (dolist (script scripts)
      (check-declared-properties library script))
    (dolist (director (remove-if-not #'director-p (script-library-definitions library)))
      (director-schedule director library 0)
      (let ((trigger (director-trigger director)))
        (when (and (eq (first trigger) :after) (not (find-director library (second trigger))))
          (script-fail (director-form director) "director ~A: (:after ~A): the library has no director ~A"
                       (lisp-text (director-name director)) (lisp-text (second trigger)) (lisp-text (second trigger))))))))

(defun check-play-cycles (library script path checked)
  "Signal a SCRIPT-ERROR when SCRIPT, reached by the :play chain PATH (innermost
first), plays itself directly or through other scripts.  CHECKED holds the
scripts known to start no cycle."
  (when (member script path)
    (let ((cycle (reverse (cons script (ldiff path (rest (member script path)))))))
      (with-script-context (script)
        (script-fail (script-form script) "nested scripts form a cycle: ~{~A~^ -> ~}"
                     (mapcar (lambda (s) (lisp-text (script-name s))) cycle)))))
  (unless (gethash script checked)
    (dolist (item (script-items script))
      (when (play-item-p item)
        (check-play-cycles library (find-script library (play-item-script item))
                           (cons script path) checked)))
    (setf (gethash script checked) t)))

(defun resolve-script-duration (library script)
  "SCRIPT's duration, inferred from its items (and nested scripts) when not given;
checks critical times and looping against it.  Nested cycles were ruled out."
  (or (script-duration script)
      (let ((duration (reduce #'max (script-items script)
                              :key (lambda (item) (item-natural-end library item))
                              :initial-value 0d0)))
        (with-script-context (script)
          (loop for (name . time) in (script-critical script)
                when (> time duration)
                  do (script-fail (script-form script) "critical time ~A (~A) lies after the script's duration ~A"
                                  (lisp-text name) (format-number time) (format-number duration)))
          (when (and (script-loop script) (< duration *shortest-loop*))
            (script-fail (script-form script) "a looping script must last some time (at least ~A s); give it a :duration"
                         (format-number *shortest-loop*))))
        (setf (script-duration script) duration))))

(defun item-natural-end (library item)
  "Where ITEM ends for the purpose of inferring its script's duration."
  (let ((at (script-item-at item)))
    (cond ((script-item-end item))
          ((sound-item-p item) (+ at (sound-duration (sound-item-sound item))))
          ((and (say-item-p item) (say-item-length item)) (+ at (say-item-length item)))
          ((and (motor-item-p item) (clip-item-length library item))
           (+ at (clip-item-length library item)))
          ((play-item-p item)
           (+ at (resolve-script-duration library (find-script library (play-item-script item)))))
          ((and (animate-item-p item) (keys-control-p (animate-item-control item))
                (not (keys-control-loop (animate-item-control item))))
           (let ((times (keys-control-times (animate-item-control item))))
             (+ at (max 0d0 (aref times (1- (length times)))))))
          (t at))))

(defun check-declared-properties (library script)
  "Check SCRIPT's :animate and :set items on objects LIBRARY declares against
their properties and types."
  (with-script-context (script)
    (dolist (item (script-items script))
      (let* ((target (typecase item
                       (animate-item (cons (animate-item-object item) (animate-item-property item)))
                       (set-item (cons (set-item-object item) (set-item-property item)))))
             (object (and target (find (car target) (script-library-objects library)
                                       :key #'scene-object-spec-name :test #'name=))))
        (when object
          (let ((type (or (builtin-property-type (cdr target))
                          (second (find (cdr target) (scene-object-spec-properties object)
                                        :key #'first :test #'name=))
                          (script-fail (script-item-form item) "object ~A has no property ~A (it has ~{~A~^ ~})"
                                       (lisp-text (car target)) (lisp-text (cdr target))
                                       (mapcar #'lisp-text
                                               (append (mapcar #'first *builtin-properties*)
                                                       (mapcar #'first (scene-object-spec-properties object))))))))
            (if (animate-item-p item)
                (check-property-kind (script-item-form item) (cdr target) type
                                     (control-kind (animate-item-control item)) :animated t)
                (check-property-kind (script-item-form item) (cdr target) type
                                     (set-value-kind (set-item-value item))
                                     :value (set-item-value item)))))))))
