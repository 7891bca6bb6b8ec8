;;;; collisions.lisp -- hands never pass through things.  After a body's pose
;;;; is composed, its hands (probes) are tested against the props of the set
;;;; and against the trunks of the bodies (its own too); a pose that would put
;;;; a hand inside one deeper than *CONTACT-TOLERANCE* stops at contact: it is
;;;; moved from the pose shown before toward the composed one only as far as
;;;; the hands stay out (found by bisection).  What a hand reaches for (a
;;;; driver's (:object NAME) target) and what it holds are not obstacles, so
;;;; fetching the note still touches it.

(in-package #:player.physics)

(defparameter *contact-tolerance* 0.002d0
  "Metres a hand may sink into a surface before it counts as passing through:
touching is allowed, and ODE's contact depths carry a little slack.")

(defun body-held-objects-and-targets (body scene)
  "The names of the objects BODY holds (hanging from it or its joints) or
reaches for (an active driver's (:object NAME) target)."
  (append (loop for object in (scene-objects scene)
                for parent = (object-parent object)
                when (or (eq parent body) (and (consp parent) (eq (car parent) body)))
                  collect (object-name object))
          (loop for driver in (body-active body)
                for target = (driver-arg driver :target)
                when (and (consp target) (eq (first target) :object) (symbolp (second target)))
                  collect (second target))))

(defun static-reach (shape)
  "The radius of a sphere holding SHAPE around its centre (NIL for a plane: unbounded)."
  (ecase (first shape)
    (:plane nil)
    (:sphere (second shape))
    (:box (* 0.5d0 (sqrt (+ (expt (second shape) 2) (expt (third shape) 2) (expt (fourth shape) 2)))))))

(declaim (inline near-p trunk-near-p))
(defun near-p (centre reach x y z radius)
  "Might a sphere of RADIUS at (X Y Z) touch a shape within REACH of CENTRE (NIL: unbounded)?"
  (declare (type vec3 centre) (type double-float x y z radius))
  (or (null reach)
      (let ((dx (- x (vec3-x centre))) (dy (- y (vec3-y centre))) (dz (- z (vec3-z centre)))
            (limit (+ (float reach 1d0) radius (float *contact-tolerance* 1d0))))
        (declare (type double-float dx dy dz limit))
        (<= (+ (* dx dx) (* dy dy) (* dz dz)) (* limit limit)))))

(defun static-box (shape)
  "For a :box SHAPE, a vector for SET-BOX-ROTATION and BOX-NEAR-P: no rotation
yet, and the box's half sizes; NIL for another shape."
  (when (eq (first shape) :box)
    (let ((box (make-array 12 :element-type 'double-float :initial-element 0d0)))
      (setf (aref box 0) 1d0 (aref box 4) 1d0 (aref box 8) 1d0)
      (loop for size in (rest shape)
            for i from 9
            do (setf (aref box i) (* 0.5d0 (float size 1d0))))
      box)))

(defun set-box-rotation (box w x y z)
  "Store in BOX the rotation matrix of the quaternion (W X Y Z), normalised as ODE does."
  (declare (type (simple-array double-float (12)) box))
  (let* ((w (float w 1d0)) (x (float x 1d0)) (y (float y 1d0)) (z (float z 1d0))
         (norm (sqrt (+ (* w w) (* x x) (* y y) (* z z)))))
    (declare (type double-float w x y z norm))
    (when (plusp norm)
      (setf w (/ w norm) x (/ x norm) y (/ y norm) z (/ z norm))
      (setf (aref box 0) (- 1d0 (* 2d0 (+ (* y y) (* z z))))
            (aref box 1) (* 2d0 (- (* x y) (* w z)))
            (aref box 2) (* 2d0 (+ (* x z) (* w y)))
            (aref box 3) (* 2d0 (+ (* x y) (* w z)))
            (aref box 4) (- 1d0 (* 2d0 (+ (* x x) (* z z))))
            (aref box 5) (* 2d0 (- (* y z) (* w x)))
            (aref box 6) (* 2d0 (- (* x z) (* w y)))
            (aref box 7) (* 2d0 (+ (* y z) (* w x)))
            (aref box 8) (- 1d0 (* 2d0 (+ (* x x) (* y y))))))
    box))

(declaim (inline box-near-p))
(defun box-near-p (box centre x y z radius)
  "Might a sphere of RADIUS at (X Y Z) touch the box BOX (see STATIC-BOX) at
CENTRE?  Its distance to the box, in the box's frame, against RADIUS; a hair
generous, so only a query (ODE's) finds a touch."
  (declare (type (simple-array double-float (12)) box) (type vec3 centre)
           (type double-float x y z radius))
  (let ((dx (- x (vec3-x centre))) (dy (- y (vec3-y centre))) (dz (- z (vec3-z centre)))
        (outside 0d0)
        (limit (+ radius (float *contact-tolerance* 1d0) 1d-6)))
    (declare (type double-float dx dy dz outside limit))
    ;; The point in the box's frame is R^T d; past each face by |that| - half size.
    (dotimes (i 3)
      (let ((excess (- (abs (+ (* (aref box i) dx) (* (aref box (+ 3 i)) dy) (* (aref box (+ 6 i)) dz)))
                       (aref box (+ 9 i)))))
        (declare (type double-float excess))
        (when (plusp excess) (incf outside (* excess excess)))))
    (<= outside (* limit limit))))

(declaim (inline static-near-p))
(defun static-near-p (static x y z radius)
  "Might a sphere of RADIUS at (X Y Z) touch STATIC's shape?"
  (and (near-p (physics-static-centre static) (physics-static-reach static) x y z radius)
       (let ((box (physics-static-box static)))
         (or (null box) (box-near-p box (physics-static-centre static) x y z radius)))))

(declaim (inline collider-near-p))
(defun collider-near-p (collider x y z radius)
  "Might a sphere of RADIUS at (X Y Z) touch any trunk part of COLLIDER?"
  (let ((reach (collider-reach collider)))
    (or (null reach)
        (near-p (collider-centre collider) reach x y z radius))))

(defun trunk-near-p (part x y z radius)
  "Might a sphere of RADIUS at (X Y Z) touch the trunk PART?"
  (declare (type double-float radius))
  (<= (the double-float (axis-distance part x y z))
      (+ (trunk-part-radius part) radius (float *contact-tolerance* 1d0))))

(defun probe-hits (probe point physics excluded)
  "The obstacles the PROBE placed at POINT (a vec3) sinks into deeper than
*CONTACT-TOLERANCE*, as (OBSTACLE DEPTH): a PHYSICS-STATIC or a TRUNK-PART;
EXCLUDED names objects that are not obstacles.  The probe's geom is put there
only when an obstacle is near."
  (declare (type vec3 point))
  (let ((x (vec3-x point)) (y (vec3-y point)) (z (vec3-z point))
        (geom (probe-geom probe)) (radius (probe-radius probe)) (placed nil) (hits '()))
    (macrolet ((depth (other)
                 `(progn (unless placed
                           (place-probe probe x y z)
                           (setf placed t))
                         (ode-geom-depth geom ,other))))
      (dolist (static (scene-physics-statics physics))
        (let ((object (physics-static-object static)))
          (when (and (static-near-p static x y z radius)
                     (not (member (object-name object) excluded :test #'string-equal)))
            (let ((depth (depth (physics-static-geom static))))
              (when (> depth *contact-tolerance*) (push (list static depth) hits))))))
      (dolist (collider (scene-physics-colliders physics))
        (dolist (part (and (collider-near-p collider x y z radius) (collider-trunk collider)))
          (when (trunk-near-p part x y z radius)
            (place-trunk-geom part)
            (let ((depth (depth (trunk-part-geom part))))
              (when (> depth *contact-tolerance*) (push (list part depth) hits)))))))
    hits))

(defparameter *hand-span* 0.25d0
  "Metres from a hand joint within which its fingers (or a wing's feathers) lie:
a hand with nothing that near is not tested further.")

(defun hand-near-anything-p (point physics)
  "Is anything of PHYSICS within *HAND-SPAN* of the hand joint at POINT (a vec3)?"
  (declare (type vec3 point))
  (let ((x (vec3-x point)) (y (vec3-y point)) (z (vec3-z point))
        (span (float *hand-span* 1d0)))
    (or (dolist (static (scene-physics-statics physics) nil)
          (when (static-near-p static x y z span)
            (return t)))
        (dolist (collider (scene-physics-colliders physics) nil)
          (dolist (part (and (collider-near-p collider x y z span) (collider-trunk collider)))
            (when (trunk-near-p part x y z span)
              (return-from hand-near-anything-p t)))))))

(defun collider-hits (collider transforms physics excluded)
  "Every (PROBE OBSTACLE DEPTH) of COLLIDER's probes placed by TRANSFORMS.  A
hand's probes come hand joint first; a hand far from everything is skipped."
  (let ((skipped '())
        (point (make-vec3 0d0 0d0 0d0)))
    (loop for probe in (collider-probes collider)
          for hand = (probe-hand probe)
          unless (member hand skipped)
            nconc (with-joint-point ((x y z) transforms (probe-joint probe))
                    (set-vec3 point x y z)
                    (cond ((and (probe-first probe) (not (hand-near-anything-p point physics)))
                           (push hand skipped)
                           '())
                          (t (loop for hit in (probe-hits probe point physics excluded)
                                   collect (cons probe hit))))))))

(defun obstacle-name (obstacle)
  "How a report names OBSTACLE: a prop's name, or BODY's JOINT."
  (etypecase obstacle
    (physics-static (lisp-text (object-name (physics-static-object obstacle))))
    (trunk-part (format nil "~A's ~A" (lisp-text (object-name (trunk-part-body obstacle)))
                        (lisp-text (body-joint-name (trunk-part-joint obstacle)))))))

(defun scene-collisions (scene)
  "What passes through what in SCENE as its bodies are now posed: a list of
\(BODY-NAME HAND-JOINT-NAME OBSTACLE-NAME DEPTH), OBSTACLE-NAME a prop's name
or \"BODY's JOINT\" for a trunk.  NIL when SCENE has no collision shapes."
  (let ((physics (scene-physics scene)))
    (when physics
      (ensure-ode-thread)
      (with-ode-traps-masked
        (place-statics physics)
        (dolist (collider (scene-physics-colliders physics))
          (place-trunk collider (body-transforms (collider-body collider))))
        (loop for collider in (scene-physics-colliders physics)
              for body = (collider-body collider)
              nconc (loop for (probe obstacle depth)
                            in (collider-hits collider (body-transforms body) physics
                                              (body-held-objects-and-targets body scene))
                          collect (list (object-name body) (body-joint-name (probe-joint probe))
                                        (obstacle-name obstacle) depth)))))))

;;;# Stopping at contact

(defun correct-collisions (physics time)
  "Keep the hands of each body of PHYSICS, posed for TIME, out of what they would pass through."
  (let ((scene (scene-physics-scene physics)))
    (dolist (collider (scene-physics-colliders physics))
      (place-trunk collider (body-transforms (collider-body collider))))
    (dolist (collider (scene-physics-colliders physics))
      (let* ((body (collider-body collider))
             (excluded (body-held-objects-and-targets body scene)))
        (when (and (collider-shown collider)
                   (collider-hits collider (body-transforms body) physics excluded))
          (or (stop-at-contact collider physics excluded)
              (push-out collider physics excluded time)))
        (if (collider-shown collider)
            (replace (collider-shown collider) (body-pose body))
            (setf (collider-shown collider) (copy-pose (body-pose body))))
        (setf (collider-shown-time collider) time)))))

(defun show-pose (collider pose)
  "Make POSE (a pose of COLLIDER's body) the one shown: its joints' transforms
follow, and the speed limiter moves on from it."
  (let ((body (collider-body collider)))
    (replace (body-pose body) pose)
    (pose-world-transforms (body-skeleton body) pose :placement (object-world-transform body)
                                                      :result (body-transforms body))
    (note-shown-pose body pose)))

(defun stop-at-contact (collider physics excluded)
  "Move COLLIDER's body from the pose shown before toward its composed pose
only as far as its hands stay out of every obstacle.  True when done; NIL,
changing nothing, when the pose shown before is not clear either (the body
itself was moved into the obstacle, or the obstacle into the hand)."
  (let* ((body (collider-body collider))
         (skeleton (body-skeleton body))
         (placement (object-world-transform body))
         (from (collider-shown collider))
         (target (copy-pose (body-pose body)))
         (trial (copy-pose target))
         (transforms (pose-world-transforms skeleton from :placement placement)))
    (flet ((clear-at (u)
             (dotimes (i (length trial))
               (setf (aref trial i) (+ (aref from i) (* u (- (aref target i) (aref from i))))))
             (pose-world-transforms skeleton trial :placement placement :result transforms)
             (null (collider-hits collider transforms physics excluded))))
      (when (clear-at 0d0)
        (let ((low 0d0) (high 1d0))
          (dotimes (i 10)
            (let ((middle (* 0.5d0 (+ low high))))
              (if (clear-at middle) (setf low middle) (setf high middle))))
          (clear-at low)
          (show-pose collider trial)
          t)))))

;;;# Pushing a hand out

(defparameter *push-steps* '(6d0 -6d0 2d0 -2d0 0.5d0 -0.5d0)
  "The degrees PUSH-OUT tries turning each arm DOF by, largest first.")

(defparameter *push-rounds* 40
  "The most DOF turns PUSH-OUT makes.")

(defun arm-channels (skeleton hands)
  "The pose indices of the DOFs of each of HANDS' (:left, :right) arm chain and hand joint."
  (loop for hand in hands
        for joints = (let ((arm (skeleton-role skeleton (if (eq hand :left) :left-arm :right-arm)))
                           (tip (skeleton-role skeleton (if (eq hand :left) :left-hand :right-hand))))
                       (remove-duplicates (append (if (consp arm) arm (and arm (list arm)))
                                                  (if (consp tip) tip (and tip (list tip))))))
        nconc (loop for joint in joints
                    nconc (loop for dof in (body-joint-dofs joint)
                                for i from (body-joint-dof-start joint)
                                collect i))))

(defun push-out (collider physics excluded time)
  "Turn the arm of each hand that is inside something, DOF by DOF (coordinate
descent on the depth), until the hands are out: IK away from the obstacle
when the body itself moved the hand in.  Each DOF stays within its limits and
within its maximum speed of the pose shown before (TIME is now)."
  (let* ((body (collider-body collider))
         (skeleton (body-skeleton body))
         (placement (object-world-transform body))
         (trial (copy-pose (body-pose body)))
         (transforms (pose-world-transforms skeleton trial :placement placement))
         (hits (collider-hits collider transforms physics excluded))
         (channels (arm-channels skeleton (remove-duplicates (mapcar (lambda (hit) (probe-hand (first hit))) hits))))
         (limits (skeleton-speed-limits skeleton))
         (dt (max 0d0 (- time (or (collider-shown-time collider) time))))
         (shown (collider-shown collider)))
    (labels ((depth ()
               (pose-world-transforms skeleton trial :placement placement :result transforms)
               (loop for hit in (collider-hits collider transforms physics excluded) sum (third hit)))
             (allowed (i angle)
               (multiple-value-bind (low high) (channel-limits skeleton i)
                 (let ((slack (if *speed-limits-enabled* (* dt (aref limits i)) most-positive-double-float)))
                   (max low (- (aref shown i) slack) (min high (+ (aref shown i) slack) angle))))))
      (let ((depth (depth)))
        (loop repeat *push-rounds*
              while (plusp depth)
              do (let ((best nil) (best-depth depth))
                   (dolist (step *push-steps*)
                     (dolist (i channels)
                       (let* ((old (aref trial i))
                              (new (allowed i (+ old step))))
                         (unless (= new old)
                           (setf (aref trial i) new)
                           (let ((d (depth)))
                             (when (< d best-depth) (setf best (cons i new) best-depth d)))
                           (setf (aref trial i) old))))
                     (when best (return)))
                   (if best
                       (setf (aref trial (car best)) (cdr best) depth best-depth)
                       (loop-finish))))
        (show-pose collider trial)
        t))))
