;;;; scene-items.lisp -- the script items that act on scene objects:
;;;; (:animate (OBJECT PROPERTY) CONTROL) binds a control to a property,
;;;; (:set (OBJECT PROPERTY) VALUE) sets one once, (:attach OBJECT :to PARENT)
;;;; reparents (see the language reference at the top of scripts.lisp).

(in-package #:player.performance)

(defstruct (animate-item (:include script-item))
  "A CONTROL bound to OBJECT's PROPERTY; control time 0 is the item's start."
  (object nil :type symbol :read-only t)
  (property nil :type symbol :read-only t)
  (control nil :read-only t))

(defstruct (set-item (:include script-item))
  "OBJECT's PROPERTY set to VALUE (a double-float, VEC3, QUAT, T or NIL)."
  (object nil :type symbol :read-only t)
  (property nil :type symbol :read-only t)
  (value nil :read-only t))

(defstruct (attach-item (:include script-item))
  "OBJECT reparented to PARENT (NIL, an object's name or (OBJECT JOINT-OR-ROLE)),
keeping its world placement when KEEP-WORLD."
  (object nil :type symbol :read-only t)
  (parent nil :read-only t)
  (keep-world t :type boolean :read-only t))

(defun parse-object-property (item target)
  "The OBJECT and PROPERTY of TARGET, (OBJECT PROPERTY), as two values."
  (unless (and (alexandria:proper-list-p target) (= (length target) 2)
               (or (eq (first target) :self) (usable-name-p (first target)))
               (usable-name-p (second target)))
    (script-fail item "a property is written (OBJECT PROPERTY), OBJECT a name or :self, not ~A"
                 (lisp-text target)))
  (values (first target) (second target)))

(defun parse-animate-item (item at arguments)
  "(:at T :animate (OBJECT PROPERTY) CONTROL [:for D])."
  (multiple-value-bind (parts options until) (item-parts item arguments 2 '(:for))
    (declare (ignore options))
    (multiple-value-bind (object property) (parse-object-property item (first parts))
      (let ((control (handler-case (parse-control (second parts))
                       (anim-error (error) (script-fail item "bad control: ~A" error)))))
        (check-property-kind item property (builtin-property-type property) (control-kind control)
                             :animated t)
        (make-animate-item :at at :until until :form item
                           :object object :property property :control control)))))

(defun parse-set-item (item at arguments)
  "(:at T :set (OBJECT PROPERTY) VALUE)."
  (destructuring-bind (target value) (item-parts item arguments 2 '())
    (multiple-value-bind (object property) (parse-object-property item target)
      (let ((value (if (member value '(t nil))
                       value
                       (handler-case (parse-value value)
                         (anim-error (error) (script-fail item "bad value: ~A" error))))))
        (check-property-kind item property (builtin-property-type property) (set-value-kind value)
                             :value value)
        (make-set-item :at at :form item :object object :property property :value value)))))

(defun parse-attach-item (item at arguments)
  "(:at T :attach OBJECT :to PARENT [:keep-world BOOLEAN])."
  (multiple-value-bind (parts options) (item-parts item arguments 1 '(:to :keep-world))
    (let ((object (first parts))
          (keep-world (getf options :keep-world t)))
      (unless (or (eq object :self) (usable-name-p object))
        (script-fail item ":attach takes an object's name or :self, not ~A" (lisp-text object)))
      (unless (member :to options)
        (script-fail item ":attach needs :to PARENT (NIL for the scene root)"))
      (unless (member keep-world '(t nil))
        (script-fail item ":keep-world must be T or NIL, not ~A" (lisp-text keep-world)))
      (make-attach-item :at at :form item :object object :keep-world keep-world
                        :parent (parse-object-parent item (getf options :to))))))

(defun parse-object-parent (form parent)
  "PARENT if it is NIL, an object's name, or (OBJECT JOINT-OR-ROLE) with a joint's
name or a role of *SKELETON-ROLES*; else a SCRIPT-ERROR about FORM."
  (cond ((or (null parent) (usable-name-p parent)) parent)
        ((not (and (alexandria:proper-list-p parent) (= (length parent) 2)
                   (or (eq (first parent) :self) (usable-name-p (first parent)))
                   (second parent) (symbolp (second parent))))
         (script-fail form "a parent is an object's name, (OBJECT JOINT-OR-ROLE) or NIL, not ~A"
                      (lisp-text parent)))
        ((and (keywordp (second parent)) (not (assoc (second parent) *skeleton-roles*)))
         (script-fail form "unknown role ~A (roles: ~{~A~^ ~})" (lisp-text (second parent))
                      (mapcar (lambda (entry) (lisp-text (car entry))) *skeleton-roles*)))
        (t parent)))

;;; ---------------------------------------------------------------------------
;;; Property types

(defun builtin-property-type (property)
  "The type of the built-in PROPERTY, or NIL for any other."
  (second (assoc property *builtin-properties* :test #'name=)))

(defun set-value-kind (value)
  "The kind of a :set VALUE: :boolean for T and NIL, else its control value kind."
  (if (member value '(t nil)) :boolean (value-kind-of value)))

(defun check-property-kind (form property type kind &key value animated)
  "Signal a SCRIPT-ERROR about the item FORM when values of KIND (:number, :vec3,
:quat or :boolean), set (VALUE, for a range check) or ANIMATED by a control,
cannot go into PROPERTY of TYPE (NIL when unknown: anything goes)."
  (let ((item form)
        (wanted (ecase type
                  ((nil) kind) (:number :number) ((:vector :colour) :vec3)
                  (:rotation :quat) (:boolean :boolean))))
    (cond ((and (eq type :boolean) animated)
           (script-fail item "~A is a boolean property: set it with :set, it cannot be animated"
                        (lisp-text property)))
          ((not (eq kind wanted))
           (script-fail item "~A is a ~(~A~) property, and this gives it a ~(~A~)"
                        (lisp-text property) type kind))
          ((and (eq type :colour) (vec3-p value)
                (notevery (lambda (x) (<= 0 x 1)) (list (vec3-x value) (vec3-y value) (vec3-z value))))
           (script-fail item "~A is a colour: each of red, green and blue must lie in [0, 1]"
                        (lisp-text property))))))
