;;;; placement.lisp -- members placed in a row (no :at) stand clear of the
;;;; set: the row moves, as little as it can, to where no member's body at
;;;; rest stands inside one of the set's pieces (a jukebox, a panel) or
;;;; behind one as the camera sees it.  A member placed with :at stays where
;;;; the author put it.  The set's pieces are its props drawn as boxes that
;;;; stand above the floor members stand on, less those the members carry.

(in-package #:player.cast)

(defparameter *placement-step* 0.05d0
  "Metres between the places tried for a row of members.")

(defparameter *placement-reach* '(1.0d0 0.5d0)
  "How far a row may move to clear the set: sideways (x, either way) and
toward the camera (z), metres.")

(defun shape-box (object)
  "The box around the prop OBJECT's collision shape where it stands now, as
two lists MIN and MAX of x y z, or NIL when it has no box shape."
  (let ((shape (prop-shape object)))
    (when (eq (first shape) :box)
      (let* ((half (mapcar (lambda (x) (/ x 2)) (rest shape)))
             (transform (object-world-transform object))
             (corners (loop for sx in '(-1 1) append
                        (loop for sy in '(-1 1) append
                          (loop for sz in '(-1 1)
                                collect (let ((v (transform-point transform
                                                                  (make-vec3 (* sx (first half)) (* sy (second half))
                                                                             (* sz (third half))))))
                                          (list (vec3-x v) (vec3-y v) (vec3-z v))))))))
        (list (reduce (lambda (a b) (mapcar #'min a b)) corners)
              (reduce (lambda (a b) (mapcar #'max a b)) corners))))))

(defun set-piece-boxes (scene carried)
  "The boxes (MIN MAX) of the set's pieces in SCENE, the world the set comes
from: its visible props with a box shape standing above y = 0.005 (not a
table or floor the members stand on), none a member's own (CARRIED names
what the members' scripts carry)."
  (loop for object in (scene-objects scene)
        for box = (and (eq (object-kind object) :prop)
                       (property-value object 'visible)
                       (not (member-owned-p object carried))
                       (shape-box object))
        when (and box (> (second (second box)) 0.005d0))
          collect box))

(defun boxes-meet-p (a b)
  "Do the boxes A and B, each (MIN MAX), share a volume?"
  (every (lambda (low-a high-a low-b high-b) (and (< low-a high-b) (< low-b high-a)))
         (first a) (second a) (first b) (second b)))

(defun body-box-at (extent place toward-camera)
  "The box of a body whose rest EXTENT about its place is (MIN MAX), standing
at PLACE (x y z), stretched along z to the camera's side (TOWARD-CAMERA +1,
-1, or NIL for no camera): a piece there hides it."
  (let ((low (mapcar #'+ (first extent) place))
        (high (mapcar #'+ (second extent) place)))
    (case toward-camera
      (1 (setf (third high) most-positive-double-float))
      (-1 (setf (third low) most-negative-double-float)))
    (list low high)))

(defun placement-offsets ()
  "The row offsets (DX DZ) tried, nearest first."
  (destructuring-bind (across toward) *placement-reach*
    (let ((offsets (loop for i from (- (round across *placement-step*)) to (round across *placement-step*)
                         append (loop for j from 0 to (round toward *placement-step*)
                                      collect (list (* i *placement-step*) (* j *placement-step*))))))
      (stable-sort offsets #'< :key (lambda (o) (+ (abs (first o)) (abs (second o))))))))

(defun place-row-clear-of-set (members extents pieces toward-camera)
  "Move MEMBERS placed in a row (a CAST-MEMBER without :at) together, by the
nearest offset of PLACEMENT-OFFSETS (its z toward the camera's side,
TOWARD-CAMERA +1 or -1; sideways only when NIL), to where no member's body
box (EXTENTS: a function of a member, its rest box about its place) meets
one of PIECES or a member placed with :at.  Leaves them when they are clear
already, or when no offset clears them all.  Returns MEMBERS."
  (let* ((row (remove-if #'cast-member-explicit members))
         (fixed (loop for member in members
                      when (cast-member-explicit member)
                        collect (body-box-at (funcall extents member) (cast-member-position member) nil)))
         (obstacles (append pieces fixed)))
    (labels ((moved (member offset)
               (destructuring-bind (x y z) (cast-member-position member)
                 (list (+ x (first offset)) y (+ z (* (or toward-camera 0) (second offset))))))
             (clear-p (offset)
               (loop for member in row
                     for box = (body-box-at (funcall extents member) (moved member offset) toward-camera)
                     never (some (lambda (obstacle) (boxes-meet-p box obstacle)) obstacles))))
      (when (and row pieces (not (clear-p '(0d0 0d0))))
        (let ((offset (find-if #'clear-p (remove-if (lambda (o) (and (null toward-camera) (plusp (second o))))
                                                    (rest (placement-offsets))))))
          (when offset
            (dolist (member row)
              (setf (cast-member-position member) (moved member offset))))))))
  members)

(defun member-probes (cast scripts body seed)
  "A table from each spec CAST's members play to a body presenter of it
standing at the origin (SCRIPTS, BODY and SEED as for MAKE-BODY-PRESENTER),
which reads and checks its library once: the members' presenters reuse it,
and PLACE-CAST-CLEAR-OF-SET measures its body and set."
  (let ((probes (make-hash-table :test 'eq)))
    (dolist (member (cast-members cast) probes)
      (let ((spec (find-spec (cast-member-spec member))))
        (unless (gethash spec probes)
          (setf (gethash spec probes)
                (make-body-presenter spec :scripts scripts :body body :seed seed
                                          :name (cast-member-name member) :origin (vec3) :check t)))))))

(defun place-cast-clear-of-set (cast probes)
  "Move CAST's members placed in a row clear of its set's pieces (see
PLACE-ROW-CLEAR-OF-SET), measuring each spec's body and the set on PROBES
\(from MEMBER-PROBES): the set is CAST's (set \"FILE\") or the first
member's library's, the pieces less the props the members carry."
  (let* ((first-probe (gethash (find-spec (cast-member-spec (first (cast-members cast)))) probes))
         (set-scene (performance-scene (or (set-performance cast) (presenter-performance first-probe))))
         (carried (remove-duplicates (loop for probe being the hash-values of probes
                                           append (library-carried-objects (presenter-library probe)))
                                     :test #'string= :key #'symbol-name))
         (camera (find :camera (scene-objects set-scene) :key #'object-kind))
         (camera-z (and camera (vec3-z (object-world-position camera))))
         (extents (make-hash-table :test 'eq)))
    (maphash (lambda (spec probe)
               (multiple-value-bind (low high) (body-rest-extent (performance-body (presenter-performance probe)))
                 (setf (gethash spec extents)
                       (list (list (vec3-x low) (vec3-y low) (vec3-z low))
                             (list (vec3-x high) (vec3-y high) (vec3-z high))))))
             probes)
    (place-row-clear-of-set (cast-members cast)
                            (lambda (member) (gethash (find-spec (cast-member-spec member)) extents))
                            (set-piece-boxes set-scene carried)
                            (cond ((null camera-z) nil) ((plusp camera-z) 1) ((minusp camera-z) -1)))))
