;;;; driver-needs.lisp -- which drivers an imported skeleton's roles
;;;; (roles.lisp) and morph targets enable, and what a disabled one lacks.

(in-package #:player.model)

;;; ---------------------------------------------------------------------------
;;; What the roles enable

(defparameter *driver-needs*
  '((:gaze :any :left-eye :right-eye :head)
    (:head :all :head :neck)
    (:facing :any :hips)
    (:reach :any :left-arm :right-arm)
    (:visemes :any :jaw :mouth-morphs)
    (:blink :any :left-upper-lid :right-upper-lid :blink-morphs))
  "What each driver needs: (DRIVER :ANY ROLE ...) wants one of the ROLEs, (DRIVER
:ALL ROLE ...) every one.  :MOUTH-MORPHS and :BLINK-MORPHS stand for morph
targets that do the job without a joint (see MORPH-ROLES).")

(defparameter *morph-roles*
  '((:mouth-morphs "viseme" "jawopen" "mouthopen" "aa" "ih" "ou" "ee" "oh" "a" "i" "u" "e" "o")
    (:blink-morphs "blink" "eyeblink" "eyesclosed" "eyeclose"))
  "Normalised morph-target names (Oculus visemes viseme_aa, ARKit jawOpen and
eyeBlink_L, VRM's A I U E O and Blink) that stand in for a role: a morph serves
when its normalised name starts with one of the longer ones (viseme_aa) or is a
vowel.")

(defun morph-serves-p (core names)
  "Does the normalised morph name CORE match NAMES: equal to one, or starting with
one of more than two letters?"
  (some (lambda (name)
          (or (string= core name)
              (and (> (length name) 2) (<= (length name) (length core))
                   (string= name core :end2 (length name)))))
        names))

(defun morph-roles (morphs)
  "The pseudo-roles (*MORPH-ROLES*) the morph target names MORPHS fill."
  (loop for (role . names) in *morph-roles*
        when (some (lambda (morph)
                     (let ((core (normalised-joint-name morph)))
                       (and core (morph-serves-p core names))))
                   morphs)
          collect role))

(defun roles-enabling-drivers (roles &key morphs)
  "Which drivers ROLES (an alist from GUESS-ROLES) enable.  Two values: the enabled
drivers' keywords, and an alist from each disabled driver to the roles it lacks
(for a driver that wants any of several, all of them).  MORPHS, a list of morph
target names, may stand in for the jaw (visemes) or the lids (blinks)."
  (let ((filled (append (mapcar #'car roles) (morph-roles morphs)))
        (enabled '()) (disabled '()))
    (loop for (driver kind . needed) in *driver-needs*
          for missing = (remove-if (lambda (role) (member role filled)) needed)
          do (if (if (eq kind :all) (null missing) (< (length missing) (length needed)))
                 (push driver enabled)
                 (push (cons driver missing) disabled)))
    (values (nreverse enabled) (nreverse disabled))))
