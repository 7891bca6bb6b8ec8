;;;; appearance.lisp -- how each skeleton looks: a table per skeleton name of
;;;; colours, drawn radii, head, eyes, brows and decorative shapes, read by
;;;; body-mesh.lisp.  Data, not code: a new look is a new table entry.

(in-package #:player.render)

;;; Per skeleton name, a plist:
;;;   :palette ((NAME R G B) ...)      named colours; the first is the default
;;;   :colours ((NAME JOINT ...) ...)  limbs from these joints (and, unless they
;;;                                    are named too, their descendants) in NAME
;;;   :radii ((JOINT R) ...)           drawn radius instead of the file's
;;;   :leaves ((JOINT LENGTH [(X Y Z)]) ...)  a capsule from a leaf joint along
;;;                                    its bone (or the direction) -- fingers, toes
;;;   :head (:offset (X Y Z) :radii (RX RY [RZ]) :colour NAME)  the head
;;;                                    ellipsoid; without RZ, deep enough that
;;;                                    the eye centres lie on its surface
;;;   :eyes (:radius R :white C :iris C :pupil C :lid C :lid-tilt DEG :lid-angle DEG)
;;;   :brows (:offset (X Y Z) :radii (RX RY RZ) :colour C)  a flat ellipsoid
;;;                                    on each brow joint
;;;   :shapes (SHAPE ...)  decoration: (:ellipsoid JOINT :offset :radii),
;;;     (:segment JOINT :child J :width :thickness :normal) a flat ellipsoid along
;;;     a bone, (:chain JOINT :points ((X Y Z R) ...)) capsules through points,
;;;     (:fan JOINT :offset :direction :normal :length :width :count :spread)
;;;     feathers; each may take :colour.
;;; Offsets and directions are metres in the joint's rest frame.  Every entry
;;; naming an L_ joint also makes its R_ twin, mirrored across x = 0.

(defparameter *body-appearances*
  '((humanoid
     :palette ((skin 0.93 0.76 0.62) (shirt 0.25 0.42 0.7) (trousers 0.22 0.24 0.32)
               (shoes 0.18 0.12 0.08) (hair 0.3 0.2 0.12) (white 0.97 0.97 0.95)
               (iris 0.35 0.22 0.1) (pupil 0.03 0.03 0.03))
     :colours ((trousers humanoid-root l_hip) (shirt vl5 l_shoulder) (skin skullbase l_elbow)
               (shoes l_ankle))
     :radii ((skullbase 0.035) (humanoid-root 0.06) (sacroiliac 0.08))
     :leaves ((l_thumb1 0.05) (l_index1 0.07) (l_middle1 0.075) (l_ring1 0.07) (l_pinky1 0.055)
              (l_midtarsal 0.05 (0 0 1)))
     :head (:offset (0 0.06 -0.005) :radii (0.075 0.095) :colour skin)
     :eyes (:white white :iris iris :pupil pupil :lid skin)
     ;; A brow pivots at its own centre, so it reaches 18 mm in front of it for
     ;; 'raise' to lift it, and back into the forehead.
     :brows (:offset (0 0 0.004) :radii (0.016 0.0035 0.014) :colour hair)
     :shapes ((:ellipsoid vl5 :offset (0 0.27 0.037) :radii (0.17 0.2 0.115))
              (:ellipsoid sacroiliac :offset (0 0.03 -0.01) :radii (0.15 0.09 0.1))
              (:ellipsoid skullbase :offset (0 0.09 0.01) :radii (0.07 0.07 0.09)) ; forehead
              (:chain skullbase :points ((0 0 -0.005 0.048) (0 -0.08 -0.012 0.055))) ; neck
              (:chain temporomandibular :points ((0 0 0 0.03) (0 -0.04 0.035 0.022)))
              (:ellipsoid l_wrist :offset (-0.004 -0.05 -0.002) :radii (0.014 0.045 0.042))))
    ;; The Persona paper (reference/persona-msr.txt) gives Peedy no colours;
    ;; these are a cartoon parrot's: green body, yellow head, orange beak, blue primaries.
    (parrot
     :palette ((body 0.25 0.65 0.2) (face 0.95 0.8 0.2) (beak 0.95 0.55 0.1)
               (primaries 0.2 0.35 0.8) (tail 0.15 0.5 0.15) (legs 0.55 0.55 0.55)
               (white 0.97 0.97 0.95) (iris 0.3 0.18 0.08) (pupil 0.03 0.03 0.03))
     :colours ((face head) (beak beak) (legs l_hip) (primaries l_primaries) (tail tail))
     :radii ((head 0.03))
     :head (:offset (0 0.018 -0.015) :radii (0.042 0.045) :colour face)
     :eyes (:radius 0.013 :white white :iris iris :pupil pupil :lid face)
     :shapes ((:ellipsoid parrot-root :offset (0 0.015 0) :radii (0.055 0.085 0.06))
              (:chain head :points ((0 0.008 0.03 0.016) (0 0 0.055 0.009) (0 -0.012 0.068 0.003)
                                    (0 -0.02 0.064 0.002))
               :colour beak)
              (:chain beak :points ((0 0 -0.008 0.011) (0 -0.008 0.012 0.007)
                                    (0 -0.012 0.025 0.002)))
              (:fan crest :direction (0 0.8 -1) :normal (1 0 0) :length 0.07 :width 0.012
               :count 3 :spread 40)
              (:segment l_shoulder :child l_elbow :width 0.05 :thickness 0.012 :normal (1 0 0))
              (:segment l_elbow :child l_wrist :width 0.045 :thickness 0.01 :normal (1 0 0))
              (:segment l_wrist :child l_primaries :width 0.04 :thickness 0.008 :normal (1 0 0))
              (:fan l_primaries :direction (-0.005 -0.06 -0.04) :normal (1 0 0) :length 0.08
               :width 0.018 :count 4 :spread 30)
              (:fan tail :direction (0 -0.8 -1) :normal (0 1 -0.8) :length 0.12 :width 0.025
               :count 5 :spread 50)
              (:chain l_foot :points ((0 0 0 0.005) (0.006 -0.003 0.02 0.003)))
              (:chain l_foot :points ((0 0 0 0.005) (-0.006 -0.003 0.02 0.003)))
              (:chain l_foot :points ((0 0 0 0.005) (0.004 -0.003 -0.018 0.003)))
              (:chain l_foot :points ((0 0 0 0.005) (-0.004 -0.003 -0.018 0.003))))))
  "How each shipped skeleton looks, by skeleton name; see the comment above.
