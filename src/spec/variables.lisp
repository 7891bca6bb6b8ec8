;;;; variables.lisp -- the (state-variable ...) and (time-variable ...) forms:
;;;; types, domains and initial values, checked as PARSE's first pass reads
;;;; them.

(in-package #:player.spec)

(defun parse-variable-type (word form)
  "The type keyword WORD names."
  (or (loop for type in '(:boolean :integer :float :string)
            when (word-p (unquote word) (symbol-name type)) return type)
      (spec-fail 'type-error-in-spec form "unknown type ~A (expected boolean, integer, float or string)"
                 (lisp-text word))))

(defun parse-state-variable (form)
  "Parse (state-variable NAME TYPE INITIAL [VALUES])."
  (unless (<= 4 (length form) 5)
    (spec-fail 'spec-syntax-error form "expected (state-variable NAME TYPE INITIAL [VALUES])"))
  (destructuring-bind (name type initial &optional (values nil values-p)) (rest form)
    (let* ((name (require-name name form "a variable name"))
           (type (progn (when (boolean-word name)
                          (spec-fail 'spec-syntax-error form "~A is a boolean word, not a variable name"
                                     (lisp-text name)))
                        (parse-variable-type type form)))
           (initial (unquote initial))
           (values (unquote values))
           (var (make-variable-def :name name :type type :form form)))
      (when (and values-p (not (and (proper-list-p values) values)))
        (spec-fail 'spec-syntax-error form "VALUES must be a non-empty list"))
      (ecase type
        (:boolean
         (when values-p
           (spec-fail 'spec-syntax-error form "a boolean variable takes no VALUES list"))
         (multiple-value-bind (truth ok) (boolean-word initial)
           (unless ok
             (spec-fail 'type-error-in-spec form "initial value ~A of boolean ~A is not true, false, t or nil"
                        (lisp-text initial) (lisp-text name)))
           (setf (var-kind var) :boolean (var-domain var) (vector nil t)
                 (var-initial var) (if truth 1 0))))
        ((:integer :string)
         (if values-p
             (setf (var-kind var) :enumerated
                   (var-domain var) (parse-domain values type form)
                   (var-initial var) (initial-index var initial form))
             (if (eq type :string)
                 (spec-fail 'spec-syntax-error form "a string variable needs a VALUES list")
                 (setf (var-kind var) :number
                       (var-initial var) (check-number initial 'integer form name)))))
        (:float
         (when values-p
           (spec-fail 'spec-syntax-error form "a float variable cannot be enumerated; use integer or string values"))
         (setf (var-kind var) :number
               (var-initial var) (to-double (check-number initial 'real form name)))))
      var)))

(defun check-number (value type form name)
  "VALUE if it is of TYPE and in range (an integer of 64 bits, a finite real),
else a type error naming variable NAME."
  (unless (and (typep value type) (finite-real-p value) (or (not (integerp value)) (int64-p value)))
    (spec-fail 'type-error-in-spec form "initial value ~A of ~A is not ~:[a finite number~;an integer from -2^63 to 2^63-1~]"
               (bounded-lisp-text value 40) (lisp-text name) (eq type 'integer)))
  value)

(defun parse-domain (values type form)
  "The domain vector of an enumerated variable, checked for type and duplicates."
  (dolist (value values)
    (unless (if (eq type :integer)
                (int64-p value)
                (or (stringp value) (and (symbolp value) value (not (keywordp value)))))
      (spec-fail 'type-error-in-spec form "value ~A is not ~:[a name~;an integer from -2^63 to 2^63-1~]"
                 (bounded-lisp-text value 40) (eq type :integer)))
    ;; A value is a name too: a line break in it would forge trace lines.
    (when (and (stringp value) (find-if #'control-character-p value))
      (spec-fail 'type-error-in-spec form "value ~A holds a control character, which could forge output"
                 (bounded-lisp-text value 40))))
  (let ((names (mapcar (lambda (v) (string-upcase (value-name v))) values)))
    (when (/= (length names) (length (remove-duplicates names :test #'string=)))
      (spec-fail 'duplicate-definition form "VALUES lists a value twice")))
  (coerce values 'simple-vector))

(defun initial-index (var initial form)
  "The domain index of enumerated VAR's INITIAL value."
  (when (and (eq (var-type var) :integer) (not (integerp initial)))
    (spec-fail 'type-error-in-spec form "initial value ~A of ~A is not an integer"
               (lisp-text initial) (lisp-text (var-name var))))
  (value-index var initial form))

(defun parse-time-variable (form)
  "Parse (time-variable NAME (EVENT...))."
  (unless (and (= (length form) 3) (proper-list-p (unquote (third form))))
    (spec-fail 'spec-syntax-error form "expected (time-variable NAME (EVENT...))"))
  (make-variable-def :name (require-name (second form) form "a variable name")
                     :type :time :kind :time :initial nil
                     :events (mapcar (lambda (e) (require-name e form "an event name"))
                                     (unquote (third form)))
                     :form form))
