;;;; object-parents.lisp -- a script library's declared objects may hang from
;;;; each other (:parent), but not in a cycle.  Checked when the library is
;;;; loaded, each object's chain of parents walked once, so 20,000 objects in
;;;; one chain load in linear time (issue 31).  Which objects its scripts
;;;; hang from a character, to carry about, is LIBRARY-CARRIED-OBJECTS.

(in-package #:player.performance)

(defun check-object-parents (library)
  "Signal a SCRIPT-ERROR when LIBRARY's declared objects hang from each other in
a cycle.  Each object's chain of parents is walked once: an object whose
chain is known to end is not walked again."
  (let ((objects (script-library-objects library))
        (by-name (make-hash-table :test 'equalp))
        (ends (make-hash-table :test 'eq)))
    (dolist (object (reverse objects))   ; the first of a name wins, as FIND's would
      (setf (gethash (string (scene-object-spec-name object)) by-name) object))
    (flet ((parent-of (object)
             (let* ((parent (scene-object-spec-parent object))
                    (name (if (consp parent) (first parent) parent)))
               (and name (or (symbolp name) (stringp name)) (gethash (string name) by-name)))))
      (dolist (object objects)
        (let ((chain '()) (on-chain (make-hash-table :test 'eq)))
          (loop for o = object then (parent-of o)
                while (and o (not (gethash o ends)))
                do (when (gethash o on-chain)
                     (script-fail (scene-object-spec-form object) "objects hang from each other in a cycle: ~{~A~^ -> ~}"
                                  (mapcar (lambda (x) (lisp-text (scene-object-spec-name x)))
                                          (reverse (cons o (ldiff chain (rest (member o chain))))))))
                   (setf (gethash o on-chain) t)
                   (push o chain))
          (dolist (o chain) (setf (gethash o ends) t)))))))

(defun library-carried-objects (library)
  "The names of the objects LIBRARY's scripts hang from a character (an
:attach to :SELF or to a body's joint): what its character picks up and
carries about, the rest of its objects standing where they are declared.
A scene of several members gives each member his own (src/cast/scene-set.lisp)."
  (let ((names '()))
    (maphash (lambda (key script)
               (declare (ignore key))
               (dolist (item (script-items script))
                 (when (and (attach-item-p item)
                            (not (eq (attach-item-object item) :self))
                            (let ((parent (attach-item-parent item)))
                              (or (eq parent :self) (consp parent))))
                   (pushnew (attach-item-object item) names))))
             (script-library-scripts library))
    (sort names #'string< :key #'symbol-name)))
