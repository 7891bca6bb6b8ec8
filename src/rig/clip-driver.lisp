;;;; clip-driver.lisp -- the :clip motor function: an animation clip played on
;;;; a body, requesting its joints' channels at a priority like any driver,
;;;; so arbitration, cuts and policies treat clips as they treat gestures.
;;;; It fades itself in over :fade: while it fades, each of its channels is
;;;; (1 - w) times what lies under it -- the clip it replaces, still playing
;;;; at a lower priority or written before it -- plus w times the clip, w
;;;; rising smoothly from 0 to :weight.  So two clips cross-fade live, not
;;;; from a frozen pose.  It masks itself to some joints (:joints) and plays
;;;; at a speed, once or looping.

(in-package #:player.rig)

(defclass clip-driver (driver)
  ((clip :initform nil :accessor clip-driver-clip :documentation "The CLIP it plays.")
   (outputs :initform nil :accessor clip-driver-outputs
            :documentation "Per angle CLIP-ANGLES gives, the pose index it drives, or -1 where masked.")
   (angles :initform nil :accessor clip-driver-angles :documentation "CLIP-ANGLES' buffer.")
   (layouts :initform nil :accessor clip-driver-layouts
            :documentation "CLIP-LAYOUTS of the clip on the body's skeleton: NIL when every joint is x/y/z.")
   (morph-tracks :initform '() :accessor clip-driver-morph-tracks
                 :documentation "The clip's morph tracks it plays (see MASKED-MORPH-TRACKS)."))
  (:documentation "Plays a CLIP of the body's model: each joint the clip moves,
and the mask lets through, follows the clip's rotations."))

(define-motor-function :clip clip-driver
  "Play an animation clip of the body's imported model; ends after the clip unless :loop."
  (:name (:or :symbol :string) :required "the clip's name (an animation of the model, or a clip its (model ...) form cuts)")
  (:from (:or :string (:member nil)) nil "a BVH or model file whose clip NAME is retargeted onto the body, NIL for the body's model")
  (:loop :boolean nil "repeat the clip until stopped")
  (:speed :positive 1 "how fast the clip plays: 2 is twice as fast")
  (:fade :non-negative 0.2 "seconds to fade in over what lies under it")
  (:weight :non-negative 1 "how much of the clip shows over what lies under it, 0 to 1")
  (:joints :list nil "only these joints (names or roles; a role means each of its joints), NIL for all")
  (:root (:member :in-place :move) :in-place "whether the clip moves the character (:move) or plays in place")
  (:priority :real 10 "arbitration priority; higher wins"))

(defvar *clip-resolvers* '()
  "Functions of a CLIP-DRIVER that return its CLIP or NIL, tried first (the
retargeting of clips :from another file registers one).")

(defun driver-clip (driver)
  "The CLIP DRIVER plays: from a resolver, else the body's model's clip by :name."
  (or (some (lambda (resolver) (funcall resolver driver)) *clip-resolvers*)
      (let ((rig (skeleton-rig (driver-skeleton driver)))
            (name (driver-arg driver :name)))
        (unless rig
          (driver-frame-fail driver "body skeleton ~A is not an imported model, so it has no clip ~A (play one :from a file)"
                             (lisp-text (skeleton-name (driver-skeleton driver))) (lisp-text name)))
        (or (find-clip rig name)
            (driver-frame-fail driver "~A has no clip ~A (clips: ~{~A~^ ~})"
                               (file-namestring (model-file (rig-model rig))) (lisp-text name)
                               (rig-clip-names rig))))))

(defun masked-joints (driver)
  "The skeleton joint indices DRIVER's :joints lets through, or T for all."
  (let ((names (driver-arg driver :joints))
        (skeleton (driver-skeleton driver)))
    (if (null names)
        t
        (loop for name in names
              append (cond ((keywordp name)
                            (let ((filled (skeleton-role skeleton name)))
                              (unless filled
                                (driver-frame-fail driver ":joints names the role ~A, which skeleton ~A does not fill"
                                                   (lisp-text name) (lisp-text (skeleton-name skeleton))))
                              (mapcar #'body-joint-index (ensure-list filled))))
                           ;; A morph target's name: its weight, not a joint (MASKED-MORPH-TRACKS).
                           ((and (stringp name) (morph-index skeleton name)) '())
                           ((and name (or (symbolp name) (stringp name)))
                            (list (body-joint-index
                                   (or (find-joint skeleton name)
                                       (driver-frame-fail driver ":joints names ~A, which is not a joint of skeleton ~A"
                                                          (lisp-text name) (lisp-text (skeleton-name skeleton)))))))
                           (t (driver-frame-fail driver ":joints holds joint names and roles, not ~A" (lisp-text name))))))))

(defun track-pose-indices (skeleton track)
  "The pose indices the three angle slots of TRACK go to: its joint's DOFs in
their order (x, y and z for an imported joint; see DOF-LAYOUTS.LISP), -1 for
the slots of the axes it lacks."
  (let ((joint (svref (skeleton-joints skeleton) (track-joint track))))
    (loop for n below 3
          collect (if (< n (length (body-joint-dofs joint))) (+ (body-joint-dof-start joint) n) -1))))

(defmethod driver-setup ((driver clip-driver))
  (let* ((clip (driver-clip driver))
         (mask (masked-joints driver))
         (skeleton (driver-skeleton driver))
         (outputs (loop for track across (clip-tracks clip)
                        append (if (or (eq mask t) (member (track-joint track) mask))
                                   (track-pose-indices skeleton track)
                                   (list -1 -1 -1)))))
    (setf (clip-driver-clip driver) clip
          (clip-driver-layouts driver) (clip-layouts clip skeleton)
          (clip-driver-outputs driver) (coerce outputs '(simple-array fixnum (*)))
          (clip-driver-angles driver) (make-array (length outputs) :element-type 'double-float)
          (clip-driver-morph-tracks driver) (masked-morph-tracks driver clip))
    (sort (append (remove -1 outputs) (mapcar #'first (clip-driver-morph-tracks driver))) #'<)))

(defun masked-morph-tracks (driver clip)
  "CLIP's morph tracks DRIVER plays: all of them without :joints, else those
whose morph target :joints names (in a string)."
  (let ((names (driver-arg driver :joints))
        (skeleton (driver-skeleton driver)))
    (if (null names)
        (clip-morph-tracks clip)
        (remove-if-not (lambda (track)
                         (let ((name (svref (skeleton-morphs skeleton)
                                            (- (first track) (skeleton-dof-count skeleton)))))
                           (member name names :test (lambda (a b) (and (stringp b) (string-equal a b))))))
                       (clip-morph-tracks clip)))))

(defun clip-local-time (driver time)
  "Seconds into DRIVER's clip at the absolute TIME: scaled by :speed, wrapped when looping."
  (let* ((clip (clip-driver-clip driver))
         (local (* (driver-local-time driver time) (driver-real driver :speed)))
         (duration (clip-duration clip)))
    (if (and (driver-arg driver :loop) (> duration 0d0))
        (mod local duration)
        local)))

(defmethod driver-drive ((driver clip-driver) time pose)
  (let ((angles (if (clip-driver-layouts driver)
                    (clip-dof-angles (clip-driver-clip driver) (clip-local-time driver time)
                                     (clip-driver-layouts driver) (clip-driver-angles driver))
                    (clip-angles (clip-driver-clip driver) (clip-local-time driver time)
                                 (clip-driver-angles driver))))
        (weight (clip-fade-weight driver time)))
    (loop for index across (clip-driver-outputs driver)
          for angle across angles
          unless (minusp index)
            do (setf (aref pose index)
                     (if (= weight 1d0)
                         angle
                         (+ (aref pose index) (* weight (- angle (aref pose index)))))))
    (let ((local (clip-local-time driver time)))
      (dolist (track (clip-driver-morph-tracks driver))
        (let ((index (first track)))
          (setf (aref pose index)
                (+ (aref pose index) (* weight (- (clip-morph-weight track local) (aref pose index))))))))))

(defun clip-fade-weight (driver time)
  "The weight DRIVER's clip has at TIME: its :weight, times its fade-in."
  (* (min 1d0 (driver-real driver :weight))
     (ramp (driver-local-time driver time) 0d0 (driver-real driver :fade))))

(defmethod driver-default-blend ((driver clip-driver))
  ;; It fades itself in over what lies under it; a crossfade from a frozen
  ;; pose on top would only slow it.
  0d0)

(defmethod driver-end-time ((driver clip-driver))
  (unless (driver-arg driver :loop)
    (+ (driver-start driver)
       (/ (clip-duration (clip-driver-clip driver)) (driver-real driver :speed)))))
