;;;; control-forms.lisp -- sums and products of controls, and controls written as s-expressions.

(in-package #:player.body)

;;;# Sums and products

(defstruct (combined-control (:include control)
                             (:constructor nil)
                             (:copier nil))
  "A control computed from the values of its CONTROLS at the same time."
  (controls #() :type simple-vector :read-only t))

(defstruct (sum-control (:include combined-control)
                        (:constructor %make-sum-control (kind controls))
                        (:copier nil))
  "The sum of its controls: numbers add, vectors add.")

(defstruct (product-control (:include combined-control)
                            (:constructor %make-product-control (kind controls))
                            (:copier nil))
  "The product of its controls: numbers multiply, rotations compose, numbers scale a vector.")

(defun check-controls (controls what)
  "Signal a ANIM-CONTROL-ERROR unless CONTROLS is a nonempty list of controls; WHAT names the combination."
  (when (null controls)
    (error 'anim-control-error :message (format nil "a ~A needs at least one control" what)))
  (dolist (control controls)
    (unless (control-p control)
      (control-fail control "a ~A combines controls, and this is not one" what))))

(defun make-sum-control (&rest controls)
  "A control whose value is the sum of the values of CONTROLS, all :number or
all :vec3. Signals a ANIM-CONTROL-ERROR when CONTROLS is empty, holds a non-control,
mixes kinds or holds rotations (rotations compose: use MAKE-PRODUCT-CONTROL)."
  (check-controls controls "sum")
  (let ((kind (control-kind (first controls))))
    (when (eq kind :quat)
      (control-fail (first controls) "rotations do not add; compose them with a product"))
    (dolist (control (rest controls))
      (unless (eq (control-kind control) kind)
        (control-fail control "cannot add a ~(~A~) control to a ~(~A~) control"
                      (control-kind control) kind)))
    (%make-sum-control kind (coerce controls 'simple-vector))))

(defun make-product-control (&rest controls)
  "A control whose value is the product of the values of CONTROLS, in order:
all :number multiply; all :quat compose (the product of A and B rotates by B,
then by A, so B acts in A's frame); one :vec3 among :numbers is scaled by them.
Signals a ANIM-CONTROL-ERROR when CONTROLS is empty, holds a non-control, or mixes
kinds otherwise."
  (check-controls controls "product")
  (let* ((kinds (mapcar #'control-kind controls))
         (kind (cond ((every (lambda (k) (eq k :number)) kinds) :number)
                     ((every (lambda (k) (eq k :quat)) kinds) :quat)
                     ((and (= 1 (count :vec3 kinds)) (null (remove :vec3 (remove :number kinds))))
                      :vec3)
                     (t (control-fail kinds "a product takes numbers, rotations, or one vector scaled by numbers; cannot multiply controls of these kinds")))))
    (%make-product-control kind (coerce controls 'simple-vector))))

(defmethod control-value ((control sum-control) time)
  (let ((controls (combined-control-controls control)))
    (if (eq (control-kind control) :number)
        (loop for c across controls sum (the double-float (control-value c time)) of-type double-float)
        (let ((sum (control-value (svref controls 0) time)))
          (loop for i from 1 below (length controls)
                do (nv+ sum (control-value (svref controls i) time)))
          sum))))

(defmethod control-value ((control product-control) time)
  (let ((controls (combined-control-controls control)))
    (ecase (control-kind control)
      (:number (let ((product 1d0))
                 (declare (type double-float product))
                 (loop for c across controls do (setf product (* product (control-value c time))))
                 product))
      (:quat (let ((product (control-value (svref controls 0) time)))
               (loop for i from 1 below (length controls)
                     do (nq* product (control-value (svref controls i) time)))
               (nqnormalize product)))
      (:vec3 (let ((scale 1d0) (vector nil))
               (declare (type double-float scale))
               (loop for c across controls
                     for value = (control-value c time)
                     do (if (vec3-p value) (setf vector value) (setf scale (* scale value))))
               (nv* vector scale))))))

;;;# Controls as s-expressions

(defun parse-value (form)
  "The control value FORM denotes: a real; a VEC3 or QUAT object; (:vec3 X Y Z);
(:quat W X Y Z) (normalized); (:axis-angle (X Y Z) ANGLE); (:euler X Y Z)
(radians, see QUAT-FROM-EULER); (:degrees X Y Z) (the same in degrees). Signals a ANIM-CONTROL-ERROR naming FORM otherwise."
  (flet ((reals (list count)
           (unless (and (listp list) (null (cdr (last list))) (= (length list) count)
                        (every #'finite-number-p list))
             (control-fail form "~(~A~) takes ~D finite real numbers" (first form) count))
           list))
    (cond ((or (realp form) (vec3-p form) (quat-p form)) (canonical-value form))
          ((not (consp form))
           (control-fail form "a control value must be a number, (:vec3 x y z), (:quat w x y z), (:axis-angle (x y z) angle), (:euler x y z) or (:degrees x y z)"))
          (t (case (first form)
               (:vec3 (apply #'make-vec3 (reals (rest form) 3)))
               (:quat (canonical-value (apply #'make-quat (reals (rest form) 4))))
               (:euler (apply #'quat-from-euler (reals (rest form) 3)))
               ;; The same in degrees, as authors think of turns.
               (:degrees (apply #'quat-from-euler
                                (mapcar (lambda (d) (* d (/ pi 180))) (reals (rest form) 3))))
               (:axis-angle
                (unless (and (alexandria:proper-list-p form) (= (length form) 3)
                             (finite-number-p (third form)))
                  (control-fail form "(:axis-angle (x y z) angle) takes an axis and a finite real angle"))
                (quat-from-axis-angle (apply #'make-vec3 (reals (second form) 3)) (third form)))
               (t (control-fail form "unknown value form (expected :vec3, :quat, :axis-angle, :euler or :degrees)")))))))

(defun parse-plist (form plist allowed)
  "Check that PLIST (from FORM) is a property list of keywords among ALLOWED; return it."
  (unless (and (listp plist) (null (cdr (last plist))) (evenp (length plist)))
    (control-fail form "options must come as :keyword value pairs"))
  (loop for (key) on plist by #'cddr
        unless (member key allowed)
          do (control-fail form "unknown option ~A (expected ~{~(~S~)~^, ~})" (anim-text key) allowed))
  plist)

(defun parse-control (form)
  "The control the s-expression FORM describes:
  VALUE                          a constant (see PARSE-VALUE)
  (:constant VALUE)
  (:keys ((TIME . VALUE)...) [:interpolation MODE] [:loop BOOLEAN])
  (:noise [:seed N] [:amplitude A] [:frequency F] [:kind KIND])
  (:sum CONTROL...)  (:product CONTROL...)
A CONTROL object stands for itself. Signals a ANIM-CONTROL-ERROR naming the
offending form; a circular FORM, or one nested too deeply, is also an
ARGUMENT-ERROR."
  (check-argument 'parse-control 'form form #'bounded-form-p
                  (format nil "a control form, not circular nor nested more than ~D deep" *max-form-depth*)
                  'control-argument-error)
  (%parse-control form))

(defun %parse-control (form)
  "PARSE-CONTROL of FORM, known to be a bounded tree."
  (cond ((control-p form) form)
        ((not (and (consp form) (member (first form) '(:constant :keys :noise :sum :product))))
         (make-constant-control (parse-value form)))
        (t (destructuring-bind (head &rest arguments) form
             (unless (listp (cdr (last arguments)))
               (control-fail form "a control form must be a proper list"))
             (ecase head
               (:constant
                (unless (= (length arguments) 1)
                  (control-fail form "(:constant VALUE) takes exactly one value"))
                (make-constant-control (parse-value (first arguments))))
               (:keys
                (when (null arguments)
                  (control-fail form "(:keys KEYS ...) needs a list of keys"))
                (let ((keys (first arguments))
                      (options (parse-plist form (rest arguments) '(:interpolation :loop))))
                  (unless (and (listp keys) (null (cdr (last keys))))
                    (control-fail keys "keys must be a list of (time . value) pairs"))
                  (apply #'make-keys-control
                         (mapcar (lambda (key)
                                   (check-key key)
                                   (cons (car key) (parse-value (cdr key))))
                                 keys)
                         options)))
               (:noise
                (apply #'make-noise-control
                       (parse-plist form arguments '(:seed :amplitude :frequency :kind))))
               ((:sum :product)
                (when (null arguments)
                  (control-fail form "a ~(~A~) needs at least one control" head))
                (apply (if (eq head :sum) #'make-sum-control #'make-product-control)
                       (mapcar #'%parse-control arguments))))))))
