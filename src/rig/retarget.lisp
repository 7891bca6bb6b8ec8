;;;; retarget.lisp -- a clip of one skeleton played on another (issue 26, item
;;;; 5): motion capture (a BVH file, another model's animation) retargeted onto
;;;; any Player skeleton, imported or Player's own, by roles and rest poses.
;;;;
;;;; Matching.  The roots match; then each role both skeletons fill (the
;;;; source's guessed from its joints' names by GUESS-ROLES, the target's as
;;;; its skeleton says), a chain joint by joint (ends to ends, the middle
;;;; spread evenly when the lengths differ), a set member by member; then
;;;; joints of equal names, case-insensitively.  The first match of a target
;;;; joint wins.  A target joint left unmatched keeps its rest (no track).
;;;;
;;;; Rotations.  Every skeleton's joint turns about its parent's rest frame,
;;;; world-aligned (rig.lisp), so the product of the Ds down a chain is the
;;;; joint's world rotation from its rest, A = W G^-1.  A matched target joint
;;;; takes its source joint's A, times C, the turn taking the target's rest
;;;; bone (towards its matched chain successor or only child) onto the
;;;; source's: with equal rests C is the identity and the target turns exactly
;;;; as the source; when the rests differ (CMU's T pose, the humanoid's arms
;;;; down) the target's bones point where the source's point.  A joint with no
;;;; bone to align takes its parent's C, so a hand stays with its forearm.
;;;; Then D = A_parent^-1 A, with A_parent the target parent's own A (its
;;;; source's, or its parent's when it is unmatched).
;;;;
;;;; Time.  The result has keys at every key time of the source clip, so it
;;;; plays the source's motion as the source's slerps would between them.  The
;;;; root's travel is scaled by the ratio of the skeletons' leg lengths.

