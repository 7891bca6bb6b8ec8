;;;; roles.lisp -- guessing an imported skeleton's roles (issue 26, item 3):
;;;; which joint is the head, which chain the left arm, from the parts its
;;;; joints' names say they are (naming-schemes.lisp), so the drivers find them.
;;;;
;;;; The parts make Player's roles (*SKELETON-ROLES* in src/body/skeleton.lisp),
;;;; the chains by the parent links when those are known.  A name no scheme lists
;;;; is no part: no role is better than a wrong one.  What the roles then enable
;;;; is in driver-needs.lisp.

(in-package #:player.model)

;;; ---------------------------------------------------------------------------
;;; Conditions

(define-condition role-error (player-error)
  ((role :initarg :role :reader role-error-role
         :documentation "The role whose joint is missing.")
   (joint :initarg :joint :reader role-error-joint
          :documentation "The joint name given for it, which the skeleton lacks."))
  (:report (lambda (condition stream)
             (format stream "role ~S names the joint ~S, which the skeleton does not have"
                     (role-error-role condition) (role-error-joint condition))))
  (:documentation "An explicit role names a joint that is not in the skeleton."))

;;; ---------------------------------------------------------------------------
;;; A skeleton's joints as the guesser sees them

(defstruct (named-joint (:constructor make-named-joint (index name core side depth)))
  "One joint of the skeleton being guessed: its position, name and normalised name."
  (index 0 :type fixnum :read-only t)
  (name "" :type string :read-only t)
  (core nil :read-only t)
  (side nil :read-only t)
  (depth 0 :type fixnum :read-only t))

(defun joint-depth (index parents)
  "How many parent links lead from joint INDEX to its root, given PARENTS (or 0 without)."
  (if (null parents)
      0
      (loop for joint = (aref parents index) then (aref parents joint)
            for depth from 0 to (length parents) ; bounded, should PARENTS loop
            while (and (integerp joint) (>= joint 0))
            finally (return depth))))

(defun descendant-p (joint ancestor parents)
  "Is JOINT (an index) below ANCESTOR in PARENTS?  Without PARENTS: does JOINT come
after ANCESTOR, as importers list a parent before its children?"
  (if (null parents)
      (> joint ancestor)
      (loop for current = (aref parents joint) then (aref parents current)
            repeat (length parents)
            while (and (integerp current) (>= current 0))
            thereis (= current ancestor))))

(defun part-candidates (part joints side &key anchor parents)
  "The joints of JOINTS that may be PART on SIDE, likeliest first: by their rank in
*NAMING-SCHEMES*, then below ANCHOR (an index or NIL), then nearer the root."
  (flet ((key (joint)
           (list (part-rank part (named-joint-core joint))
                 (if (and anchor (descendant-p (named-joint-index joint) anchor parents)) 0 1)
                 (named-joint-depth joint)
                 (named-joint-index joint))))
    (let ((matches (remove-if-not (lambda (joint)
                                    (and (named-joint-core joint)
                                         (eq (named-joint-side joint) side)
                                         (part-rank part (named-joint-core joint))))
                                  joints)))
      (sort matches (lambda (a b) (key< (key a) (key b)))))))

(defun key< (a b)
  "Is the list of integers A before B, element by element?"
  (loop for x in a for y in b
        when (< x y) return t
        when (> x y) return nil))

(defun best-part (part joints side &key anchor parents)
  "The index of the likeliest joint for PART on SIDE, or NIL."
  (let ((best (first (part-candidates part joints side :anchor anchor :parents parents))))
    (and best (named-joint-index best))))

(defun find-chain (parts joints side parents &key (required (length parts)))
  "Indices of a joint for each of PARTS on SIDE, each below the one before (when
PARENTS are known), the likeliest such chain, a whole one if there is one; else
the first REQUIRED parts with what follows them.  NIL when no chain exists."
  (labels ((extend (parts previous found required)
             (if (null parts)
                 (reverse found)
                 (or (loop for joint in (part-candidates (first parts) joints side :anchor previous
                                                                                 :parents parents)
                           for index = (named-joint-index joint)
                           when (and (not (member index found))
                                     (or (null previous) (descendant-p index previous parents)))
                             do (let ((chain (extend (rest parts) index (cons index found) required)))
                                  (when chain (return chain))))
                     (and (>= (length found) required) (reverse found))))))
    ;; A whole chain first: a bird's ankle then foot beats its foot alone.
    (or (extend parts nil '() (length parts))
        (extend parts nil '() required))))

;;; ---------------------------------------------------------------------------
;;; Roles from parts

(defparameter *single-roles*
  '((:neck :neck nil nil) (:head :head nil :neck) (:hips :hips nil nil)
    (:left-eye :eye :left :head) (:right-eye :eye :right :head)
    (:left-upper-lid :upper-lid :left :head) (:right-upper-lid :upper-lid :right :head)
    (:left-brow :brow :left :head) (:right-brow :brow :right :head)
    (:jaw :jaw nil :head) (:crest :crest nil :head) (:tail :tail nil :hips))
  "Roles of one joint: (ROLE PART SIDE ANCHOR-ROLE), the joint preferred below the
ANCHOR-ROLE's joint (a row above) when names tie.  :NECK and :HIPS are roles
Player's own skeletons do not declare; imported rigs have them and the head and
facing drivers want them.")

(defparameter *chain-roles*
  '((:left-arm (:upper-arm :forearm :hand) :left 3)
    (:right-arm (:upper-arm :forearm :hand) :right 3)
    (:left-leg (:thigh :shin :foot :toe) :left 3)
    (:right-leg (:thigh :shin :foot :toe) :right 3))
  "Chain roles: (ROLE PARTS SIDE REQUIRED), each part below the one before; the
first REQUIRED parts must all be there (a leg's toe may be missing).")

(defparameter *finger-parts* '(:thumb :index :middle :ring :pinky)
  "The fingers' first joints, in the order of a :left-fingers set: thumb first.")

(defun guess-single-roles (joints parents)
  "An alist of the guessed one-joint roles (*SINGLE-ROLES*) of JOINTS."
  (let ((roles '()))
    (loop for (role part side anchor-role) in *single-roles*
          for anchor = (cdr (assoc anchor-role roles))
          for index = (best-part part joints side :anchor anchor :parents parents)
          when index do (push (cons role index) roles))
    (nreverse roles)))

(defun with-root-as-hips (roles parents)
  "ROLES, with the skeleton's one root as :HIPS when no name gave the hips: the
facing driver turns the whole figure by its root, whatever it is called."
  (let ((root (root-joint parents)))
    (if (or (assoc :hips roles) (null root))
        roles
        (append roles (list (cons :hips root))))))

(defun guess-chain-roles (joints parents)
  "An alist of the guessed limb chains (*CHAIN-ROLES*) of JOINTS."
  (loop for (role parts side required) in *chain-roles*
        for chain = (find-chain parts joints side parents :required required)
        when chain collect (cons role chain)))

(defun guess-hand (side chains joints parents)
  "The index of SIDE's hand: the end of its arm chain in CHAINS, else the likeliest hand."
  (let ((arm (cdr (assoc (if (eq side :left) :left-arm :right-arm) chains))))
    (if arm
        (car (last arm))
        (best-part :hand joints side :parents parents))))

(defun guess-fingers (side hand joints parents)
  "The indices of SIDE's fingers' first joints, thumb first, below HAND when known.
A finger's first joint is never below another finger's: in a .x file Finger2 may
be the second joint of Finger1, not Biped's middle finger."
  (let ((fingers '()))
    (dolist (part *finger-parts* (nreverse fingers))
      (let ((best (find-if (lambda (joint)
                             (let ((index (named-joint-index joint)))
                               (and (or (null hand) (descendant-p index hand parents))
                                    (notany (lambda (finger)
                                              (and parents (descendant-p index finger parents)))
                                            fingers))))
                           (part-candidates part joints side :anchor hand :parents parents))))
        (when best (push (named-joint-index best) fingers))))))

(defun spinal-joint-p (joint)
  "Is JOINT named as a vertebra or spine segment (*SPINAL-NAMES*)?"
  (member (named-joint-core joint) *spinal-names* :test #'equal))

(defun spine-base (joints parents top neck)
  "The index of the spine's lowest joint below TOP: the likeliest spine base, else
the neck when TOP is a head above it (a bird's spine is its neck); or NIL."
  (let ((base (find-if (lambda (joint) (descendant-p top (named-joint-index joint) parents))
                       (part-candidates :spine-base joints nil :parents parents))))
    (cond (base (named-joint-index base))
          ((and neck (/= neck top) (descendant-p top neck parents)) neck))))

(defun spine-path (joints parents base top neck)
  "The indices from BASE up to TOP: through the parent links when known, else
through the joints between them named as vertebrae, then NECK."
  (if parents
      (nreverse (loop for joint = top then (aref parents joint)
                      collect joint
                      until (= joint base)))
      (append (list base)
              (loop for joint in joints
                    for index = (named-joint-index joint)
                    when (and (< base index top) (not (eql index neck)) (spinal-joint-p joint))
                      collect index)
              (and neck (< base neck top) (list neck))
              (list top))))

(defun guess-spine (joints parents head neck)
  "The spine chain, from its lowest joint up to the head (or the neck when there is
no head), or NIL."
  (let* ((top (or head neck))
         (base (and top (spine-base joints parents top neck))))
    (and base (spine-path joints parents base top neck))))

(defun root-joint (parents)
  "The index of the one root in PARENTS, or NIL when there are none, several, or no PARENTS."
  (and parents
       (= 1 (count -1 parents))
       (position -1 parents)))

(defun named-joints (joint-names parents)
  "JOINT-NAMES (a sequence of strings) as a list of NAMED-JOINTs."
  (loop for name across (coerce joint-names 'vector)
        for index from 0
        collect (multiple-value-bind (core side) (normalised-joint-name name)
                  (make-named-joint index name core side (joint-depth index parents)))))

;;; ---------------------------------------------------------------------------
;;; Explicit roles

(defun joint-index (name joint-names role)
  "The index of the joint NAME in JOINT-NAMES (exact, else ignoring case); a
ROLE-ERROR naming ROLE when there is none."
  (let ((names (coerce joint-names 'list)))
    (or (position name names :test #'equal)
        (position name names :test #'string-equal)
        (error 'role-error :role role :joint name))))

(defun explicit-role-target (role target joint-names)
  "The index (TARGET a string) or indices (a list of strings) TARGET names for ROLE."
  (if (listp target)
      (mapcar (lambda (name) (joint-index name joint-names role)) target)
      (joint-index target joint-names role)))

(defun merge-explicit-roles (guessed explicit joint-names)
  "GUESSED with every role of EXPLICIT (an alist ROLE -> name or names) replaced."
  (let ((resolved (loop for (role . target) in explicit
                        collect (cons role (explicit-role-target role target joint-names)))))
    (append (remove-if (lambda (entry) (assoc (car entry) resolved)) guessed)
            resolved)))

;;; ---------------------------------------------------------------------------
;;; The entry point

(defun guess-roles (joint-names &key parents explicit)
  "An alist from Player's role keywords to joint indices, guessed from the names of
an imported skeleton's joints.  JOINT-NAMES is a vector of strings, the joints in
order; PARENTS, when given, a vector of each joint's parent index (-1 for a
root), used to keep chains linked (the elbow below the shoulder) and to break
ties.  The roles are *SKELETON-ROLES*' (src/body/skeleton.lisp) and :NECK and
:HIPS; with PARENTS and no joint named as hips, the one root is the :HIPS.  A
chain role (:left-arm, :right-leg, :spine) or a set (:left-fingers) maps to a
list of indices, root end first; any other role to one index.  EXPLICIT, an alist from a role to a joint name or a list of names, wins over the
guesses; a name it gives that is not a joint signals a ROLE-ERROR."
  (let* ((parents (and parents (coerce parents 'vector)))
         (joints (named-joints joint-names parents))
         (singles (with-root-as-hips (guess-single-roles joints parents) parents))
         (chains (guess-chain-roles joints parents))
         (hands (loop for (role side) in '((:left-hand :left) (:right-hand :right))
                      for hand = (guess-hand side chains joints parents)
                      when hand collect (cons role hand)))
         (fingers (loop for (role side hand-role) in '((:left-fingers :left :left-hand)
                                                       (:right-fingers :right :right-hand))
                        for fingers = (guess-fingers side (cdr (assoc hand-role hands))
                                                     joints parents)
                        when fingers collect (cons role fingers)))
         (spine (guess-spine joints parents (cdr (assoc :head singles))
                             (cdr (assoc :neck singles)))))
    (merge-explicit-roles (append singles chains hands fingers
                                  (and spine (list (cons :spine spine))))
                          explicit joint-names)))
