;;;; scene-set.lisp -- a scene's one set.  Each member plays in a world of its
;;;; own, placed where it stands, so it moves exactly as it would alone; but
;;;; the scene is drawn with one set -- one table, one jukebox, one camera and
;;;; its lights -- taken from the script library the scene's (set "FILE")
;;;; names, or else from the first member's world, put back at the scene's
;;;; origin.  A member brings its bodies and its own props: those his scripts
;;;; pick up and carry (LIBRARY-CARRIED-OBJECTS: a note, headphones) and what
;;;; hangs from him, drawn where his own world has them -- at his feet, in
;;;; his hand -- the whole time; the set leaves those out.  So each member
;;;; picks up the note lying at his own feet, and no note is ever drawn twice,
;;;; one in a hand and the set's beside it.  The camera is the set's, pulled back to take in
;;;; every member side by side; when it would still lose one (he flies off),
;;;; the render layer's framing camera keeps him in frame.  The objects the
;;;; scene draws are copies made once, so they stay the same from frame to
;;;; frame: the renderer's caches and an export follow each throughout.

(in-package #:player.cast)

(defparameter *set-kinds* '(:prop :camera :light :group)
  "The kinds of object a scene's set is made of.")

(defun parent-object (object)
  "The object OBJECT hangs from (from a joint of it, for a (BODY . JOINT) parent), or NIL."
  (let ((parent (object-parent object)))
    (if (consp parent) (car parent) parent)))

(defun hangs-from-body-p (object)
  "Does OBJECT hang, directly or not, from a body (held in a hand, say)?"
  (loop for o = (parent-object object) then (parent-object o)
        while o
        thereis (typep o 'body)))

(defun member-stage (scene)
  "The group SCENE's bodies hang from, which stands at the member's place, or NIL."
  (let ((body (find-if (lambda (object) (typep object 'body)) (scene-objects scene))))
    (and body (parent-object body))))

(defun copy-slots (copy object &optional fresh-tables)
  "Give COPY, an instance of OBJECT's class, each of OBJECT's slot values:
shared, or with FRESH-TABLES its hash tables (the properties) copied, so
COPY can be changed without changing OBJECT.  Returns COPY."
  (dolist (slot (sb-mop:class-slots (class-of object)) copy)
    (let ((name (sb-mop:slot-definition-name slot)))
      (when (slot-boundp object name)
        (let ((value (slot-value object name)))
          (setf (slot-value copy name)
                (if (and fresh-tables (hash-table-p value)) (alexandria:copy-hash-table value) value)))))))

(defun carried-name-p (object carried)
  "Is OBJECT called one of the names CARRIED (what the members' scripts carry)?"
  (member (symbol-name (object-name object)) carried :key #'symbol-name :test #'string=))

(defun member-owned-p (object carried)
  "Is OBJECT, a prop of a member's world, the member's own rather than the
set's: one the scripts carry (named in CARRIED), or one hanging from a body?"
  (and (eq (object-kind object) :prop)
       (or (carried-name-p object carried) (hangs-from-body-p object))))

(defun member-prop-proxy (object proxies carried)
  "The copy the scene draws of OBJECT, a prop of a member's world: the
member's own (MEMBER-OWNED-P) shares OBJECT's properties and hangs where it
hangs, at the member's place; any other is a hidden copy (the set shows
that prop).  One copy per prop, kept in PROXIES' member table, so the
objects of a scene's frames stay the same from frame to frame."
  (let* ((table (or (gethash :members proxies)
                    (setf (gethash :members proxies) (make-hash-table :test 'eq :weakness :key))))
         (entry (or (gethash object table)
                    (setf (gethash object table) (cons (allocate-instance (class-of object)) nil))))
         (copy (car entry)))
    (cond ((member-owned-p object carried)
           (unless (eq (cdr entry) :own)
             (copy-slots copy object)
             (setf (cdr entry) :own))
           (setf (object-parent copy) (object-parent object)))
          ((not (eq (cdr entry) :hidden))
           (copy-slots copy object t)
           (setf (property-value copy 'visible) nil
                 (cdr entry) :hidden)))
    copy))

(defun member-objects (scene proxies carried &optional set-world)
  "What a member whose world is SCENE brings to the scene's picture: its
bodies and its props (see MEMBER-PROP-PROXY; CARRIED names what the
members' scripts carry); when SCENE is the SET-WORLD, only its own props,
the set drawing the rest."
  (loop for object in (scene-objects scene)
        when (typep object 'body)
          collect object
        else when (and (eq (object-kind object) :prop)
                       (or (not set-world) (member-owned-p object carried)))
               collect (member-prop-proxy object proxies carried)))

(defun set-object-p (object stage carried)
  "Is OBJECT, of the world whose stage is STAGE, part of the set?  Every
prop, camera, light and group but the stage and the props its member owns
\(MEMBER-OWNED-P, CARRIED naming what the members' scripts carry)."
  (and (member (object-kind object) *set-kinds*)
       (not (eq object stage))
       (not (member-owned-p object carried))))

(defun set-proxy (object stage proxies)
  "OBJECT of the set's world as the scene draws it: one copy per object,
kept in PROXIES (a weak EQ table) so the renderer's caches and an export see
the same object every frame, hung each frame where OBJECT hangs now -- from
the scene's origin for the world's STAGE, from a parent's copy for another
object of the set, from a body's joint as OBJECT is (a note picked up)."
  (let ((copy (or (gethash object proxies)
                  (setf (gethash object proxies) (copy-slots (allocate-instance (class-of object)) object))))
        (parent (object-parent object)))
    (setf (object-parent copy)
          (cond ((or (null parent) (eq parent stage)) nil)
                ((and (typep parent 'scene-object) (member (object-kind parent) *set-kinds*)
                      (not (eq parent stage)))
                 (set-proxy parent stage proxies))
                (t parent)))
    copy))

(defun scene-set-objects (scene proxies carried)
  "The set of a scene whose set comes from the world SCENE: its props,
cameras and lights but those the members own (CARRIED naming what their
scripts carry), copied to stand at the scene's origin (see SET-PROXY)."
  (let ((stage (member-stage scene)))
    (loop for object in (scene-objects scene)
          when (set-object-p object stage carried)
            collect (set-proxy object stage proxies))))

(defun members-rest-boxes (member-scenes)
  "The box around each body of MEMBER-SCENES in its rest pose where it stands."
  (loop for scene in member-scenes
        append (loop for object in (scene-objects scene)
                     when (and (typep object 'body) (property-value object 'visible))
                       collect (multiple-value-call #'cons (body-rest-extent object)))))

(defun take-in-members (camera member-scenes proxies)
  "The scene's CAMERA, a set copy, made to take in every member: a camera
object of the scene, where CAMERA would stand pulled back along its view
until every member's body, at rest where it stands, is in the picture (see
CAMERA-TAKING-IN).  Made once (kept in PROXIES under :camera) and moved each frame."
  (let* ((fov (camera-fov camera))
         (transform (camera-taking-in (object-world-transform camera) fov (members-rest-boxes member-scenes)))
         (taking-in (or (gethash :camera proxies)
                        (setf (gethash :camera proxies)
                              (let ((object (make-instance 'scene-object :name (object-name camera) :kind :camera)))
                                (define-property object 'fov :number fov)
                                object)))))
    (setf (property-value taking-in 'position) (transform-translation transform)
          (property-value taking-in 'rotation) (transform-rotation transform))
    taking-in))

(defun set-performance (cast)
  "A performance of the script library CAST's (set \"FILE\") names, on a
hidden stand-in body: the scene's set, standing at the origin; NIL when the
set is the first member's.  Signals what LOAD-SCRIPT-LIBRARY signals."
  (when (cast-set cast)
    (make-performance (load-script-library (cast-set cast)) (list (list '%set 'none)) :silent t)))

(defun gather-scene-objects (set-scene member-scenes proxies &optional carried)
  "The objects of a scene's frame, given SET-SCENE, the world its set comes
from (the first member's, or the scene's own set), MEMBER-SCENES, each
member's world in member order, and CARRIED, the names of the props the
members' scripts carry: the set (its first camera taking in every member),
then every member's bodies and own props."
  (let* ((set (and set-scene (scene-set-objects set-scene proxies carried)))
         (camera (find :camera set :key #'object-kind)))
    (append (if camera
                (substitute (take-in-members camera member-scenes proxies) camera set)
                set)
            (loop for scene in member-scenes
                  append (member-objects scene proxies carried (eq scene set-scene))))))
