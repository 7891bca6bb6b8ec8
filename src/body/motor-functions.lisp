;;;; motor-functions.lisp -- Pantomime's DriverManager: the motor functions a
;;;; script may call, each with documented parameters and defaults, checked
;;;; before anything moves.  A call is a frame, a keyword list:
;;;;   (:gaze :target (:object user) :speed 1.0)

(in-package #:player.body)

(define-condition motor-error (spec-error)
  ()
  (:report report-spec-error-safely)
  (:documentation "A motor-function frame is malformed: unknown function or
parameter, a missing parameter, a value of the wrong type.  FORM is the frame."))

(defun motor-fail (form control &rest arguments)
  "Signal a MOTOR-ERROR about FORM with a message from CONTROL and ARGUMENTS."
  (error 'motor-error :form form :message (apply #'format nil control arguments)))

;;;# Parameter types

(defparameter *motor-parameter-types*
  '((:real finite-number-p "a finite number")
    (:positive positive-real-p "a positive number")
    (:non-negative non-negative-real-p "a number >= 0")
    (:reflex-interval reflex-interval-p "a number of seconds of at least 0.05 (a reflex fires no faster)")
    (:brief brief-seconds-p "a positive number of seconds up to 10")
    (:angle finite-number-p "an angle in degrees")
    (:boolean boolean-value-p "T or NIL")
    (:symbol symbolp "a symbol")
    (:keyword keywordp "a keyword")
    (:list alexandria:proper-list-p "a list")
    (:string stringp "a string")
    (:target target-form-p "a target: (:point X Y Z), (:object NAME) or (:joint OBJECT JOINT) [:offset (X Y Z)]")
    (:vector vector-form-p "three numbers (X Y Z)")
    (:zone zone-form-p "a gesture-space zone: (:zone NAME), NAME one of :center-center :center :periphery-upper :periphery-lower :periphery-side :extreme-periphery-upper :extreme-periphery-lower :extreme-periphery-side"))
  "The parameter types a motor function may declare: (TYPE PREDICATE DESCRIPTION).
A type may also be (:member VALUE...) or (:or TYPE...).")

(defun positive-real-p (x) "Is X a finite real > 0?" (and (finite-number-p x) (plusp x)))
(defun non-negative-real-p (x) "Is X a finite real >= 0?" (and (finite-number-p x) (>= x 0)))
(defun reflex-interval-p (x)
  "Is X a mean interval a reflex may have: at least 0.05 s, so its firings stay few?"
  (and (finite-number-p x) (>= x 0.05)))
(defun brief-seconds-p (x)
  "Is X the length of a brief movement (a blink): > 0 and at most 10 s?"
  (and (finite-number-p x) (< 0 x) (<= x 10)))

(defun vector-form-p (x)
  "Is X a list of three finite reals?"
  (and (alexandria:proper-list-p x) (= (length x) 3) (every #'finite-number-p x)))

(defun target-form-p (x)
  "Is X a target form: (:point X Y Z), (:object NAME) or (:joint OBJECT JOINT),
optionally followed by :offset (X Y Z)?"
  (and (consp x) (alexandria:proper-list-p x)
       (multiple-value-bind (head-length ok)
           (case (first x)
             (:point (values 4 (and (>= (length x) 4) (every #'finite-number-p (subseq x 1 4)))))
             (:object (values 2 (and (>= (length x) 2) (symbolp (second x)))))
             (:joint (values 3 (and (>= (length x) 3) (symbolp (second x)) (symbolp (third x)))))
             (t (values 0 nil)))
         (and ok
              (let ((tail (nthcdr head-length x)))
                (or (null tail)
                    (and (= (length tail) 2) (eq (first tail) :offset)
                         (vector-form-p (second tail)))))))))

(defun motor-type-p (value type)
  "Does VALUE have the motor parameter TYPE?"
  (cond ((and (consp type) (eq (first type) :member)) (member value (rest type)))
        ((and (consp type) (eq (first type) :or))
         (some (lambda (type) (motor-type-p value type)) (rest type)))
        (t (funcall (second (or (assoc type *motor-parameter-types*)
                                (error "unknown motor parameter type ~S" type)))
                    value))))

(defun motor-type-description (type)
  "TYPE described for an error message."
  (cond ((and (consp type) (eq (first type) :member))
         (format nil "one of ~{~A~^, ~}" (mapcar #'lisp-text (rest type))))
        ((and (consp type) (eq (first type) :or))
         (format nil "~{~A~^, or ~}" (mapcar #'motor-type-description (rest type))))
        (t (third (assoc type *motor-parameter-types*)))))

;;;# The registry

(defstruct (motor-parameter (:constructor make-motor-parameter (key type default documentation)))
  "One documented parameter of a motor function; DEFAULT :REQUIRED means no default."
  (key nil :type keyword :read-only t)
  (type nil :read-only t)
  (default nil :read-only t)
  (documentation "" :type string :read-only t))

(defstruct (motor-function (:constructor make-motor-function (name driver-class documentation parameters)))
  "A motor function: the driver class that performs it and its parameters."
  (name nil :type keyword :read-only t)
  (driver-class nil :type symbol :read-only t)
  (documentation "" :type string :read-only t)
  (parameters '() :type list :read-only t))

(defvar *motor-functions* (make-hash-table :test #'eq)
  "Every motor function by name (a keyword).")

(defparameter *common-motor-parameters*
  (list (make-motor-parameter :blend '(:or :non-negative (:member nil)) nil
                              "seconds to crossfade when this call takes or gives up a channel; NIL for the body's default")
        (make-motor-parameter :weight :non-negative 1
                              "how much this call counts where it blends with calls of equal priority on a channel, or how much of its motion an additive call adds")
        (make-motor-parameter :usurp :boolean nil
                              "take channels held at an equal priority instead of blending with them")
        (make-motor-parameter :on-channel-loss '(:member :hand-over :end) :hand-over
                              "when a higher priority takes one of a set of channels that move together (an arm's chain): :hand-over gives up the whole set, :end ends the call"))
  "Parameters every motor function takes besides its own (and :priority, whose
default each function declares).")

(defmacro define-motor-function (name driver-class documentation &body parameters)
  "Define the motor function NAME (a keyword) performed by DRIVER-CLASS, with
PARAMETERS, each (KEY TYPE DEFAULT DOCUMENTATION); DEFAULT :REQUIRED means the
caller must give it.  Give (:priority :real N \"...\") to set the default priority."
  `(setf (gethash ,name *motor-functions*)
         (make-motor-function ,name ',driver-class ,documentation
                              (append (list ,@(loop for (key type default doc) in parameters
                                                    collect `(make-motor-parameter ,key ',type ',default ,doc)))
                                      ,@(unless (assoc :priority parameters)
                                          '((list (make-motor-parameter :priority :real 10 "arbitration priority; higher wins"))))
                                      *common-motor-parameters*))))

(defun find-motor-function (name &optional (errorp t) form)
  "The motor function called NAME, or a MOTOR-ERROR about FORM naming the known ones (NIL without ERRORP)."
  (or (and (symbolp name) (gethash name *motor-functions*))
      (and errorp
           (motor-fail (or form name) "unknown motor function ~A (known: ~{~A~^ ~})"
                       (lisp-text name) (mapcar #'lisp-text (motor-function-names))))))

(defun motor-function-names ()
  "The names of every motor function, sorted."
  (sort (hash-table-keys *motor-functions*) #'string<))

(defun describe-motor-function (name &optional (stream *standard-output*))
  "Print NAME's documentation and parameters with their types and defaults."
  (check-argument 'describe-motor-function 'name name #'keywordp
                  (format nil "a motor function's name (~{~A~^, ~})" (mapcar #'lisp-text (motor-function-names))))
  (check-argument 'describe-motor-function 'stream stream
                  (lambda (x) (and x (output-stream-designator-p x))) "an output stream or T")
  (let ((function (find-motor-function name)))
    (format stream "~A -- ~A~%" (lisp-text name) (motor-function-documentation function))
    (dolist (parameter (motor-function-parameters function))
      (format stream "  ~A ~A, ~:[default ~A~;required~*~]: ~A~%"
              (lisp-text (motor-parameter-key parameter))
              (motor-type-description (motor-parameter-type parameter))
              (eq (motor-parameter-default parameter) :required)
              (lisp-text (motor-parameter-default parameter))
              (motor-parameter-documentation parameter)))))

;;;# Calls

(defstruct (motor-call (:constructor make-motor-call (function args frame)))
  "A checked motor-function frame: FUNCTION's name and ARGS, every parameter
present (defaults filled in)."
  (function nil :type keyword :read-only t)
  (args '() :type list :read-only t)
  (frame nil :read-only t))

(defun motor-arg (call key)
  "The value of parameter KEY in the motor call CALL."
  (getf (motor-call-args call) key))

(defun parse-motor-frame (frame)
  "Check FRAME, (NAME :PARAMETER VALUE ...), against its motor function and return
a MOTOR-CALL with every default filled in.  Signals MOTOR-ERROR, naming FRAME,
for an unknown function, an unknown, repeated or missing parameter, or a value
of the wrong type.  Nothing else is touched, so a bad frame changes no body."
  (unless (and (consp frame) (alexandria:proper-list-p frame) (bounded-form-p frame)
               (keywordp (first frame)))
    (motor-fail frame
                "a motor call is written (:FUNCTION :PARAMETER VALUE ...), a proper list"))
  (let* ((function (find-motor-function (first frame) t frame))
         (parameters (motor-function-parameters function))
         (plist (rest frame)))
    (unless (evenp (length plist))
      (motor-fail frame "motor function ~A takes :PARAMETER VALUE pairs" (lisp-text (first frame))))
    (loop for (key value) on plist by #'cddr
          for parameter = (find key parameters :key #'motor-parameter-key)
          for seen = (list key) then (cons key seen)
          do (cond ((null parameter)
                    (motor-fail frame "motor function ~A has no parameter ~A (parameters: ~{~A~^ ~})"
                                (lisp-text (first frame)) (lisp-text key)
                                (mapcar (lambda (p) (lisp-text (motor-parameter-key p))) parameters)))
                   ((member key (rest seen))
                    (motor-fail frame "motor function ~A: parameter ~A is given twice"
                                (lisp-text (first frame)) (lisp-text key)))
                   ((not (motor-type-p value (motor-parameter-type parameter)))
                    (motor-fail frame "motor function ~A: ~A must be ~A, not ~A"
                                (lisp-text (first frame)) (lisp-text key)
                                (motor-type-description (motor-parameter-type parameter))
                                (argument-value-text value)))))
    (make-motor-call
     (first frame)
     (loop for parameter in parameters
           for key = (motor-parameter-key parameter)
           for given = (loop for (k v) on plist by #'cddr
                             when (eq k key) return (list v))
           append (list key
                        (cond (given (first given))
                              ((eq (motor-parameter-default parameter) :required)
                               (motor-fail frame "motor function ~A needs ~A (~A)"
                                           (lisp-text (first frame)) (lisp-text key)
                                           (motor-parameter-documentation parameter)))
                              (t (motor-parameter-default parameter)))))
     frame)))
