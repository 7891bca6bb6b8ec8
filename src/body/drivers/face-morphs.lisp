;;;; face-morphs.lisp -- a face made of morph targets (blend shapes) instead of
;;;; joints: which of an imported model's morph targets make its visemes and
;;;; close its eyes, by the names the common rigs give them, so :lips and
;;;; :blink move a face without a jaw or lids; and the :morph motor function,
;;;; which sets any morph target's weight.

(in-package #:player.body)

(defparameter *oculus-visemes*
  '((:rest . "sil") (:mm . "PP") (:ff . "FF") (:th . "TH") (:dd . "DD") (:kk . "kk")
    (:ch . "CH") (:ss . "SS") (:ll . "nn") (:rr . "RR") (:aa . "aa") (:ee . "E")
    (:ih . "I") (:oh . "O") (:oo . "U"))
  "Each of Player's visemes and the Oculus Lipsync viseme (morph viseme_NAME,
as Ready Player Me and many VRoid exports name them) that shapes it.")

(defparameter *vowel-morphs*
  '((:aa . "A") (:ih . "I") (:oo . "U") (:ee . "E") (:oh . "O"))
  "Player's vowel visemes and the VRM vowel morphs (A I U E O) that shape them.")

(defparameter *mouth-open-morphs* '("jawOpen" "mouthOpen" "MouthOpen" "jaw_open" "mouth_open")
  "Morphs that open the mouth (ARKit's jawOpen and its relatives), weighted by a viseme's opening.")

(defparameter *blink-morphs*
  '(("eyeBlink_L" "eyeBlink_R") ("eyeBlinkLeft" "eyeBlinkRight") ("Blink_L" "Blink_R")
    ("blink") ("Blink") ("eyesClosed") ("EyesClosed"))
  "Morph sets that close the eyes, tried in order: ARKit's pair, others' one morph.")

(defun morph-named (skeleton name)
  "The pose index of SKELETON's morph target NAME, or of one whose name ends
with _NAME, .NAME or :NAME (a rig's prefix), compared case-insensitively; or NIL."
  (or (morph-index skeleton name)
      (let ((position (position-if (lambda (morph)
                                     (and (> (length morph) (length name))
                                          (string-equal name morph :start2 (- (length morph) (length name)))
                                          (member (char morph (- (length morph) (length name) 1)) '(#\_ #\. #\:))))
                                   (skeleton-morphs skeleton))))
        (and position (+ (skeleton-dof-count skeleton) position)))))

(defun viseme-morph-table (skeleton)
  "How SKELETON's morph targets shape each viseme of *VISEMES*: an alist from
each viseme to its ((POSE-INDEX . WEIGHT) ...), from Oculus viseme morphs,
else VRM vowels, else a mouth-open morph weighted by the viseme's opening;
NIL when SKELETON has none of them."
  (let ((oculus (loop for (viseme . name) in *oculus-visemes*
                      for index = (morph-named skeleton (format nil "viseme_~A" name))
                      when index collect (cons viseme index)))
        (vowels (loop for (viseme . name) in *vowel-morphs*
                      for index = (morph-named skeleton name)
                      when index collect (cons viseme index)))
        (open (some (lambda (name) (morph-named skeleton name)) *mouth-open-morphs*)))
    (flet ((table (shapes fallback)
             ;; A viseme without its own morph opens the mouth on FALLBACK by its opening.
             (let ((channels (remove-duplicates (append (mapcar #'cdr shapes) (and fallback (list fallback))))))
               (loop for (viseme opening) in *visemes*
                     for own = (cdr (assoc viseme shapes))
                     collect (cons viseme
                                   (loop for channel in channels
                                         collect (cons channel
                                                       (cond (own (if (eql channel own) 1d0 0d0))
                                                             ((eql channel fallback) (float opening 1d0))
                                                             (t 0d0)))))))))
      (cond ((>= (length oculus) 5) (table oculus nil))
            (vowels (table vowels (or open (cdr (assoc :aa vowels)))))
            (open (table '() open))
            (t nil)))))

(defun blink-morph-indices (skeleton)
  "The pose indices of the morph targets that close SKELETON's eyes (*BLINK-MORPHS*), or NIL."
  (loop for set in *blink-morphs*
        for indices = (mapcar (lambda (name) (morph-named skeleton name)) set)
        when (every #'identity indices) return indices))

;;;# :morph

(defclass morph-driver (keyframe-driver)
  ()
  (:documentation "The :morph function: a keyframe driver easing one morph
target's weight from where it is to a weight, and holding it."))

(define-motor-function :morph morph-driver
  "Ease a morph target (blend shape) of the body's model to a weight over :duration, then hold it."
  (:name (:or :symbol :string) :required "the morph target's name (a string keeps its case)")
  (:weight :non-negative 1 "the weight to reach, from 0 (none) to 1 (the whole target)")
  (:duration :non-negative 0.3 "seconds to reach it")
  (:priority :real 10 "arbitration priority; higher wins"))

(defmethod keyframe-key-forms ((driver morph-driver))
  (let ((clauses `((:morph ,(driver-arg driver :name) ,(driver-arg driver :weight))))
        (duration (driver-arg driver :duration)))
    (if (zerop duration)
        `((0 ,clauses))
        `((0 :start) (,duration ,clauses)))))

(defmethod keyframe-interpolation ((driver morph-driver)) :ease-in-out)
(defmethod keyframe-loop-p ((driver morph-driver)) nil)
(defmethod keyframe-hold-p ((driver morph-driver)) t)
(defmethod driver-default-blend ((driver morph-driver)) 0d0)
