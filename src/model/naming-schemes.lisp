;;;; naming-schemes.lisp -- the words of an imported joint's name and the
;;;; naming schemes artists' tools write (issue 26, item 3), for guessing roles.
;;;;
;;;; A name is normalised first (NORMALISED-JOINT-NAME): a tool's prefix
;;;; (mixamorig:, Bip01, B_, DEF-) and a side marker (Left, L, l, _L, .L, " L")
;;;; are taken off, the rest is lower-cased and run together, with leading zeros
;;;; dropped from numbers written apart: "mixamorig:LeftForeArm" is (:left
;;;; "forearm"), "Bip01 L Toe0" (:left "toe0"), "spine.001" (nil "spine1").  Then
;;;; *NAMING-SCHEMES* says which PART each normalised name is (PART-RANK); the
;;;; role guesser (roles.lisp) builds Player's roles from the parts.

(in-package #:player.model)

;;; ---------------------------------------------------------------------------
;;; Normalising a joint's name

(defparameter *name-separators* '(#\_ #\- #\. #\: #\Space #\Tab)
  "Characters that separate the words of a joint name.")

(defparameter *side-words* '(("left" . :left) ("l" . :left) ("right" . :right) ("r" . :right))
  "Words that mark a joint's side, and the side they mark.")

(defparameter *prefix-words* '("mixamorig" "mixamorig1" "mixamorig2" "bip01" "bip001" "b" "def")
  "Leading words tools put before every joint's name (Mixamo's namespace when its
colon became a separator, 3ds Max Biped's Bip01, the B_ of some .x files,
Rigify's deform bones); they say nothing about the joint.")

(defun word-boundary-p (name index)
  "Does a new word start at INDEX of NAME?  At a separator's end, or where camel
case turns: aB, 1B, and the B of ABc (so LHand is L + Hand)."
  (let ((char (char name index))
        (before (char name (1- index)))
        (after (and (< (1+ index) (length name)) (char name (1+ index)))))
    (and (upper-case-p char)
         (or (lower-case-p before) (digit-char-p before)
             (and (upper-case-p before) after (lower-case-p after))))))

(defun split-joint-name (name)
  "The words of NAME, split at separators and camel-case turns, as written."
  (let ((words '()) (start nil))
    (flet ((end-word (end) (when start (push (subseq name start end) words) (setf start nil))))
      (dotimes (index (length name))
        (cond ((member (char name index) *name-separators*) (end-word index))
              ((and start (word-boundary-p name index)) (end-word index) (setf start index))
              ((not start) (setf start index))))
      (end-word (length name)))
    (nreverse words)))

(defun drop-leading-zeros (word)
  "WORD without leading zeros when it is a number of its own (the 001 of spine.001);
digits glued to letters are kept as written, since Biped's Finger01 (the thumb's
second joint) is not Finger1 (the index finger)."
  (if (every #'digit-char-p word)
      (princ-to-string (parse-integer word))
      word))

(defun side-word (word)
  "The side WORD marks, :LEFT or :RIGHT, or NIL."
  (cdr (assoc word *side-words* :test #'string-equal)))

(defun split-glued-side (words)
  "WORDS, with a side glued to the front of the first (\"leftarm\") made a word of its own."
  (let ((first (first words)))
    (dolist (side '("left" "right") words)
      (when (and (> (length first) (length side))
                 (string-equal side first :end2 (length side)))
        (return (list* side (subseq first (length side)) (rest words)))))))

(defun normalised-joint-name (name)
  "Two values for the joint NAME: its CORE, the lower-case words but the prefix and
side run together (NIL when nothing is left, or when NAME marks both sides), and
its SIDE, :LEFT, :RIGHT or NIL."
  (let ((words (mapcar #'drop-leading-zeros (split-joint-name name))))
    (loop while (and (rest words) (member (first words) *prefix-words* :test #'string-equal))
          do (pop words))
    (unless (some #'side-word words)
      (setf words (split-glued-side words)))
    (let ((sides (remove nil (mapcar #'side-word words)))
          (core (string-downcase (format nil "~{~A~}" (remove-if #'side-word words)))))
      (if (or (> (length sides) 1) (zerop (length core)))
          (values nil nil)
          (values core (first sides))))))

;;; ---------------------------------------------------------------------------
;;; The naming schemes

(defparameter *naming-schemes*
  '((:mixamo                            ; mixamorig:LeftForeArm, after the prefix
     (:head "head") (:neck "neck") (:hips "hips") (:spine-base "spine") (:eye "eye")
     (:upper-arm "arm") (:forearm "forearm") (:hand "hand")
     (:thigh "upleg") (:shin "leg") (:foot "foot") (:toe "toebase")
     (:thumb "handthumb1") (:index "handindex1") (:middle "handmiddle1")
     (:ring "handring1") (:pinky "handpinky1"))
    (:cmu                               ; the CMU motion capture BVH files
     (:head "head") (:neck "neck") (:hips "hips") (:spine-base "spine")
     (:upper-arm "arm") (:forearm "forearm") (:hand "hand")
     (:thigh "upleg") (:shin "leg") (:foot "foot") (:toe "toebase")
     (:thumb "thumb") (:index "handindex1"))
    (:vrm                               ; VRM humanoid bones: leftLowerArm
     (:head "head") (:neck "neck") (:hips "hips") (:spine-base "spine") (:eye "eye")
     (:jaw "jaw") (:upper-arm "upperarm") (:forearm "lowerarm") (:hand "hand")
     (:thigh "upperleg") (:shin "lowerleg") (:foot "foot") (:toe "toes")
     (:thumb "thumbmetacarpal" "thumbproximal") (:index "indexproximal")
     (:middle "middleproximal") (:ring "ringproximal") (:pinky "littleproximal"))
    (:rigify                            ; Blender's metarig: forearm.L, f_index.01.L
     (:head "head") (:neck "neck") (:hips "hips") (:spine-base "spine") (:eye "eye")
     (:jaw "jaw") (:upper-lid "lidt") (:upper-arm "upperarm") (:forearm "forearm")
     (:hand "hand") (:thigh "thigh") (:shin "shin") (:foot "foot") (:toe "toe")
     (:thumb "thumb1") (:index "findex1" "fingerindex1") (:middle "fmiddle1" "fingermiddle1")
     (:ring "fring1" "fingerring1") (:pinky "fpinky1" "fingerpinky1"))
    (:biped                             ; 3ds Max Biped, after Bip01: L Calf
     (:head "head") (:neck "neck") (:hips "pelvis") (:spine-base "spine")
     (:upper-arm "upperarm") (:forearm "forearm") (:hand "hand")
     (:thigh "thigh") (:shin "calf") (:foot "foot") (:toe "toe0")
     (:thumb "finger0") (:index "finger1") (:middle "finger2") (:ring "finger3")
     (:pinky "finger4") (:tail "tail"))
    (:h-anim                            ; H-Anim joints: l_elbow, skullbase, vl5
     (:head "skullbase") (:neck "vc4" "vc7") (:hips "humanoidroot" "sacroiliac")
     (:spine-base "vl5") (:eye "eyeballjoint") (:upper-lid "eyelidjoint")
     (:brow "eyebrowjoint") (:jaw "temporomandibular")
     ;; H-Anim's shoulder is the arm's root; other schemes' shoulder is the
     ;; clavicle, which is why this scheme comes after theirs.
     (:upper-arm "shoulder") (:forearm "elbow") (:hand "wrist")
     (:thigh "hip") (:shin "knee") (:foot "ankle") (:toe "midtarsal")
     (:thumb "thumb1") (:index "index1") (:middle "middle1") (:ring "ring1") (:pinky "pinky1"))
    (:plain                             ; names people write: Arm_Left, ArmL, L_Arm
     (:head "head") (:neck "neck" "neck1") (:hips "hips" "pelvis" "root")
     (:spine-base "spine" "spine1") (:eye "eye" "eyeball")
     (:upper-lid "uppereyelid" "upperlid" "eyelid" "lid") (:brow "eyebrow" "brow")
     (:jaw "jaw" "lowerjaw" "beak") (:crest "crest") (:tail "tail" "tail1" "tail01")
     (:upper-arm "upperarm" "uparm" "arm") (:forearm "forearm" "lowerarm" "elbow")
     (:hand "hand" "wrist") (:thigh "thigh" "upperleg" "leg")
     (:shin "shin" "calf" "lowerleg" "knee") (:foot "foot" "ankle")
     (:toe "toe" "toes" "ball" "foot") (:thumb "thumb" "thumb1") (:index "index" "index1")
     (:middle "middle" "middle1") (:ring "ring" "ring1") (:pinky "pinky" "pinky1" "little")))
  "Each naming scheme, earliest first, as (SCHEME (PART NORMALISED-NAME ...) ...).
A joint whose normalised name a row lists may be that PART; the earlier its
scheme and name, the likelier.  Schemes share names (Mixamo's leg is the shin,
a plain leg the thigh): order settles it, and the chains settle the rest.")

(defparameter *spinal-names*
  '("spine" "spine1" "spine2" "spine3" "spine4" "spine5" "chest" "upperchest"
    "lowerback" "vl5" "vl4" "vl3" "vl2" "vl1" "vt12" "vt11" "vt10" "vt9" "vt8" "vt7"
    "vt6" "vt5" "vt4" "vt3" "vt2" "vt1" "vc7" "vc6" "vc5" "vc4" "vc3" "vc2" "vc1")
  "Normalised names of the joints between the spine's base and the neck, for
building the spine when no parents say how they link.")

(defun part-rank (part core)
  "How early *NAMING-SCHEMES* lists CORE as PART (0 the earliest), or NIL if never."
  (loop with rank = 0
        for (nil . rows) in *naming-schemes*
        do (loop for name in (rest (assoc part rows))
                 do (if (string= name core) (return-from part-rank rank) (incf rank)))))
