;;;; test-bvh.lisp -- the BVH writer, checked by reading its output back with
;;;; READ-BVH, a small independent reader written here, and QUAT-TO-EULER,
;;;; checked by recomposing its angles.

(in-package #:player-tests)

(def-suite* bvh :in player-tests)

;;; ---------------------------------------------------------------------------
;;; An independent BVH reader: tokens, a recursive HIERARCHY parser, MOTION.

(defstruct (bvh-node (:conc-name bvh-node-))
  "A joint as read from a BVH file."
  name parent offset channels end-site (first-channel 0))

(defun bvh-tokens (text)
  "TEXT split at whitespace, as a list of strings."
  (loop with start = nil
        for i from 0 to (length text)
        for char = (if (< i (length text)) (char text i) #\Space)
        for space-p = (member char '(#\Space #\Tab #\Newline #\Return))
        if (and space-p start) collect (subseq text start i) and do (setf start nil)
        else if (and (not space-p) (not start)) do (setf start i)))

(defun bvh-number (token)
  "The real TOKEN spells, [-]DIGITS[.DIGITS], as a double; an error for anything else."
  (let ((digits (string-left-trim "-" token)))
    (assert (and (plusp (length digits)) (<= (count #\. digits) 1)
                 (every (lambda (c) (or (digit-char-p c) (char= c #\.))) digits)
                 (<= (- (length token) (length digits)) 1))
            () "~S is not a plain decimal number" token)
    (let* ((point (or (position #\. digits) (length digits)))
           (whole (parse-integer digits :end point))
           (fraction (subseq digits (min (length digits) (1+ point))))
           (value (+ whole (if (string= fraction "") 0
                               (/ (parse-integer fraction) (expt 10 (length fraction)))))))
      (float (if (char= (char token 0) #\-) (- value) value) 1d0))))

(defun read-bvh (text)
  "Parse the BVH TEXT into a plist (:nodes NODES :frame-time SECONDS :frames
FRAMES): NODES in file order, FRAMES a list of vectors of channel values."
  (let ((tokens (bvh-tokens text))
        (nodes '())
        (channel-count 0))
    (labels ((next () (or (pop tokens) (error "the BVH text ends early")))
             (expect (word)
               (let ((token (next)))
                 (assert (string= token word) () "expected ~A, read ~A" word token)))
             (triple () (list (bvh-number (next)) (bvh-number (next)) (bvh-number (next))))
             (node (name parent)
               (expect "{")
               (expect "OFFSET")
               (let ((node (make-bvh-node :name name :parent parent :offset (triple)
                                          :first-channel channel-count)))
                 (expect "CHANNELS")
                 (setf (bvh-node-channels node)
                       (loop repeat (parse-integer (next)) collect (next)))
                 (incf channel-count (length (bvh-node-channels node)))
                 (push node nodes)
                 (loop for token = (next)
                       until (string= token "}")
                       do (cond ((string= token "JOINT") (node (next) name))
                                ((string= token "End")
                                 (expect "Site") (expect "{") (expect "OFFSET")
                                 (setf (bvh-node-end-site node) (triple))
                                 (expect "}"))
                                (t (error "unexpected ~A in joint ~A" token name)))))))
      (expect "HIERARCHY")
      (expect "ROOT")
      (node (next) nil)
      (expect "MOTION")
      (expect "Frames:")
      (let ((count (parse-integer (next))))
        (expect "Frame") (expect "Time:")
        (let ((frame-time (bvh-number (next)))
              (frames (loop repeat count
                            collect (coerce (loop repeat channel-count
                                                  collect (bvh-number (next)))
                                            'vector))))
          (assert (null tokens) () "~D tokens after the last frame" (length tokens))
          (list :nodes (nreverse nodes) :frame-time frame-time :frames frames))))))

(defun bvh-vec3 (list)
  "The vec3 of the three reals in LIST."
  (destructuring-bind (x y z) list
    (player::vec3 (float x 1d0) (float y 1d0) (float z 1d0))))

(defun bvh-channel-rotation (names values)
  "The quaternion R(ch1) R(ch2) ... of the rotation channels NAMES with VALUES (degrees)."
  (let ((q (player::quat)))
    (loop for name in names
          for value in values
          for axis = (cdr (assoc name '(("Xrotation" 1 0 0) ("Yrotation" 0 1 0) ("Zrotation" 0 0 1))
                                 :test #'string=))
          when axis
            do (setf q (player.body::q* q (player.body::quat-from-axis-angle
                                      (bvh-vec3 axis) (* value (/ pi 180))))))
    q))

;;; ---------------------------------------------------------------------------
;;; Random data

(defun bvh-random-quat (state)
  "A random unit quaternion drawn from STATE (normalized from the cube, rejecting short ones)."
  (loop for q = (player.body::make-quat (- (random 2d0 state) 1) (- (random 2d0 state) 1)
                                   (- (random 2d0 state) 1) (- (random 2d0 state) 1))
        when (< 0.1d0 (player.body::qnorm q) 1d0) return (player.body::qnormalize q)))

(defun bvh-random-pose (skeleton state)
  "A pose of SKELETON with every angle uniform within its limits."
  (let ((pose (player::make-pose skeleton)))
    (loop for joint across (player::skeleton-joints skeleton)
          do (loop for dof in (player.body::body-joint-dofs joint)
                   for i from (player.body::body-joint-dof-start joint)
                   for low = (float (player.body::body-dof-min dof) 1d0)
                   for high = (float (player.body::body-dof-max dof) 1d0)
                   do (setf (aref pose i) (+ low (random (max 1d-9 (- high low)) state)))))
    pose))

(defun bvh-random-placement (state)
  "A random rigid MAT4: any rotation, a translation within 5 m."
  (player.body::make-transform :rotation (bvh-random-quat state)
                          :translation (player::vec3 (- (random 10d0 state) 5)
                                                     (random 2d0 state)
                                                     (- (random 10d0 state) 5))))

(defun bvh-degrees-between (a b)
  "The angle between the rotations of unit quaternions A and B, in degrees."
  (* (player.body::quat-angle a b) (/ 180 pi)))

;;; ---------------------------------------------------------------------------
;;; The writer, read back

(defun bvh-round-trip (skeleton-name seed &key (frames 12))
  "Write FRAMES random poses and placements of the skeleton SKELETON-NAME as BVH,
read the text back and check it against what was written."
  (let* ((state (sb-ext:seed-random-state seed))
         (skeleton (player::load-skeleton skeleton-name))
         (joints (player::skeleton-joints skeleton))
         (root (player.body::skeleton-root skeleton))
         (poses (loop repeat frames collect (bvh-random-pose skeleton state)))
         (placements (loop repeat frames collect (bvh-random-placement state))))
    ;; One frame at gimbal lock: the root's second DOF axis turned a right angle.
    (setf (first poses) (player::make-pose skeleton)
          (first placements)
          (player.body::make-transform
           :rotation (player.body::quat-from-axis-angle
                      (bvh-vec3 (player.body::dof-axis-vector (second (player.body::body-joint-dofs root))))
                      (/ pi 2))))
    (let* ((text (with-output-to-string (out)
                   (player::write-bvh out skeleton poses :placements placements
                                                          :frame-time 0.04d0)))
           (bvh (read-bvh text))
           (nodes (getf bvh :nodes)))
      (is (notany (lambda (token) (and (char= (char token 0) #\-)
                                       (every (lambda (c) (find c "-0.")) token)))
                  (bvh-tokens text))
          "a negative zero is written")
      (is (= (length joints) (length nodes)))
      (is (= 0.04d0 (getf bvh :frame-time)))
      (is (= frames (length (getf bvh :frames))))
      (check-bvh-hierarchy joints nodes)
      (loop for frame in (getf bvh :frames)
            for pose in poses
            for placement in placements
            for number from 0
            do (multiple-value-bind (turn turn-joint shift shift-joint)
                   (check-bvh-frame skeleton nodes frame pose placement)
                 (is (< turn 1d-4) "frame ~D: joint ~A turns ~,7F degrees off"
                     number turn-joint turn)
                 (is (< shift 1d-5) "frame ~D: joint ~A is ~,7F m out of place"
                     number shift-joint shift))))))

(defun check-bvh-hierarchy (joints nodes)
  "Check the BVH NODES against the skeleton's JOINTS: names, parents, offsets, channels, ends."
  (flet ((file-name (joint) (string-downcase (string (player.body::body-joint-name joint)))))
    (loop for joint across joints
          for node in nodes
          for name = (file-name joint)
          for parent = (player.body::body-joint-parent joint)
          for offset = (player.body::joint-offset joint)
          for dofs = (player.body::body-joint-dofs joint)
          for channels = (bvh-node-channels node)
          for end = (bvh-node-end-site node)
          do (is (string= name (bvh-node-name node)))
             (is (equal (and parent (file-name parent)) (bvh-node-parent node)))
             (is (every (lambda (a b) (< (abs (- a b)) 1d-6))
                        (list (player.body::vec3-x offset) (player.body::vec3-y offset)
                              (player.body::vec3-z offset))
                        (bvh-node-offset node))
                 "offset of ~A" name)
             ;; Position channels for the root, the DOF axes first, three rotations.
             (is (= (if parent 3 6) (length channels)))
             (is (equal (append (if parent '() '("Xposition" "Yposition" "Zposition"))
                                (mapcar (lambda (dof)
                                          (format nil "~:@(~A~)rotation"
                                                  (player.body::dof-axis-line dof)))
                                        dofs))
                        (subseq channels 0 (+ (if parent 0 3) (length dofs))))
                 "channels of ~A" name)
             (if (player.body::body-joint-children joint)
                 (is (null end))
                 (is (< 0.001d0 (sqrt (reduce #'+ (mapcar #'* end end))))
                     "the End Site of ~A has no length" name)))))

(defun check-bvh-frame (skeleton nodes frame pose placement)
  "The worst rotation error (degrees) and position error (metres) over the joints
when the channel values FRAME, read per NODES, are taken for POSE under PLACEMENT;
as four values, each error followed by the name of the joint where it occurs."
  (let ((transforms (player::pose-world-transforms skeleton pose :placement placement))
        (worlds (make-array (length nodes)))
        (worst-turn 0d0) (turn-joint nil) (worst-shift 0d0) (shift-joint nil))
    (loop for joint across (player::skeleton-joints skeleton)
          for node in nodes
          for index from 0
          for start = (bvh-node-first-channel node)
          for values = (coerce (subseq frame start (+ start (length (bvh-node-channels node))))
                               'list)
          for rotation = (bvh-channel-rotation (bvh-node-channels node) values)
          for parent = (player.body::body-joint-parent joint)
          for expected = (if parent
                             (player.body::joint-local-rotation joint pose)
                             (player.body::q* (player.body::transform-rotation placement)
                                         (player.body::joint-local-rotation joint pose)))
          do ;; Rebuild the world transforms from the file alone, BVH's way.
             (setf (aref worlds index)
                   (if parent
                       (player.body::transform-compose
                        (aref worlds (player.body::body-joint-index parent))
                        (player.body::make-transform :rotation rotation
                                                :translation (bvh-vec3 (bvh-node-offset node))))
                       (player.body::make-transform :rotation rotation
                                               :translation (bvh-vec3 (subseq values 0 3)))))
             (let ((turn (bvh-degrees-between rotation expected))
                   (shift (player.body::vdistance (player.body::transform-translation (aref worlds index))
                                             (player::joint-world-position transforms joint))))
               (when (> turn worst-turn)
                 (setf worst-turn turn turn-joint (bvh-node-name node)))
               (when (> shift worst-shift)
                 (setf worst-shift shift shift-joint (bvh-node-name node)))))
    (values worst-turn turn-joint worst-shift shift-joint)))

(test bvh-round-trip-humanoid
  (bvh-round-trip 'humanoid 1905))

(test bvh-round-trip-parrot
  (bvh-round-trip 'parrot 1996))

;;; ---------------------------------------------------------------------------
;;; Euler angles

(defparameter *euler-axis-orders*
  '((:x :y :z) (:y :z :x) (:z :x :y) (:x :z :y) (:z :y :x) (:y :x :z))
  "Every order of three distinct axes.")

(defun bvh-euler-quat (axes angles)
  "R(axis1, angle1) R(axis2, angle2) R(axis3, angle3), angles in degrees."
  (bvh-channel-rotation (mapcar (lambda (axis) (format nil "~:@(~A~)rotation" axis)) axes) angles))

(defun euler-recomposition-error (q axes)
  "The angle in radians between Q and its QUAT-TO-EULER angles recomposed."
  (player.body::quat-angle q (bvh-euler-quat axes (multiple-value-list (player.body::quat-to-euler q axes)))))

(test quat-to-euler-recomposes-random-rotations
  (let ((state (sb-ext:seed-random-state 42)))
    (dolist (axes *euler-axis-orders*)
      (let ((worst (loop repeat 500
                         maximize (euler-recomposition-error (bvh-random-quat state) axes))))
        (is (< worst 1d-9) "order ~A: off by ~A rad" axes worst)))))

(test quat-to-euler-recovers-angles
  (let ((state (sb-ext:seed-random-state 7)))
    (dolist (axes *euler-axis-orders*)
      (let ((wrong (loop repeat 200
                         for angles = (list (- (random 358d0 state) 179) (- (random 178d0 state) 89)
                                            (- (random 358d0 state) 179))
                         for got = (multiple-value-list
                                    (player.body::quat-to-euler (bvh-euler-quat axes angles) axes))
                         unless (every (lambda (a b) (< (abs (- a b)) 1d-7)) angles got)
                           collect (list angles got))))
        (is (null wrong) "order ~A: angles not recovered (given, got): ~A" axes wrong)))))

(test quat-to-euler-near-gimbal-lock
  (let ((state (sb-ext:seed-random-state 11)))
    (dolist (axes *euler-axis-orders*)
      (dolist (middle '(90d0 -90d0 89.99999d0 -89.9999999d0 90.0000000001d0 -90.00001d0))
        (let ((worst (loop repeat 50
                           for angles = (list (- (random 360d0 state) 180) middle
                                              (- (random 360d0 state) 180))
                           maximize (euler-recomposition-error (bvh-euler-quat axes angles) axes))))
          (is (< worst 1d-9) "order ~A, middle angle ~A: off by ~A rad" axes middle worst))))))

(test quat-to-euler-rejects-bad-orders
  (signals error (player.body::quat-to-euler (player::quat) '(:x :x :z)))
  (signals error (player.body::quat-to-euler (player::quat) '(:x :y))))

;;; ---------------------------------------------------------------------------
;;; Files and errors

(test bvh-file-is-written-and-replaced
  (let* ((skeleton (player::load-skeleton 'parrot))
         (base (merge-pathnames (format nil "player-bvh-~D/" (random 1000000 (make-random-state t)))
                                (uiop:temporary-directory)))
         (path (merge-pathnames "sub/motion.bvh" base)))
    (unwind-protect
         (progn
           (player::write-bvh-file path skeleton (list (player::make-pose skeleton)))
           (player::write-bvh-file path skeleton (make-list 3 :initial-element
                                                            (player::make-pose skeleton)))
           (is (= 3 (length (getf (read-bvh (uiop:read-file-string path)) :frames)))))
      (uiop:delete-directory-tree base :validate t :if-does-not-exist :ignore))))

(test bvh-errors
  (let* ((skeleton (player::load-skeleton 'parrot))
         (pose (player::make-pose skeleton))
         (blocker (uiop:with-temporary-file (:pathname p :keep t) p)))
    (unwind-protect
         (signals player-error
           (player::write-bvh-file (merge-pathnames "sub/motion.bvh"
                                                    (uiop:ensure-directory-pathname blocker))
                                   skeleton (list pose)))
      (delete-file blocker))
    (signals player-error (player::write-bvh (make-broadcast-stream) skeleton (list #(1 2 3))))
    (signals player-error (player::write-bvh (make-broadcast-stream) skeleton (list pose)
                                             :placements (list (player.body::identity-transform)
                                                               (player.body::identity-transform))))
    (signals player-error (player::write-bvh (make-broadcast-stream) skeleton (list pose)
                                             :frame-time 0))))