(in-package #:player.rig)

;;;# Matching joints

(defun chain-match (targets sources)
  "Pairs (TARGET . SOURCE) of two chains, root end first: ends to ends, a
target joint in between to the source joint at the same fraction of its chain."
  (let ((nt (length targets)) (ns (length sources)))
    (loop for target in targets
          for i from 0
          collect (cons target (nth (if (= nt 1) 0 (round (* i (1- ns)) (1- nt))) sources)))))

(defun role-matches (target source)
  "Pairs (TARGET-JOINT . SOURCE-JOINT) of the roles skeletons TARGET and SOURCE both fill."
  (loop for (role . filled) in (skeleton-roles target)
        for theirs = (cdr (assoc role (skeleton-roles source)))
        when theirs
          append (cond ((not (listp filled)) (list (cons filled (if (listp theirs) (first (last theirs)) theirs))))
                       ((not (listp theirs)) '())
                       ((eq (second (assoc role *skeleton-roles*)) :chain) (chain-match filled theirs))
                       (t (mapcar #'cons filled theirs)))))

(defun name-matches (target source)
  "Pairs (TARGET-JOINT . SOURCE-JOINT) of joints with equal names, case-insensitively."
  (loop for joint across (skeleton-joints target)
        for theirs = (find-joint source (symbol-name (body-joint-name joint)))
        when theirs collect (cons joint theirs)))

(defun joint-matches (target source)
  "A vector, per joint of TARGET, the index of the SOURCE joint it follows, or NIL."
  (let ((matches (make-array (length (skeleton-joints target)) :initial-element nil)))
    (loop for (mine . theirs) in (append (list (cons (svref (skeleton-joints target) 0)
                                                     (svref (skeleton-joints source) 0)))
                                         (role-matches target source)
                                         (name-matches target source))
          do (unless (aref matches (body-joint-index mine))
               (setf (aref matches (body-joint-index mine)) (body-joint-index theirs))))
    matches))

;;;# Rest alignment

(defun joint-centre (joint)
  "JOINT's rest centre as a vec3 of doubles."
  (let ((c (body-joint-center joint)))
    (make-vec3 (float (svref c 0) 1d0) (float (svref c 1) 1d0) (float (svref c 2) 1d0))))

(defun bone-successor (skeleton joint)
  "The joint JOINT's bone points at: its successor in a chain role of SKELETON,
else its only child; NIL for none."
  (or (loop for (role . filled) in (skeleton-roles skeleton)
            when (and (listp filled) (eq (second (assoc role *skeleton-roles*)) :chain))
              do (let ((next (second (member joint filled))))
                   (when next (return next))))
      (let ((children (body-joint-children joint)))
        (and children (null (rest children)) (first children)))))

(defun ancestor-p (source ancestor joint)
  "Is the joint index ANCESTOR a proper ancestor of the joint index JOINT in SOURCE?"
  (loop for j = (body-joint-parent (svref (skeleton-joints source) joint)) then (body-joint-parent j)
        while j thereis (= (body-joint-index j) ancestor)))

(defun shortest-arc (from to)
  "The smallest rotation taking the unit vec3 FROM onto the unit vec3 TO, a QUAT."
  (let ((cosine (vdot from to)))
    (if (< cosine (- 1d-9 1d0))
        ;; Opposite: a half turn about any axis across FROM.
        (let ((axis (vcross from (if (< (abs (vec3-x from)) 0.9d0) (make-vec3 1 0 0) (make-vec3 0 1 0)))))
          (quat-from-axis-angle (vnormalize axis) pi))
        (let ((axis (vcross from to)))
          (qnormalize (make-quat (+ 1d0 cosine) (vec3-x axis) (vec3-y axis) (vec3-z axis)))))))

(defun rest-alignments (target source matches)
  "Per joint of TARGET, the QUAT C turning its rest bone onto its matched SOURCE
joint's (MATCHES from JOINT-MATCHES), its parent's C when either has none."
  (let ((alignments (make-array (length (skeleton-joints target)))))
    (loop for joint across (skeleton-joints target)
          for k from 0
          for j = (aref matches k)
          for next = (bone-successor target joint)
          for j-next = (and j next (aref matches (body-joint-index next)))
          for parent = (body-joint-parent joint)
          do (setf (svref alignments k)
                   (if (and j-next (ancestor-p source j j-next))
                       (let ((mine (v- (joint-centre next) (joint-centre joint)))
                             (theirs (v- (joint-centre (svref (skeleton-joints source) j-next))
                                         (joint-centre (svref (skeleton-joints source) j)))))
                         (if (and (> (vnorm mine) 1d-9) (> (vnorm theirs) 1d-9))
                             (shortest-arc (vnormalize mine) (vnormalize theirs))
                             (if parent (svref alignments (body-joint-index parent)) (quat))))
                       (if parent (svref alignments (body-joint-index parent)) (quat)))))
    alignments))

;;;# Sampling the source

(defun clip-key-times (clip)
  "Every key time of CLIP's tracks and root travel, increasing, times within a
nanosecond of the one kept before dropped, as DOUBLES."
  (let ((times (sort (apply #'concatenate 'list (or (clip-root-times clip) #())
                            (map 'list #'track-times (clip-tracks clip)))
                     #'<))
        (kept '()))
    (dolist (time times (doubles (nreverse kept)))
      (unless (and kept (< (- time (first kept)) 1d-9))
        (push time kept)))))

(defun source-deltas (source clip time)
  "Each SOURCE joint's world rotation from its rest (A, a QUAT) when CLIP plays
at TIME: the product of the Ds down its chain (the identity for a joint CLIP
does not move)."
  (let* ((joints (skeleton-joints source))
         (own (make-array (length joints) :initial-element nil))
         (deltas (make-array (length joints))))
    (loop for track across (clip-tracks clip)
          do (setf (svref own (track-joint track))
                   (multiple-value-call #'make-quat (sample-track-quat track time))))
    (loop for joint across joints
          for k from 0
          for parent = (body-joint-parent joint)
          for d = (or (svref own k) (quat))
          do (setf (svref deltas k) (if parent (q* (svref deltas (body-joint-index parent)) d) d)))
    deltas))

(defun target-rotations (target matches alignments deltas)
  "Per joint of TARGET, its D (a QUAT) for the source's world rotations
DELTAS, or NIL for a joint no source joint matches."
  (let* ((joints (skeleton-joints target))
         (world (make-array (length joints)))
         (rotations (make-array (length joints) :initial-element nil)))
    (loop for joint across joints
          for k from 0
          for j = (aref matches k)
          for parent-world = (let ((parent (body-joint-parent joint)))
                               (if parent (svref world (body-joint-index parent)) (quat)))
          do (setf (svref world k) (if j (q* (svref deltas j) (svref alignments k)) parent-world))
             (when j
               (setf (svref rotations k) (qnormalize (q* (qconjugate* parent-world) (svref world k))))))
    rotations))

;;;# Root travel

(defun leg-length (skeleton)
  "The length of SKELETON's left leg (else its right), hip to the chain's last
joint; else its root's height; NIL when that is 0."
  (let* ((leg (or (skeleton-role skeleton :left-leg) (skeleton-role skeleton :right-leg)))
         (length (if leg
                     (loop for (a b) on leg while b sum (vnorm (v- (joint-centre b) (joint-centre a))))
                     (vec3-y (joint-centre (svref (skeleton-joints skeleton) 0))))))
    (and (> length 1d-9) length)))

(defun scaled-root-travel (clip ratio)
  "CLIP's root offsets times RATIO, as DOUBLES, or NIL when it has none."
  (let ((offsets (clip-root-offsets clip)))
    (and offsets (map 'doubles (lambda (x) (* ratio x)) offsets))))

;;;# The entry point

(defun retarget-clip (source name target &key (clip-name (string-downcase (string name))))
  "The MOTION-CLIP playing SOURCE's clip NAME on the skeleton TARGET (see the
top of retarget.lisp): per matched joint of TARGET a track of its rotations D
at every key time of the clip, and the root's travel scaled by the ratio of
the leg lengths.  SOURCE is a MODEL (from IMPORT-MODEL) or a skeleton made from
one (MODEL-SKELETON).  The clip is called CLIP-NAME.  Signals a RIG-ERROR when
SOURCE has no clip NAME."
  (check-argument 'retarget-clip 'source source
                  (lambda (x) (or (model-p x) (and (skeleton-p x) (skeleton-rig x))))
                  "a model (from import-model) or a skeleton made from one (model-skeleton)")
  (check-argument 'retarget-clip 'target target #'skeleton-p "a skeleton (from load-skeleton or model-skeleton)")
  (let* ((source (if (model-p source) (model-skeleton source) source))
         (clip (find-clip (skeleton-rig source) name t))
         (matches (joint-matches target source))
         (alignments (rest-alignments target source matches))
         (times (clip-key-times clip))
         (keys (make-array (length (skeleton-joints target)) :initial-element nil)))
    (loop for time across times
          for rotations = (target-rotations target matches alignments (source-deltas source clip time))
          do (loop for d across rotations
                   for k from 0
                   when d do (push d (svref keys k))))
    (let ((source-leg (leg-length source)) (target-leg (leg-length target)))
      (make-motion-clip clip-name (clip-duration clip)
                        (coerce (loop for k from 0 below (length keys)
                                      when (svref keys k)
                                        collect (make-track k times (continuous-quats (reverse (svref keys k)))))
                                'simple-vector)
                        :root-times (clip-root-times clip)
                        :root-offsets (scaled-root-travel clip (if (and source-leg target-leg)
                                                                   (/ target-leg source-leg)
                                                                   1d0))
                        :source (format nil "~A, clip ~A, retargeted onto ~A"
                                        (file-namestring (model-file (rig-model (skeleton-rig source))))
                                        (clip-name clip) (lisp-text (skeleton-name target)))))))

(defun continuous-quats (quats)
  "QUATS as DOUBLES, w x y z each, each key's sign chosen within 180 degrees
of the one before (so slerp takes the short way)."
  (let ((previous nil))
    (doubles (loop for q in quats
                   collect (progn
                             (when (and previous (minusp (+ (* (quat-w q) (quat-w previous)) (* (quat-x q) (quat-x previous))
                                                     (* (quat-y q) (quat-y previous)) (* (quat-z q) (quat-z previous)))))
                               (setf q (make-quat (- (quat-w q)) (- (quat-x q)) (- (quat-y q)) (- (quat-z q)))))
                             (setf previous q)
                             (list (quat-w q) (quat-x q) (quat-y q) (quat-z q)))))))
