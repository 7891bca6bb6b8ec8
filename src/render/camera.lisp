;;;; camera.lisp -- where a frame is seen from: the scene's camera object (or a
;;;; default one framing the characters), orbit offsets for the viewer, and the
;;;; view and perspective matrices the shaders take.

(in-package #:player.render)

;;; A camera object looks along its own -z with +y up, like an OpenGL eye, so
;;; its world transform is the inverse of the view matrix.  Its FOV property
;;; is the vertical field of view in degrees.  Matrices here are MAT4-shaped
;;; (row, column) double-float arrays; UPLOAD-MATRIX hands them to GL.

(defparameter *default-fov* 35d0
  "Vertical field of view, in degrees, of a camera without a FOV property.")

(defparameter *near-plane* 0.02d0 "Metres from the eye to the near clipping plane.")
(defparameter *far-plane* 80d0 "Metres from the eye to the far clipping plane.")

(defparameter *default-camera-pitch* -8d0
  "Degrees the default camera looks down, so the floor under the character shows.")

(defstruct (view (:constructor %make-view))
  "A frame's viewpoint: VIEW-PROJECTION maps world points to clip space,
INVERSE-VIEW-PROJECTION back; EYE is the camera's world position, CAMERA its
world transform (after any orbit), FOV its vertical field in degrees."
  view-projection inverse-view-projection eye camera (fov *default-fov*))

(defstruct (orbit (:constructor make-orbit (&key (yaw 0d0) (pitch 0d0) (distance 1d0))))
  "How the viewer has moved the camera: YAW about the world's up axis and PITCH
about the camera's own x axis (radians), both around the point the camera
looks at, and DISTANCE, a factor on how far from that point it stands."
  (yaw 0d0 :type double-float)
  (pitch 0d0 :type double-float)
  (distance 1d0 :type double-float))

;;;# Matrices

(defun mat4* (a b)
  "The product A B of two 4x4 double-float matrices, as a new one."
  (let ((m (make-array '(4 4) :element-type 'double-float :initial-element 0d0)))
    (dotimes (i 4 m)
      (dotimes (j 4)
        (setf (aref m i j) (loop for k below 4 sum (* (aref a i k) (aref b k j))))))))

(defun perspective-matrices (fov aspect near far)
  "The OpenGL perspective projection for a vertical field of FOV degrees, width
over height ASPECT and clipping planes NEAR and FAR, and its inverse: two values."
  (let* ((f (/ 1d0 (tan (* 0.5d0 (float fov 1d0) (/ pi 180)))))
         (a (/ (+ far near) (- near far)))
         (b (/ (* 2 far near) (- near far)))
         (p (make-array '(4 4) :element-type 'double-float :initial-element 0d0))
         (inverse (make-array '(4 4) :element-type 'double-float :initial-element 0d0)))
    (setf (aref p 0 0) (/ f aspect) (aref p 1 1) f (aref p 2 2) a (aref p 2 3) b (aref p 3 2) -1d0
          (aref inverse 0 0) (/ aspect f) (aref inverse 1 1) (/ f)
          (aref inverse 2 3) -1d0 (aref inverse 3 2) (/ b) (aref inverse 3 3) (/ a b))
    (values p inverse)))

(defun upload-matrix (location matrix)
  "Set the mat4 uniform at LOCATION to MATRIX (row, column indexed), column-major as GL reads it."
  (cffi:with-foreign-object (floats :float 16)
    (dotimes (column 4)
      (dotimes (row 4)
        (setf (cffi:mem-aref floats :float (+ row (* 4 column))) (float (aref matrix row column) 1f0))))
    (gl-uniform-matrix4fv location 1 +gl-false+ floats)))

(defun project-point (view point width height)
  "Where the world vec3 POINT lands in a WIDTH x HEIGHT frame seen through VIEW:
pixel column and row (top-down, fractional) as two values, and its clip w."
  (let* ((m (view-view-projection view))
         (p (list (vec3-x point) (vec3-y point) (vec3-z point) 1d0))
         (clip (loop for i below 4 collect (loop for j below 4 for x in p sum (* (aref m i j) x))))
         (w (fourth clip)))
    (values (* width (* 0.5d0 (+ 1 (/ (first clip) w))))
            (* height (* 0.5d0 (- 1 (/ (second clip) w))))
            w)))

;;;# What there is to look at

(defun scene-bodies (scene)
  "SCENE's visible bodies, in scene order."
  (remove-if-not (lambda (object) (and (typep object 'body) (property-value object 'visible)))
                 (scene-objects scene)))

(defun model-rest-extent (body)
  "The box around BODY's skin in its bind pose (its rig's bounds) at its
placement, as two vec3s MIN and MAX."
  (let ((corners (mapcar (lambda (corner) (transform-point (object-world-transform body) corner))
                         (box-corners (rig-bounds (skeleton-rig (body-skeleton body)))))))
    (values (reduce (lambda (a b) (vec3 (min (vec3-x a) (vec3-x b)) (min (vec3-y a) (vec3-y b)) (min (vec3-z a) (vec3-z b))))
                    corners)
            (reduce (lambda (a b) (vec3 (max (vec3-x a) (vec3-x b)) (max (vec3-y a) (vec3-y b)) (max (vec3-z a) (vec3-z b))))
                    corners))))

(defun body-rest-extent (body)
  "The box around BODY's joints in its skeleton's rest pose at its placement,
each joint grown by its radius, as two vec3s MIN and MAX; for an imported
model, the box around its skin in the bind pose.  The default camera frames
this, not the current pose, so that it holds still while the body moves."
  (when (skeleton-rig (body-skeleton body))
    (return-from body-rest-extent (model-rest-extent body)))
  (let ((placement (object-world-transform body))
        (low (list most-positive-double-float most-positive-double-float most-positive-double-float))
        (high (list most-negative-double-float most-negative-double-float most-negative-double-float)))
    (loop for joint across (skeleton-joints (body-skeleton body))
          for r = (body-joint-radius joint)
          for p = (transform-point placement (apply #'make-vec3 (coerce (body-joint-center joint) 'list)))
          for xyz = (list (vec3-x p) (vec3-y p) (vec3-z p))
          do (setf low (mapcar (lambda (a b) (min a (- b r))) low xyz)
                   high (mapcar (lambda (a b) (max a (+ b r))) high xyz)))
    (values (apply #'make-vec3 low) (apply #'make-vec3 high))))

(defun scene-focus (scene)
  "The centre and radius (two values) of a sphere around SCENE's bodies in their
rest poses, or a point a metre up and radius 1 when it has none."
  (let ((boxes (loop for body in (scene-bodies scene)
                     collect (multiple-value-list (body-rest-extent body)))))
    (if (null boxes)
        (values (vec3 0d0 1d0 0d0) 1d0)
        (let ((low (reduce (lambda (a b) (vec3 (min (vec3-x a) (vec3-x b)) (min (vec3-y a) (vec3-y b))
                                               (min (vec3-z a) (vec3-z b))))
                           (mapcar #'first boxes)))
              (high (reduce (lambda (a b) (vec3 (max (vec3-x a) (vec3-x b)) (max (vec3-y a) (vec3-y b))
                                                (max (vec3-z a) (vec3-z b))))
                            (mapcar #'second boxes))))
          (values (vlerp low high 0.5d0) (* 0.5d0 (vdistance low high)))))))

;;;# Cameras

(defun scene-camera (scene)
  "SCENE's first camera object, or NIL."
  (find :camera (scene-objects scene) :key #'object-kind))

(defun camera-fov (camera)
  "CAMERA's vertical field of view in degrees: its FOV property, else *DEFAULT-FOV*."
  (let ((fov (and camera (property-type camera 'fov nil) (property-value camera 'fov))))
    (if (and fov (< 1 fov 179)) (float fov 1d0) *default-fov*)))

(defun default-camera-transform (scene &optional (fov *default-fov*))
  "A camera pose framing SCENE's characters from their front (+z), a little
above and looking slightly down, far enough back that the sphere around them
fills 85% of the height of a FOV-degree view."
  (multiple-value-bind (centre radius) (scene-focus scene)
    (let* ((rotation (quat-from-axis-angle (vec3 1d0 0d0 0d0) (* *default-camera-pitch* (/ pi 180))))
           (back (qrotate rotation (vec3 0d0 0d0 1d0)))
           (distance (/ radius (* 0.85d0 (tan (* 0.5d0 fov (/ pi 180)))))))
      (make-transform :rotation rotation :translation (v+ centre (v* back distance))))))

(defun box-corners (bounds)
  "The 8 corners of the box BOUNDS, (MIN . MAX) vec3s, as a list of vec3s."
  (loop for corner below 8
        collect (vec3 (vec3-x (if (logbitp 0 corner) (cdr bounds) (car bounds)))
                      (vec3-y (if (logbitp 1 corner) (cdr bounds) (car bounds)))
                      (vec3-z (if (logbitp 2 corner) (cdr bounds) (car bounds))))))

(defun corners-fit-p (corners camera tangent aspect fill)
  "Do all CORNERS (vec3s) lie in front of the CAMERA transform and within FILL
of a view whose vertical half-field has the TANGENT, width over height ASPECT?"
  (let ((view (transform-invert camera)))
    (every (lambda (corner)
             (let* ((p (transform-point view corner))
                    (depth (- (vec3-z p))))
               (and (> depth *near-plane*)
                    (<= (abs (vec3-y p)) (* fill tangent depth))
                    (<= (abs (vec3-x p)) (* fill tangent aspect depth)))))
           corners)))

(defun frame-bounds-camera (bounds &key (aspect 4/3) (fov *default-fov*) (fill 0.85d0))
  "A camera transform looking at the box BOUNDS, a (MIN . MAX) pair of vec3s
\(a rig's bind-pose bounds moved to where its body stands), from its front
\(+z towards the viewer), a little above and looking *DEFAULT-CAMERA-PITCH*
degrees down at its centre, as near as lets every corner of the box lie
within FILL of the height and width of a FOV-degree view of width over
height ASPECT.  Unlike DEFAULT-CAMERA-TRANSFORM's sphere, the box frames a
long model (a quadruped, a snake) without standing far off."
  (let* ((centre (vlerp (car bounds) (cdr bounds) 0.5d0))
         (corners (box-corners bounds))
         (aspect (float aspect 1d0))
         (tangent (tan (* 0.5d0 (float fov 1d0) (/ pi 180))))
         (rotation (quat-from-axis-angle (vec3 1d0 0d0 0d0) (* *default-camera-pitch* (/ pi 180))))
         (back (qrotate rotation (vec3 0d0 0d0 1d0)))
         (size (max 0.01d0 (vdistance (car bounds) (cdr bounds)))))
    (flet ((camera (distance)
             (make-transform :rotation rotation :translation (v+ centre (v* back distance)))))
      ;; Step back from a tenth of the box's diagonal until it fits: 2% steps,
      ;; finer than a pixel's worth of framing at any size Player renders.
      (loop for distance = (* 0.1d0 size) then (* distance 1.02d0)
            for camera = (camera distance)
            when (or (corners-fit-p corners camera tangent aspect fill) (> distance (* 100 size)))
              return camera))))

(defun scene-model-bounds (scene)
  "The box, (MIN . MAX) vec3s, around SCENE's visible imported models in their
bind poses where they stand, or NIL when none of its bodies is one."
  (let ((boxes (loop for body in (scene-bodies scene)
                     when (skeleton-rig (body-skeleton body))
                       collect (multiple-value-list (model-rest-extent body)))))
    (when boxes
      (cons (reduce (lambda (a b) (vec3 (min (vec3-x a) (vec3-x b)) (min (vec3-y a) (vec3-y b)) (min (vec3-z a) (vec3-z b))))
                    (mapcar #'first boxes))
            (reduce (lambda (a b) (vec3 (max (vec3-x a) (vec3-x b)) (max (vec3-y a) (vec3-y b)) (max (vec3-z a) (vec3-z b))))
                    (mapcar #'second boxes))))))

(defun orbit-transform (camera focus orbit)
  "The camera transform CAMERA moved by ORBIT around the point FOCUS metres in
front of it: yawed about world +y, pitched about its own x, its distance scaled."
  (let* ((forward (transform-vector camera (vec3 0d0 0d0 -1d0)))
         (pivot (v+ (transform-translation camera) (v* forward focus)))
         (yaw (quat-from-axis-angle (vec3 0d0 1d0 0d0) (orbit-yaw orbit)))
         (pitch (quat-from-axis-angle (vec3 1d0 0d0 0d0) (orbit-pitch orbit)))
         (rotation (qnormalize (q* yaw (q* (transform-rotation camera) pitch))))
         (back (qrotate rotation (vec3 0d0 0d0 1d0))))
    (make-transform :rotation rotation
                    :translation (v+ pivot (v* back (* focus (max 0.05d0 (orbit-distance orbit))))))))

(defun camera-focus-distance (camera scene)
  "How far in front of CAMERA (a transform) the viewer orbits: the depth of the
characters' centre, or 1.5 m when they are behind it or absent."
  (let ((depth (vdot (v- (scene-focus scene) (transform-translation camera))
                     (transform-vector camera (vec3 0d0 0d0 -1d0)))))
    (if (> depth 0.1d0) depth 1.5d0)))

;;;# Keeping the characters in frame

(defun box-union (a b)
  "The box around the boxes A and B, (MIN . MAX) vec3 pairs; either may be NIL."
  (cond ((null a) b)
        ((null b) a)
        (t (cons (vec3 (min (vec3-x (car a)) (vec3-x (car b))) (min (vec3-y (car a)) (vec3-y (car b)))
                       (min (vec3-z (car a)) (vec3-z (car b))))
                 (vec3 (max (vec3-x (cdr a)) (vec3-x (cdr b))) (max (vec3-y (cdr a)) (vec3-y (cdr b)))
                       (max (vec3-z (cdr a)) (vec3-z (cdr b))))))))

(defun body-current-bounds (body)
  "The box, (MIN . MAX) vec3s, around BODY's joints where they are now (as
last evaluated), each grown by its radius; NIL before its first evaluation."
  (let ((transforms (body-transforms body))
        (joints (skeleton-joints (body-skeleton body))))
    (when (and (simple-vector-p transforms) (= (length transforms) (length joints)))
      (loop with box = nil
            for joint across joints
            for r = (float (body-joint-radius joint) 1d0)
            for p = (joint-world-position transforms joint)
            do (setf box (box-union box (cons (v- p (vec3 r r r)) (v+ p (vec3 r r r)))))
            finally (return box)))))

(defun point-box-distance (point box)
  "How far POINT lies outside BOX, a (MIN . MAX) pair (0 inside)."
  (flet ((excess (p low high) (max 0d0 (- low p) (- p high))))
    (let ((x (excess (vec3-x point) (vec3-x (car box)) (vec3-x (cdr box))))
          (y (excess (vec3-y point) (vec3-y (car box)) (vec3-y (cdr box))))
          (z (excess (vec3-z point) (vec3-z (car box)) (vec3-z (cdr box)))))
      (sqrt (+ (* x x) (* y y) (* z z))))))

(defun view-axis-miss (camera box)
  "How far the ray the CAMERA transform looks along passes from BOX: 0 when
it goes through it.  The distance from a ray to a convex box is convex
along the ray, so a ternary search over the first kilometre finds it."
  (let ((eye (transform-translation camera))
        (forward (transform-vector camera (vec3 0d0 0d0 -1d0))))
    (flet ((miss (s) (point-box-distance (v+ eye (v* forward s)) box)))
      (loop with low = 0d0 and high = 1d3
            repeat 80
            do (let ((a (/ (+ low low high) 3)) (b (/ (+ low high high) 3)))
                 (if (<= (miss a) (miss b)) (setf high b) (setf low a)))
            finally (return (miss (* 0.5d0 (+ low high))))))))

(defun fitting-dolly (camera box tangent aspect &optional (fill 1d0))
  "The least distance the CAMERA transform must move back along its view
axis for every corner of BOX to lie within FILL of its view (vertical
half-field TANGENT, ASPECT): 0 when it fits already."
  (flet ((fits-p (distance)
           (corners-fit-p (box-corners box) (dolly-back camera distance) tangent aspect fill)))
    (if (fits-p 0d0)
        0d0
        ;; Double until the box fits (or hopelessly far), then halve the gap
        ;; down to a millimetre: the nearest distance that fits.
        (let ((far (loop for distance = 0.05d0 then (* 2 distance)
                         when (or (fits-p distance) (> distance 1d3)) return distance))
              (near 0d0))
          (loop while (> (- far near) 1d-3)
                do (let ((middle (* 0.5d0 (+ near far))))
                     (if (fits-p middle) (setf far middle) (setf near middle))))
          far))))

(defun dolly-back (transform distance)
  "The camera TRANSFORM moved DISTANCE metres back along its own view axis."
  (make-transform :rotation (transform-rotation transform)
                  :translation (v+ (transform-translation transform)
                                   (transform-vector transform (vec3 0d0 0d0 distance)))))

(defun camera-taking-in (transform fov boxes &key (aspect 4/3) (fill 0.75d0))
  "The camera TRANSFORM (of FOV degrees) pulled back along its view axis,
if need be, until the box around BOXES ((MIN . MAX) vec3 pairs) lies within
FILL of a view of ASPECT: how a scene's one camera takes in every member."
  (let ((box (reduce #'box-union boxes :initial-value nil)))
    (if box
        (dolly-back transform (fitting-dolly transform box (tan (* 0.5d0 fov (/ pi 180))) (float aspect 1d0)
                                             (float fill 1d0)))
        transform)))

(defun keep-in-frame (transform scene fov aspect)
  "TRANSFORM, a scene camera's, pulled back along its view axis as far as
keeps each body of SCENE in frame: a framing camera driven by the bodies'
bounds where they are now.  A body the camera looks at (its view axis goes
through the body's box: a close-up, say) is the library's shot and pulls
nothing; one the axis misses by a box's half-diagonal or more, flown out of
the shot, pulls the camera back until all of it is in frame; in between, in
proportion, so the picture never jumps."
  (let ((tangent (tan (* 0.5d0 fov (/ pi 180))))
        (distance 0d0))
    (dolist (body (scene-bodies scene))
      (let ((box (body-current-bounds body)))
        (when box
          (let* ((radius (max 1d-3 (* 0.5d0 (vdistance (car box) (cdr box)))))
                 (weight (min 1d0 (/ (view-axis-miss transform box) radius))))
            (when (plusp weight)
              (setf distance (max distance (* weight (fitting-dolly transform box tangent aspect)))))))))
    (if (plusp distance) (dolly-back transform distance) transform)))

(defun scene-view (scene aspect &key orbit camera)
  "The VIEW of SCENE for a frame of width over height ASPECT: through CAMERA (a
camera object, default the scene's first; when that would lose a character,
a camera framing the bodies where they are, see KEEP-IN-FRAME), or a default
camera framing the characters (FRAME-BOUNDS-CAMERA when they are imported
models), moved by ORBIT when given."
  (let* ((object (or camera (scene-camera scene)))
         (fov (camera-fov object))
         (models (and (null object) (scene-model-bounds scene)))
         ;; Scenes of Player's own skeletons keep the sphere framing they always had.
         (transform (cond (object (keep-in-frame (object-world-transform object) scene fov
                                                 (float aspect 1d0)))
                          (models (frame-bounds-camera models :aspect aspect :fov fov))
                          (t (default-camera-transform scene fov))))
         (transform (if orbit
                        (orbit-transform transform (camera-focus-distance transform scene) orbit)
                        transform)))
    (multiple-value-bind (projection inverse-projection)
        (perspective-matrices fov aspect *near-plane* *far-plane*)
      (%make-view :view-projection (mat4* projection (transform-invert transform))
                  :inverse-view-projection (mat4* transform inverse-projection)
                  :eye (transform-translation transform) :camera transform :fov fov))))
