;;;; ik-search.lisp -- the arm solver's numeric half and its entry points:
;;;; damped least squares where the analytic answer (ik.lisp) misses, a coarse
;;;; search for better starts when that stalls, and SOLVE-ARM-CHAIN.

(in-package #:player.body)

;;;# Refinement and search

(defun refine-arm-chain (chain angles before w target)
  "Move ANGLES (in place, within CHAIN's limits) to bring its effector nearer
TARGET by damped least squares (Levenberg-Marquardt): step = J^T (J J^T + mu
I)^-1 r over the free angles, an angle at a limit the error pushes further out
being held; a step that does not help is retried with more damping.  Returns
the distance left."
  (declare #.*anim-optimize* (type angle-vector angles) (type vec3 target))
  (let* ((n (arm-chain-size chain)) (minima (arm-chain-minima chain)) (maxima (arm-chain-maxima chain))
         (s (arm-chain-shoulder-offset chain))
         (out (arm-chain-evaluate chain angles before w (make-evaluation chain)))
         (trial-out (make-evaluation chain))
         (trial (make-array n :element-type 'double-float))
         (columns (make-array (* 3 n) :element-type 'double-float))
         (free (make-array n :element-type 'bit))
         (distance (evaluation-distance out target))
         (damping 1d-2))
    (declare (type double-float distance damping) (type fixnum n) (type angle-vector out trial-out))
    (loop repeat *reach-refinement-iterations*
          while (and (> distance 1d-6) (< damping 1d8))
          do (let ((rx (- (vec3-x target) (aref out 0))) (ry (- (vec3-y target) (aref out 1)))
                   (rz (- (vec3-z target) (aref out 2)))
                   (xx 0d0) (xy 0d0) (xz 0d0) (yy 0d0) (yz 0d0) (zz 0d0) (largest 1d-12))
               (declare (type double-float xx xy xz yy yz zz largest))
               (dotimes (i n)
                 ;; Column i: axis x (effector - centre), per degree; the centre
                 ;; is the shoulder's for its angles, the elbow's for the hinge.
                 (let* ((k (+ 6 (* 3 i))) (hinge (= i (1- n)))
                        (ax (aref out k)) (ay (aref out (+ 1 k))) (az (aref out (+ 2 k)))
                        (px (- (aref out 0) (if hinge (aref out 3) (vec3-x s))))
                        (py (- (aref out 1) (if hinge (aref out 4) (vec3-y s))))
                        (pz (- (aref out 2) (if hinge (aref out 5) (vec3-z s))))
                        (x (* (/ pi 180) (- (* ay pz) (* az py))))
                        (y (* (/ pi 180) (- (* az px) (* ax pz))))
                        (z (* (/ pi 180) (- (* ax py) (* ay px))))
                        (downhill (+ (* x rx) (* y ry) (* z rz)))
                        (held (or (and (>= (aref angles i) (- (aref maxima i) 1d-9)) (> downhill 0))
                                  (and (<= (aref angles i) (+ (aref minima i) 1d-9)) (< downhill 0)))))
                   (setf (aref columns (* 3 i)) x (aref columns (+ 1 (* 3 i))) y (aref columns (+ 2 (* 3 i))) z
                         (sbit free i) (if held 0 1))
                   (unless held
                     (incf xx (* x x)) (incf xy (* x y)) (incf xz (* x z))
                     (incf yy (* y y)) (incf yz (* y z)) (incf zz (* z z)))))
               (when (zerop (count 1 free)) (return))
               ;; Solve (J J^T + mu I) u = r, symmetric positive definite, by its adjugate.
               (let* ((mu (+ 1d-18 (* damping (/ (+ xx yy zz) 3))))
                      (xx (+ xx mu)) (yy (+ yy mu)) (zz (+ zz mu))
                      (c0 (- (* yy zz) (* yz yz))) (c1 (- (* xz yz) (* xy zz))) (c2 (- (* xy yz) (* xz yy)))
                      (c3 (- (* xx zz) (* xz xz))) (c4 (- (* xy xz) (* xx yz))) (c5 (- (* xx yy) (* xy xy)))
                      (det (+ (* xx c0) (* xy c1) (* xz c2)))
                      (ux (/ (+ (* c0 rx) (* c1 ry) (* c2 rz)) det))
                      (uy (/ (+ (* c1 rx) (* c3 ry) (* c4 rz)) det))
                      (uz (/ (+ (* c2 rx) (* c4 ry) (* c5 rz)) det)))
                 (dotimes (i n)
                   (setf (aref trial i) (* (sbit free i)
                                           (+ (* ux (aref columns (* 3 i))) (* uy (aref columns (+ 1 (* 3 i))))
                                              (* uz (aref columns (+ 2 (* 3 i))))))
                         largest (max largest (abs (aref trial i))))))
               ;; No angle moves over 20 degrees a step: the model is linear.
               (let ((scale (min 1d0 (/ 20d0 largest))))
                 (dotimes (i n)
                   (setf (aref trial i) (max (aref minima i) (min (aref maxima i)
                                                                  (+ (aref angles i) (* scale (aref trial i)))))))))
               (let ((new (evaluation-distance (arm-chain-evaluate chain trial before w trial-out) target)))
                 (cond ((< new distance)
                        (let ((gain (- distance new)))
                          (replace angles trial)
                          (rotatef out trial-out)
                          (setf distance new damping (max 1d-9 (* damping 0.3d0)))
                          (when (< gain 1d-8) (return))))
                       (t (setf damping (* damping 5d0))))))
    distance))

(defun search-arm-chain (chain angles before w target distance)
  "Look for better starts than the analytic one, whose refinement left
DISTANCE (a target out of reach or behind a limit can trap a refinement): a
grid through CHAIN's limits, refined from its best few local minima (no nearer
neighbour along any angle, so the starts lie in different basins).  Puts the
best result into ANGLES; returns the distance left."
  (let* ((n (arm-chain-size chain)) (steps *reach-search-steps*) (cells (expt steps n))
         (minima (arm-chain-minima chain)) (maxima (arm-chain-maxima chain))
         (distances (make-array cells :element-type 'double-float))
         (point (make-array n :element-type 'double-float))
         (out (make-evaluation chain))
         (seeds '()))
    (declare #.*anim-optimize* (type fixnum n steps cells) (type angle-vector minima maxima))
    (flet ((grid-angles (cell point)
             (declare (type fixnum cell) (type angle-vector point))
             (dotimes (i n point)
               (multiple-value-bind (rest r) (floor cell steps)
                 (setf cell rest
                       (aref point i) (+ (aref minima i)
                                         (* r (/ (- (aref maxima i) (aref minima i)) (1- steps)))))))))
      (dotimes (cell cells)
        (setf (aref distances cell)
              (evaluation-distance (arm-chain-evaluate chain (grid-angles cell point) before w out) target)))
      (dotimes (cell cells)
        (when (loop for i below n
                    for place of-type fixnum = 1 then (* place steps)
                    for coordinate = (mod (floor cell place) steps)
                    always (and (or (= coordinate 0) (<= (aref distances cell) (aref distances (- cell place))))
                                (or (= coordinate (1- steps))
                                    (<= (aref distances cell) (aref distances (+ cell place))))))
          (push cell seeds)))
      (loop for cell in (sort seeds #'< :key (lambda (cell) (aref distances cell)))
            repeat *reach-search-seeds*
            for seed = (grid-angles cell (make-array n :element-type 'double-float))
            for d = (refine-arm-chain chain seed before w target)
            when (< d distance)
              do (replace angles seed)
                 (setf distance d)))
    distance))

;;;# The solver

(defun solve-arm-chain-local (chain pose target &optional (angles (arm-chain-angles chain pose)))
  "Solve CHAIN for TARGET, a point in its parent frame (ARM-CHAIN-PARENT-TRANSFORM).
POSE gives the starting angles and the held ones (see ARM-CHAIN-HELD).  The
elbow hinge makes |shoulder->effector| = |shoulder->target|, then the shoulder
turns shoulder->effector onto the target (AIM-SHOULDER); a miss over
*REACH-TOLERANCE* is refined, one over *REACH-SEARCH-DISTANCE* searched.  Two
values: ANGLES (an angle vector in ARM-CHAIN-INDICES order, filled from POSE
and solved in place) and the distance (metres) left."
  (loop for i across (arm-chain-indices chain)
        for j from 0
        do (setf (aref angles j) (aref pose i)))
  (multiple-value-bind (before w) (arm-chain-held chain pose)
    (let* ((hinge (1- (arm-chain-size chain)))
           (shoulder (arm-chain-shoulder-offset chain))
           (goal (v- target shoulder))
           (out (make-evaluation chain)))
      (setf (aref angles hinge)
            (solve-hinge (qrotate (qconjugate before) (arm-chain-elbow-offset chain)) w
                         (dof-axis-vec3 (nth (arm-chain-hinge chain) (body-joint-dofs (arm-chain-elbow chain))))
                         (aref angles hinge) (aref (arm-chain-minima chain) hinge)
                         (aref (arm-chain-maxima chain) hinge) (vnorm goal)))
      (arm-chain-evaluate chain angles before w out)
      (aim-shoulder chain angles (v- (make-vec3 (aref out 0) (aref out 1) (aref out 2)) shoulder) goal)
      (let ((distance (evaluation-distance (arm-chain-evaluate chain angles before w out) target)))
        (when (> distance *reach-tolerance*)
          (setf distance (refine-arm-chain chain angles before w target)))
        (when (> distance *reach-search-distance*)
          (setf distance (search-arm-chain chain angles before w target distance)))
        (values angles distance)))))

(defun solve-arm-chain (chain pose target &key (placement (identity-transform)))
  "A copy of POSE with CHAIN's shoulder and elbow turned so that its effector
reaches the world point TARGET (a vec3), the body placed by PLACEMENT, or comes
as near as reach and limits allow; POSE's angles are the starting point.  Two
values: the new pose and the distance (metres) left."
  (let ((local (transform-point (transform-invert (arm-chain-parent-transform chain pose placement))
                                target))
        (result (copy-pose pose)))
    (multiple-value-bind (angles distance) (solve-arm-chain-local chain pose local)
      (loop for i across (arm-chain-indices chain)
            for angle across angles
            do (setf (aref result i) angle))
      (values result distance))))