A skeleton not listed gets grey limbs, a head, eyes, lids and brows from its roles.")

(defparameter *face-roles*
  '(:left-eye :right-eye :left-upper-lid :right-upper-lid :left-brow :right-brow :jaw :crest)
  "Roles whose joints get face parts (or, for :jaw and :crest, the table's
shapes) instead of limb capsules.")

(defun twin-joint-name (name)
  "The right-side twin of the left-side joint NAME (L_X gives \"R_X\"), or NIL."
  (let ((s (string name)))
    (and (> (length s) 2) (string-equal "L_" s :end2 2) (concatenate 'string "R_" (subseq s 2)))))

(defun mirror-offset (point)
  "POINT, a list (X Y Z ...), mirrored across x = 0."
  (cons (- (first point)) (rest point)))

(defun mirror-appearance-shape (shape)
  "The right-side twin of SHAPE, (KIND JOINT . OPTIONS), or NIL for a shape not on an L_ joint."
  (destructuring-bind (kind joint &rest options) shape
    (let ((twin (twin-joint-name joint)))
      (and twin
           (list* kind twin
                  (loop for (key value) on options by #'cddr
                        collect key
                        collect (case key
                                  ((:offset :direction :normal) (mirror-offset value))
                                  (:points (mapcar #'mirror-offset value))
                                  (:child (twin-joint-name value))
                                  (t value))))))))

(defun mirror-appearance-entry (entry)
  "The right-side twin of ENTRY, (JOINT VALUE [(X Y Z)]), or NIL for an entry not on an L_ joint."
  (let ((twin (twin-joint-name (first entry))))
    (and twin (list* twin (second entry) (mapcar #'mirror-offset (cddr entry))))))

(defun skeleton-appearance (skeleton)
  "SKELETON's entry of *BODY-APPEARANCES*, with the R_ twins of L_ entries added
(those whose joint SKELETON has)."
  (let ((plist (rest (assoc (string (skeleton-name skeleton)) *body-appearances*
                            :key #'string :test #'string-equal))))
    (flet ((twins (entries mirror joint-of)
             ;; A twin is kept only when the skeleton has its joint.
             (append entries (remove-if-not (lambda (twin)
                                              (and twin (find-joint skeleton (funcall joint-of twin))))
                                            (mapcar mirror entries)))))
      (list* :shapes (twins (getf plist :shapes) #'mirror-appearance-shape #'second)
             :leaves (twins (getf plist :leaves) #'mirror-appearance-entry #'first)
             :radii (twins (getf plist :radii) #'mirror-appearance-entry #'first)
             :colours (mapcar (lambda (entry)
                                (append entry (remove nil (mapcar #'twin-joint-name (rest entry)))))
                              (getf plist :colours))
             plist))))

(defun appearance-colour (appearance designator)
  "The colour (R G B) DESIGNATOR names: a palette entry's name or a list of three reals."
  (if (listp designator)
      designator
      (or (rest (assoc (string designator) (getf appearance :palette)
                       :key #'string :test #'string-equal))
          (skeleton-fail designator "no colour ~A in the palette" (lisp-text designator)))))

(defun joint-colours (skeleton appearance)
  "A vector, indexed like SKELETON's joints, of each joint's limb colour: its
:colours entry, else its parent's colour, else the palette's first."
  (let* ((joints (skeleton-joints skeleton))
         (colours (make-array (length joints))))
    (loop for joint across joints
          for entry = (find-if (lambda (e)
                                 (member (body-joint-name joint) (rest e) :test #'string-equal))
                               (getf appearance :colours))
          for parent = (body-joint-parent joint)
          do (setf (svref colours (body-joint-index joint))
                   (cond (entry (appearance-colour appearance (first entry)))
                         (parent (svref colours (body-joint-index parent)))
                         (t (or (rest (first (getf appearance :palette))) '(0.7 0.7 0.7))))))
    colours))

(defun drawn-radius (joint appearance)
  "The radius JOINT's limbs are drawn with, in metres, as a double-float."
  (float (or (second (assoc (body-joint-name joint) (getf appearance :radii) :test #'string-equal))
             (body-joint-radius joint))
         1d0))
