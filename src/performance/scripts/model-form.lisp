;;;; model-form.lisp -- the (model "FILE" ...) form of a script library: the
;;;; character is an imported model (src/model/, made a skeleton by
;;;; src/rig/), taking the place of the spec's (:body NAME).
;;;;
;;;;   (model "FILE" &key texture height scale up roles clips limits)
;;;;
;;;; FILE and :texture are relative to the library file.  :height is the bind
;;;; pose's height in metres (or :scale, metres per unit of the file; default:
;;;; the file's units are metres); :up is the model's up axis, :y (default) or
;;;; :z.  :roles ((ROLE "JOINT") (ROLE ("JOINT" ...)) ...) wins over the roles
;;;; guessed from the joints' names.  :clips ((NAME :from FRAME :to FRAME :fps
;;;; N [:animation NAME-OR-INDEX]) ...) cuts clips by frame range; every
;;;; animation of the file is a clip too, named in lower case with other
;;;; characters turned to -.  :limits ((JOINT-OR-ROLE (AXIS MIN MAX) ...) ...)
;;;; narrows DOFs (an imported joint turns +-180 degrees about x, y and z).
;;;; A model with no joints is no character; (defobject NAME :kind :prop
;;;; :model "FILE" [:texture F] [:height H | :scale S] [:up :y|:z]) draws it
;;;; as a prop (PARSE-PROP-MODEL).

(in-package #:player.performance)

(defparameter *model-form-options* '(:texture :height :scale :up :roles :clips :limits)
  "The options of a (model \"FILE\" ...) form.")

(defun model-form-path (form name what)
  "NAME, a file named in FORM, resolved against the library's directory; a
SCRIPT-ERROR when it is not a nonempty string."
  (unless (and (stringp name) (plusp (length name)))
    (script-fail form "~A is a file's name in a string, not ~A" what (argument-value-text name)))
  (merge-pathnames name (or *library-directory* *default-pathname-defaults*)))

(defun import-library-model (form path texture)
  "The MODEL imported from PATH (with TEXTURE, a path, as every mesh's
texture when given), FORM naming it; a texture that cannot be decoded fails
here, at FORM's line, not at render.  Signals PLAYER-ERRORs."
  (let ((model (import-model path :texture (and texture (model-form-path form texture ":texture")))))
    (loop for (texture-path . result) in (model-texture-images model)
          when (typep result 'image-error)
            do (script-fail form "~A: ~A" (file-namestring texture-path) result))
    model))

(defun parse-model-form (form)
  "The SKELETON (with its rig) that FORM, (model \"FILE\" &key ...), makes of the
model file: imported, scaled, its roles and clips resolved.  Any problem with
the file, its texture or the options is a SCRIPT-ERROR at FORM's line; a
model with no joints and no morph targets is one saying to make it a prop."
  (unless (and (alexandria:proper-list-p form) (>= (length form) 2))
    (script-fail form "a model is written (model \"FILE\" &key texture height scale up roles clips limits)"))
  (let* ((path (model-form-path form (second form) "the model"))
         (options (check-options form (cddr form) *model-form-options* "the model form")))
    (destructuring-bind (&key texture height scale (up :y) roles clips limits) options
      (handler-case
          (let ((model (import-library-model form path texture)))
            ;; A face of morph targets without joints is a character (one root
            ;; joint is made for it); a model with neither moves nothing.
            (when (and (zerop (length (model-joints model))) (null (model-morph-targets model)))
              (script-fail form "~A has no joints, so it cannot be the character: draw it as a prop, ~
                                 (defobject NAME :kind :prop :model ~S)"
                           (file-namestring path) (second form)))
            (model-skeleton model :height height :scale scale :up up :roles roles :limits limits
                                  :clips clips :name (make-symbol (pathname-name path))))
        ;; A RIG-ERROR names its own clause and line already; a model's or an
        ;; image's error names only the file, so it is placed at the form.
        (spec-error (error) (error error))
        (player-error (error)
          (script-fail form "~A" error))))))

(defun parse-prop-model (form file texture height scale up)
  "The PROP-MODEL of a (defobject NAME :kind :prop :model FILE ...) FORM:
FILE (and TEXTURE) relative to the library, imported and checked; HEIGHT,
SCALE and UP as the model form's.  Any problem is a SCRIPT-ERROR at FORM's line."
  (let ((path (model-form-path form file ":model")))
    (handler-case (make-prop-model (import-library-model form path texture)
                                   :height height :scale scale :up up)
      (script-error (error) (error error))
      (player-error (error) (script-fail form "~A" error)))))

(defun set-library-model (library form)
  "Record in LIBRARY the skeleton of its (model \"FILE\" ...) FORM; a library has one."
  (when (script-library-skeleton library)
    (script-fail form "a library names one model; this is the second"))
  (setf (script-library-skeleton library) (parse-model-form form)))
