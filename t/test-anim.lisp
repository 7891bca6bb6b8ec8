;;;; test-anim.lisp -- the animation math (vectors, quaternions, transforms) and
;;;; controls, checked against closed forms, identities and finite differences.

(in-package #:player-tests)

(def-suite* anim :in player-tests)

;;;# Helpers

(defun close-p (a b &optional (tolerance 1d-9))
  "True when the reals A and B differ by at most TOLERANCE."
  (<= (abs (- a b)) tolerance))

(defun vec-close-p (a b &optional (tolerance 1d-9))
  "True when vectors A and B are within TOLERANCE of each other, component by component."
  (and (close-p (player.body::vec3-x a) (player.body::vec3-x b) tolerance)
       (close-p (player.body::vec3-y a) (player.body::vec3-y b) tolerance)
       (close-p (player.body::vec3-z a) (player.body::vec3-z b) tolerance)))

(defun same-rotation-p (a b &optional (tolerance 1d-9))
  "True when unit quaternions A and B are the same rotation (Q and -Q are) within TOLERANCE."
  (close-p (abs (player.body::qdot a b)) 1d0 tolerance))

(defun random-vec (state &optional (scale 10d0))
  "A vector with coordinates uniform in [-SCALE, SCALE), drawn from random STATE."
  (player::vec3 (- (random (* 2 scale) state) scale)
                (- (random (* 2 scale) state) scale)
                (- (random (* 2 scale) state) scale)))

(defun random-rotation (state)
  "A random unit quaternion drawn from random STATE."
  (player.body::quat-from-axis-angle (random-vec state 1d0) (random (* 2 pi) state)))

(defun about-z (angle)
  "The rotation by ANGLE radians about Z."
  (player.body::quat-from-axis-angle (player::vec3 0d0 0d0 1d0) angle))

(defun keys (interpolation &rest times-and-values)
  "A keys control with INTERPOLATION from alternating TIMES-AND-VALUES."
  (player::make-keys-control (loop for (time value) on times-and-values by #'cddr
                                   collect (cons time value))
                             :interpolation interpolation))

(defmacro signals-control-error ((&rest fragments) &body body)
  "Check that BODY signals an ANIM-CONTROL-ERROR, a PLAYER-ERROR, whose report contains every string of FRAGMENTS."
  (let ((condition (gensym "CONDITION")))
    `(let ((,condition (handler-case (progn ,@body nil)
                         (player-error (c) c))))
       (is (typep ,condition 'player::anim-control-error)
           "~S signalled ~S, not an anim-control-error" ',body ,condition)
       (when ,condition
         (let ((report (princ-to-string ,condition)))
           (dolist (fragment (list ,@fragments))
             (is (search fragment report) "report ~S does not mention ~S" report fragment)))))))

;;;# Vectors

(test vector-arithmetic
  (let ((a (player::vec3 1d0 2d0 3d0))
        (b (player::vec3 -4d0 0.5d0 2d0)))
    (is (vec-close-p (player::vec3 -3d0 2.5d0 5d0) (player.body::v+ a b)))
    (is (vec-close-p (player::vec3 5d0 1.5d0 1d0) (player.body::v- a b)))
    (is (vec-close-p (player::vec3 2d0 4d0 6d0) (player.body::v* a 2d0)))
    (is (close-p 3d0 (player.body::vdot a b)))
    (is (close-p (sqrt 14d0) (player.body::vnorm a)))
    (is (close-p 1d0 (player.body::vnorm (player.body::vnormalize b))))
    (is (vec-close-p (player::vec3 0d0 0d0 1d0)
                     (player.body::vcross (player::vec3 1d0 0d0 0d0) (player::vec3 0d0 1d0 0d0))))
    (let ((c (player.body::vcross a b)))
      (is (close-p 0d0 (player.body::vdot c a)))
      (is (close-p 0d0 (player.body::vdot c b))))
    (is (vec-close-p (player::vec3 1d0 2d0 3d0) a) "V+ and friends leave their arguments alone")
    (let ((c (player.body::copy-vec3 a)))
      (is (eq c (player.body::nv+ c b)))
      (is (vec-close-p (player.body::v+ a b) c)))
    (is (vec-close-p (player::vec3) (player.body::vnormalize (player::vec3))) "a zero vector stays zero")))

(test in-place-variants-do-not-cons
  (let* ((state (sb-ext:seed-random-state 11))
         (v (random-vec state))
         (w (random-vec state))
         (q (random-rotation state))
         (a (player.body::make-transform :rotation q :translation w))
         (b (player.body::make-transform :rotation (random-rotation state) :translation v))
         (result (player.body::identity-transform))
         (before (sb-ext:get-bytes-consed)))
    (dotimes (i 10000)
      (player.body::nv+ v w)
      (player.body::nv- v w)
      (player.body::nvnormalize v)
      (player.body::nqrotate q v)
      (player.body::nq* q q)
      (player.body::nqnormalize q)
      (player.body::ntransform-point a v)
      (player.body::transform-compose a b result)
      (player.body::transform-invert result result))
    (is (< (- (sb-ext:get-bytes-consed) before) 65536)
        "10000 rounds of in-place operations consed ~D bytes"
        (- (sb-ext:get-bytes-consed) before))))

;;;# Quaternions

(test quaternion-identities
  (let ((state (sb-ext:seed-random-state 42)))
    (dotimes (i 200)
      (let* ((q (random-rotation state))
             (r (random-rotation state))
             (v (random-vec state))
             (identity (player::quat)))
        (is (same-rotation-p identity (player.body::q* q (player.body::qconjugate q))))
        (is (same-rotation-p identity (player.body::q* (player.body::qinverse q) q)))
        (is (close-p (player.body::vnorm v) (player.body::vnorm (player.body::qrotate q v)) 1d-9)
            "rotation preserves length")
        (is (vec-close-p (player.body::qrotate q v) (player.body::mat3-apply (player.body::quat-to-matrix q) v) 1d-9)
            "matrix and quaternion rotation agree")
        (is (vec-close-p (player.body::qrotate (player.body::q* q r) v)
                         (player.body::qrotate q (player.body::qrotate r v)) 1d-9)
            "(q r) v = q (r v)")
        (is (same-rotation-p q (player.body::matrix-to-quat (player.body::quat-to-matrix q))))
        (is (same-rotation-p q (player.body::qexp (player.body::qlog q))))
        (multiple-value-bind (axis angle) (player.body::quat-to-axis-angle q)
          (is (same-rotation-p q (player.body::quat-from-axis-angle axis angle))))
        (is (close-p 1d0 (player.body::qnorm (player.body::qnormalize (player.body::make-quat 1 2 3 4)))))))))

(test quaternion-from-axis-angle-and-euler
  (let ((x (player::vec3 1d0 0d0 0d0)) (y (player::vec3 0d0 1d0 0d0)) (z (player::vec3 0d0 0d0 1d0)))
    (is (vec-close-p y (player.body::qrotate (about-z (/ pi 2)) x)) "right-handed: Z turns X into Y")
    (is (vec-close-p z (player.body::qrotate (player.body::quat-from-axis-angle x (/ pi 2)) y)))
    (is (close-p 0.7d0 (player.body::quat-angle (player::quat) (about-z 0.7d0))))
    (is (close-p 0.7d0 (player.body::quat-angle (about-z 0.2d0) (about-z -0.5d0))))
    (is (close-p 1d0 (player.body::quat-angle (about-z 0d0) (player.body::qnegate (about-z 1d0))))
        "Q and -Q are the same rotation")
    (loop for (ax ay az) in '((0.3d0 -1.1d0 2.0d0) (1.5d0 0.2d0 -0.4d0) (0d0 0d0 1d0))
          do (is (same-rotation-p
                  (player.body::q* (player.body::quat-from-axis-angle z az)
                              (player.body::q* (player.body::quat-from-axis-angle y ay)
                                          (player.body::quat-from-axis-angle x ax)))
                  (player.body::quat-from-euler ax ay az))
                 "Euler angles apply X, then Y, then Z"))))

(test slerp-against-closed-forms
  (loop for (a b) in '((0d0 1d0) (0.3d0 2.9d0) (-1d0 0.5d0) (0d0 1d-9))
        do (let ((qa (about-z a)) (qb (about-z b)))
             (is (same-rotation-p qa (player::qslerp qa qb 0d0)))
             (is (same-rotation-p qb (player::qslerp qa qb 1d0)))
             (dolist (u '(0.1d0 0.25d0 0.5d0 0.9d0))
               (let ((q (player::qslerp qa qb u)))
                 (is (close-p 1d0 (player.body::qnorm q) 1d-12))
                 (is (same-rotation-p (about-z (+ a (* u (- b a)))) q 1d-12)
                     "slerp about Z from ~A to ~A at ~A is the rotation by the interpolated angle" a b u)))))
  ;; Shortest path: -B is B, and from 0 to 350 degrees is 10 degrees backwards.
  (let ((qa (about-z 0d0)) (qb (about-z (* 350 (/ pi 180)))))
    (is (same-rotation-p (player::qslerp qa qb 0.5d0) (player::qslerp qa (player.body::qnegate qb) 0.5d0)))
    (is (same-rotation-p (about-z (* -5 (/ pi 180))) (player::qslerp qa qb 0.5d0))))
  ;; Constant angular speed between random rotations.
  (let ((state (sb-ext:seed-random-state 5)))
    (dotimes (i 50)
      (let* ((qa (random-rotation state)) (qb (random-rotation state))
             (angle (player.body::quat-angle qa qb)))
        (dolist (u '(0.2d0 0.5d0 0.8d0))
          (is (close-p (* u angle) (player.body::quat-angle qa (player::qslerp qa qb u)) 1d-9)))))))

(test squad-endpoints-and-single-axis
  (let ((state (sb-ext:seed-random-state 8)))
    (dotimes (i 50)
      (let* ((q0 (random-rotation state)) (q1 (random-rotation state))
             (q2 (random-rotation state)) (q3 (random-rotation state))
             (s1 (player.body::squad-control-point q0 q1 q2))
             (s2 (player.body::squad-control-point q1 q2 q3)))
        (is (same-rotation-p q1 (player::qsquad q1 q2 s1 s2 0d0)))
        (is (same-rotation-p q2 (player::qsquad q1 q2 s1 s2 1d0)))
        (is (close-p 1d0 (player.body::qnorm (player::qsquad q1 q2 s1 s2 0.37d0)) 1d-12)))))
  ;; Evenly spaced keys about one axis: the curve is the rotation by the interpolated angle.
  (let* ((qs (mapcar #'about-z '(0d0 0.5d0 1d0 1.5d0)))
         (s1 (apply #'player.body::squad-control-point (subseq qs 0 3)))
         (s2 (apply #'player.body::squad-control-point (subseq qs 1 4))))
    (dolist (u '(0.25d0 0.5d0 0.75d0))
      (is (same-rotation-p (about-z (+ 0.5d0 (* 0.5d0 u)))
                           (player::qsquad (second qs) (third qs) s1 s2 u) 1d-12)))))

;;;# Transforms

(test rigid-transforms
  (let ((state (sb-ext:seed-random-state 3)))
    (dotimes (i 50)
      (let* ((qa (random-rotation state)) (ta (random-vec state))
             (qb (random-rotation state)) (tb (random-vec state))
             (a (player.body::make-transform :rotation qa :translation ta))
             (b (player.body::make-transform :rotation qb :translation tb))
             (p (random-vec state))
             (ab (player.body::transform-compose a b)))
        (is (vec-close-p (player.body::v+ (player.body::qrotate qa p) ta) (player.body::transform-point a p) 1d-9))
        (is (vec-close-p (player.body::qrotate qa p) (player.body::transform-vector a p) 1d-9))
        (is (vec-close-p (player.body::transform-point a (player.body::transform-point b p))
                         (player.body::transform-point ab p) 1d-9)
            "A B applies B, then A")
        (is (vec-close-p p (player.body::transform-point (player.body::transform-invert a)
                                                    (player.body::transform-point a p)) 1d-9))
        (is (same-rotation-p (player.body::q* qa qb) (player.body::transform-rotation ab)))
        (is (vec-close-p (player.body::v+ (player.body::qrotate qa tb) ta) (player.body::transform-translation ab) 1d-9))
        ;; Results may alias the arguments.
        (let ((a2 (player.body::transform-compose a b (player.body::transform-compose a (player.body::identity-transform)))))
          (is (equalp ab a2)))
        (let ((b2 (player.body::transform-compose a (player.body::identity-transform))))
          (player.body::transform-compose a b b2)
          (is (equalp ab b2)))
        (let ((inverse (player.body::transform-invert a)) (in-place (player.body::transform-compose a (player.body::identity-transform))))
          (player.body::transform-invert in-place in-place)
          (is (equalp inverse in-place)))))))

(test world-transforms-of-a-chain
  (let* ((step (player.body::make-transform :rotation (about-z (/ pi 2))
                                       :translation (player::vec3 1d0 0d0 0d0)))
         (locals (vector (player.body::identity-transform) step step step))
         (worlds (player::world-transforms #(nil 0 1 2) locals)))
    ;; Each joint is one unit along its parent's X, turned a quarter about Z.
    (is (vec-close-p (player::vec3 0d0 0d0 0d0) (player.body::transform-translation (aref worlds 0))))
    (is (vec-close-p (player::vec3 1d0 0d0 0d0) (player.body::transform-translation (aref worlds 1))))
    (is (vec-close-p (player::vec3 1d0 1d0 0d0) (player.body::transform-translation (aref worlds 2))))
    (is (vec-close-p (player::vec3 0d0 1d0 0d0) (player.body::transform-translation (aref worlds 3))))
    (is (eq worlds (player::world-transforms #(-1 0 1 2) locals worlds)) "WORLDS is reused")
    (signals player-error (player::world-transforms #(nil 2 0) (vector step step step)))))

;;;# Keyframe controls

(test linear-keys-are-exact-at-midpoints-and-hold-at-the-ends
  (let ((control (keys :linear 0 1d0 2 5d0 3 -1d0)))
    (is (= 3d0 (player::control-value control 1)))
    (is (= 2d0 (player::control-value control 2.5d0)))
    (is (= 4d0 (player::control-value control 1.5d0)))
    (is (= 5d0 (player::control-value control 2)))
    (is (= 1d0 (player::control-value control -10)))
    (is (= -1d0 (player::control-value control 3)))
    (is (= -1d0 (player::control-value control 100))))
  (let ((control (keys :linear 0 (player::vec3 0d0 0d0 0d0) 4 (player::vec3 4d0 -8d0 2d0))))
    (is (vec-close-p (player::vec3 1d0 -2d0 0.5d0) (player::control-value control 1)))))

(test step-keys-hold
  (let ((control (keys :step 0 1 1 2 3 7)))
    (is (= 1d0 (player::control-value control 0.99d0)))
    (is (= 2d0 (player::control-value control 1)))
    (is (= 2d0 (player::control-value control 2.999d0)))
    (is (= 7d0 (player::control-value control 3)))
    (is (= 1d0 (player::control-value control -1)))))

(test ease-in-out-symmetry-and-flat-ends
  (let ((control (keys :ease-in-out 0 2d0 2 6d0 3 0d0))
        (h 1d-6))
    (is (close-p 4d0 (player::control-value control 1)) "halfway is halfway")
    (dolist (d '(0.1d0 0.3d0 0.77d0))
      (is (close-p 8d0 (+ (player::control-value control d) (player::control-value control (- 2 d))) 1d-12)
          "symmetric about the middle of the segment"))
    (dolist (key '(0d0 2d0 3d0))
      (is (< (abs (/ (- (player::control-value control (+ key h)) (player::control-value control key)) h)) 1d-4)
          "zero slope just after the key at ~A" key)
      (is (< (abs (/ (- (player::control-value control key) (player::control-value control (- key h))) h)) 1d-4)
          "zero slope just before the key at ~A" key))))

(test catmull-rom-passes-through-keys-and-matches-the-cubic
  (let* ((points '(1d0 4d0 2d0 -3d0 0.5d0))
         (control (apply #'keys :catmull-rom (loop for p in points for i from 0 collect i collect p))))
    (loop for p in points for i from 0
          do (is (close-p p (player::control-value control i) 1d-12)))
    ;; Segment 1 to 2 at u = 0.3: the uniform Catmull-Rom cubic of keys 0..3.
    (destructuring-bind (p0 p1 p2 p3) (subseq points 0 4)
      (let ((u 0.3d0))
        (is (close-p (* 0.5d0 (+ (* 2 p1) (* (- p2 p0) u)
                                 (* (+ (* 2 p0) (* -5 p1) (* 4 p2) (- p3)) u u)
                                 (* (+ (- p0) (* 3 p1) (* -3 p2) p3) u u u)))
                     (player::control-value control 1.3d0) 1d-12))))
    ;; C1: the slope just before a key equals the slope just after it.
    (let ((h 1d-6))
      (dolist (key '(1 2 3))
        (is (close-p (/ (- (player::control-value control key) (player::control-value control (- key h))) h)
                     (/ (- (player::control-value control (+ key h)) (player::control-value control key)) h)
                     1d-4)))))
  (let ((control (keys :catmull-rom 0 (player::vec3 0d0 0d0 0d0) 1 (player::vec3 1d0 2d0 3d0)
                       2 (player::vec3 2d0 0d0 1d0) 3 (player::vec3 3d0 2d0 0d0))))
    (is (vec-close-p (player::vec3 1d0 2d0 3d0) (player::control-value control 1) 1d-12))
    ;; Closed form per component: x is linear, so Catmull-Rom reproduces it.
    (is (close-p 1.6d0 (player.body::vec3-x (player::control-value control 1.6d0)) 1d-12))))

(test rotation-keys-slerp-and-squad
  (let ((linear (keys :linear 0 (about-z 0d0) 2 (about-z 1d0)))
        (eased (keys :ease-in-out 0 (about-z 0d0) 2 (about-z 1d0))))
    (is (same-rotation-p (about-z 0.25d0) (player::control-value linear 0.5d0) 1d-12))
    (is (same-rotation-p (about-z 0.5d0) (player::control-value eased 1d0) 1d-12))
    (is (same-rotation-p (about-z (* 3 0.25d0 0.25d0 (- 1 (* 2/3 0.25d0))))
                         (player::control-value eased 0.5d0) 1d-12)
        "ease-in-out is slerp at smoothstep(u)"))
  (let* ((state (sb-ext:seed-random-state 21))
         (rotations (loop repeat 5 collect (random-rotation state)))
         (control (player::make-keys-control (loop for q in rotations for i from 0 collect (cons i q))
                                             :interpolation :catmull-rom))
         (h 1d-5))
    (loop for q in rotations for i from 0
          do (is (same-rotation-p q (player::control-value control i) 1d-12) "squad passes through key ~D" i))
    (dolist (key '(1 2 3))
      (let ((before (player::control-value control (- key h)))
            (at (player::control-value control key))
            (after (player::control-value control (+ key h))))
        (is (< (player.body::quat-angle before at) 1d-3) "continuous at key ~D" key)
        (is (close-p (player.body::quat-angle before at) (player.body::quat-angle at after) (* 1d-2 h))
            "the angular speed is continuous at key ~D" key)
        ;; The turning axis is continuous too: compare the two small rotations.
        (is (same-rotation-p (player.body::q* at (player.body::qconjugate before))
                             (player.body::q* after (player.body::qconjugate at)) 1d-9))))))

(test looping-keys-repeat
  (let ((control (player::make-keys-control '((1 . 0) (2 . 10) (3 . 0)) :interpolation :catmull-rom :loop t)))
    (dolist (time '(1.2d0 1.5d0 2.7d0))
      (is (close-p (player::control-value control time) (player::control-value control (+ time 2)) 1d-9))
      (is (close-p (player::control-value control time) (player::control-value control (- time 6)) 1d-9)))
    (is (close-p 0d0 (player::control-value control 5)))))

;;;# Noise

(test perlin-noise-is-continuous-and-bounded
  (let* ((amplitude 0.75d0) (frequency 3d0)
         (control (player.body::make-noise-control :seed 1234 :amplitude amplitude :frequency frequency))
         (vector-control (player.body::make-noise-control :seed 99 :amplitude 2 :frequency 0.5 :kind :vec3))
         (state (sb-ext:seed-random-state 77))
         (dt 1d-5)
         (largest 0d0))
    (dotimes (i 5000)
      (let* ((time (- (random 200d0 state) 100d0))
             (value (player::control-value control time))
             (next (player::control-value control (+ time dt))))
        (setf largest (max largest (abs value)))
        (unless (<= (abs value) amplitude)
          (fail "|noise| = ~A exceeds the amplitude ~A at ~A" (abs value) amplitude time))
        ;; |d noise / dt| <= 2 amplitude frequency (1 + 15/8): gradients in [-1, 1], fade slope <= 15/8.
        (unless (<= (abs (- next value)) (* 6 amplitude frequency dt))
          (fail "noise jumps by ~A over ~A s at ~A" (abs (- next value)) dt time))
        (let ((v (player::control-value vector-control time)))
          (unless (every (lambda (c) (<= (abs c) 2d0))
                         (list (player.body::vec3-x v) (player.body::vec3-y v) (player.body::vec3-z v)))
            (fail "vector noise ~A exceeds its amplitude" v)))))
    (is (> largest (* 0.3d0 amplitude)) "the noise moves (largest value ~A)" largest)
    (pass)))

(test controls-are-deterministic
  (let ((a (player.body::make-noise-control :seed 7 :amplitude 2 :frequency 1.5 :kind :quat))
        (b (player.body::make-noise-control :seed 7 :amplitude 2 :frequency 1.5 :kind :quat))
        (c (player.body::make-noise-control :seed 8 :amplitude 2 :frequency 1.5 :kind :quat))
        (times (loop for i below 100 collect (* i 0.37d0))))
    (is (equalp (mapcar (lambda (time) (player::control-value a time)) times)
                (mapcar (lambda (time) (player::control-value b time)) (reverse (reverse times)))))
    (is (equalp (mapcar (lambda (time) (player::control-value a time)) times)
                (reverse (mapcar (lambda (time) (player::control-value a time)) (reverse times))))
        "the order of evaluation does not matter")
    (is (not (equalp (mapcar (lambda (time) (player::control-value a time)) times)
                     (mapcar (lambda (time) (player::control-value c time)) times)))
        "another seed gives other noise"))
  ;; Modifying a returned value does not change the control.
  (let ((control (keys :linear 0 (player::vec3 1d0 1d0 1d0) 1 (player::vec3 2d0 2d0 2d0))))
    (player.body::nv* (player::control-value control -1) 100d0)
    (is (vec-close-p (player::vec3 1d0 1d0 1d0) (player::control-value control -1)))))

;;;# Sums and products

(test sums-and-products
  (let* ((offset (player.body::make-constant-control (player::vec3 1d0 2d0 3d0)))
         (path (keys :linear 0 (player::vec3 0d0 0d0 0d0) 2 (player::vec3 2d0 0d0 0d0)))
         (sum (player.body::make-sum-control offset path)))
    (is (eq :vec3 (player.body::control-kind sum)))
    (is (vec-close-p (player::vec3 2d0 2d0 3d0) (player::control-value sum 1))))
  (is (= 7d0 (player::control-value (player.body::make-sum-control (player.body::make-constant-control 3)
                                                             (player.body::make-constant-control 4))
                                   0)))
  (is (= 12d0 (player::control-value (player::parse-control '(:product 3 (:keys ((0 . 0) (1 . 8))))) 0.5d0)))
  (is (vec-close-p (player::vec3 1d0 2d0 3d0)
                   (player::control-value (player::parse-control '(:product 2 (:vec3 1 2 3) 0.5)) 0)))
  (let ((turn (player::parse-control '(:product (:axis-angle (0 0 1) 0.5) (:keys ((0 :axis-angle (0 0 1) 0) (1 :axis-angle (0 0 1) 1)))))))
    (is (eq :quat (player.body::control-kind turn)))
    (is (same-rotation-p (about-z 1d0) (player::control-value turn 0.5d0) 1d-12) "rotations compose"))
  (let ((idle (player::parse-control '(:sum (:keys ((0 . 1) (1 . 2))) (:noise :seed 3 :amplitude 0.1)))))
    (is (<= 0.9d0 (player::control-value idle 0.3d0) 2.1d0))))

(test parse-control-forms
  (is (= 2.5d0 (player::control-value (player::parse-control 2.5) 10)))
  (is (= 2.5d0 (player::control-value (player::parse-control '(:constant 2.5)) 10)))
  (is (same-rotation-p (player.body::quat-from-euler 0.1d0 0.2d0 0.3d0)
                       (player::control-value (player::parse-control '(:euler 0.1 0.2 0.3)) 0)))
  (is (same-rotation-p (player.body::qnormalize (player.body::make-quat 1 1 0 0))
                       (player::control-value (player::parse-control '(:quat 1 1 0 0)) 0)))
  (let ((control (player::parse-control '(:keys ((0 . 0) (1 . 1)) :interpolation :step :loop t))))
    (is (= 0d0 (player::control-value control 1.5d0)))))

;;;# Errors

(test bad-controls-signal-control-errors
  (signals-control-error ("at least one key") (player::make-keys-control '()))
  (signals-control-error ("not sorted" "(0 . 1)") (player::make-keys-control '((1 . 0) (0 . 1))))
  (signals-control-error ("not sorted") (player::make-keys-control '((0 . 0) (1 . 1) (1 . 2))))
  (signals-control-error ("unknown interpolation" ":cubic")
    (player::make-keys-control '((0 . 1)) :interpolation :cubic))
  (signals-control-error ("vec3" "number")
    (player::make-keys-control (list '(0 . 1) (cons 1 (player::vec3 1d0 2d0 3d0)))))
  (signals-control-error ("(time . value)") (player::make-keys-control '((0 . 1) oops)))
  (signals-control-error ("must be a number" "\"a\"") (player.body::make-constant-control "a"))
  (signals-control-error ("nonzero") (player.body::make-constant-control (player.body::make-quat 0 0 0 0)))
  (signals-control-error ("do not add") (player::parse-control '(:sum (:euler 0 0 1) (:euler 0 1 0))))
  (signals-control-error ("cannot add") (player::parse-control '(:sum 1 (:vec3 1 2 3))))
  (signals-control-error ("product") (player::parse-control '(:product (:vec3 1 2 3) (:vec3 1 2 3))))
  (signals-control-error ("at least one control" "(:sum)") (player::parse-control '(:sum)))
  (signals-control-error ("not one") (player.body::make-sum-control 3))
  (signals-control-error ("amplitude" "-1") (player.body::make-noise-control :amplitude -1))
  (signals-control-error ("frequency") (player.body::make-noise-control :frequency 0))
  (signals-control-error ("seed") (player.body::make-noise-control :seed 1.5))
  (signals-control-error ("unknown noise kind") (player.body::make-noise-control :kind :color))
  (signals-control-error ("vec3 takes 3" "(:vec3 1 2)") (player::parse-control '(:vec3 1 2)))
  (signals-control-error ("unknown option" ":bogus") (player::parse-control '(:keys ((0 . 1)) :bogus 3)))
  (signals-control-error ("time" "\"x\"") (player::control-value (player.body::make-constant-control 1) "x")))
