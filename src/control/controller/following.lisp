;;;; following.lisp -- controllers that follow their spec: re-evaluating the
;;;; DEFSPEC (or reloading its file) switches them to the new definition.
;;;;
;;;; Followers are held weakly, so a controller nobody uses is forgotten.  When
;;;; DEFINE-SPEC registers a spec, the spec is compiled once (plan rows whose
;;;; inputs did not change are reused, see plan-memo.lisp) and each follower of
;;;; that name is handed the new machine through its DELIVER function: by
;;;; default REDEFINE-CONTROLLER there and then; a controller running on
;;;; another thread (a viewer's) delivers it to that thread instead.  Errors
;;;; never escape into DEFINE-SPEC: they become REDEFINITION-WARNINGs, and the
;;;; controller keeps its old machine.

(in-package #:player.control)

(defvar *followers* (make-hash-table :test 'eq :weakness :key :synchronized t)
  "Controller -> the function that hands it a new machine of its spec.")

(defun redefine-or-warn (controller machine)
  "REDEFINE-CONTROLLER CONTROLLER to MACHINE; a PLAYER-ERROR becomes a
REDEFINITION-WARNING and the controller keeps its machine."
  (handler-case (redefine-controller controller machine)
    (player-error (e)
      (warn 'redefinition-warning :error e :controller controller))))

(defun follow-spec (controller &key (deliver #'redefine-or-warn))
  "Make CONTROLLER follow its spec: whenever a spec of the same name is
defined again, DELIVER is called with CONTROLLER and the new compiled machine
(by default REDEFINE-OR-WARN: switch at the next safe point, or warn and keep
the old machine).  Returns CONTROLLER.  An ARGUMENT-ERROR for a non-controller."
  (check-argument 'follow-spec 'controller controller #'controller-p "a controller (from make-controller)")
  (check-argument 'follow-spec :deliver deliver #'functionp "a function of a controller and a machine")
  (setf (gethash controller *followers*) deliver)
  controller)

(defun unfollow-spec (controller)
  "Stop CONTROLLER following its spec; true when it did."
  (check-argument 'unfollow-spec 'controller controller #'controller-p "a controller (from make-controller)")
  (remhash controller *followers*))

(defun spec-followers (spec)
  "The (CONTROLLER . DELIVER) pairs that follow the spec named as SPEC is."
  (let ((key (name-key (spec-name spec))))
    (sb-ext:with-locked-hash-table (*followers*)
      (loop for controller being the hash-keys of *followers* using (hash-value deliver)
            when (equal key (name-key (spec-name (spec-of controller))))
              collect (cons controller deliver)))))

(defun update-followers (spec)
  "Hand the controllers following SPEC's name SPEC compiled (a hook of
DEFINE-SPEC).  A spec that does not compile is reported by a
REDEFINITION-WARNING per follower, which keeps its machine."
  (let ((followers (spec-followers spec)))
    (when followers
      (let ((machine (handler-case (compile-spec spec)
                       (player-error (e)
                         (loop for (controller) in followers
                               do (warn 'redefinition-warning :error e :controller controller))
                         (return-from update-followers nil)))))
        (loop for (controller . deliver) in followers
              do (funcall deliver controller machine))))))

(pushnew 'update-followers *spec-definition-hooks*)
