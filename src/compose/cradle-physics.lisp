;;;; cradle-physics.lisp -- the cradle that never gets stuck: one reading added
;;;; to the paper's single sphere, and one restriction after its collisions.
;;;;
;;;; The paper's G^n (stage :PAPER) has dead ends: with 2 of 5 spheres lifted,
;;;; 4 of its 20 reachable states have no successor. Two things cause them.
;;;;
;;;; 1. In G^1 a sphere moving at 0 must move on, stop or turn: it cannot stay
;;;;    at 0 and keep its velocity. But in a real cradle the middle spheres of
;;;;    a collision do exactly that: two spheres moving left into one at rest,
;;;;    [0,0][0,-1][0,-1], end as [0,-1][0,-1][0,0] -- the middle sphere passes
;;;;    the momentum on and keeps its velocity. [Reading] G18, "a sphere at 0
;;;;    passes the momentum on", (0, x) -> (0, x) for x /= 0, is added:
;;;;    G^1+ = G^1 + G18; G17+ is G17 built from it.
;;;;
;;;; 2. The paper's collision rule lets a change at 0 pair with any sphere on
;;;;    the far side, so momentum may jump to an inner sphere that is then
;;;;    blocked (CS-CS-CE-CE-CS after CE-CE-CS-CS-CS), and G18's loop would let
;;;;    a lone moving sphere hover at 0. The paper's text says how a cradle
;;;;    behaves ("We assume that the reader is familiar with the behaviour of
;;;;    Newton's Cradle"): collisions of equal spheres exchange velocities
;;;;    pair by pair. [Reading] One more restriction, applied after the
;;;;    collision restriction as the paper applies its own after the merge:
;;;;    RESOLVED -- an edge keeps a contact block (a run of neighbouring
;;;;    spheres at 0) whose velocities approach each other (a left neighbour
;;;;    faster to the right than its right neighbour) only by exchanging them
;;;;    until none approach, which sorts them; every other sphere swings
;;;;    freely. Each state then has exactly one successor, the one the
;;;;    physics gives, and nothing stops: the cradle is at rest only when
;;;;    every sphere is.
;;;;
;;;; G^n = (G17+ ⊗ ... ⊗ G17+) \ (samechanges & causesleftright & causesrightleft) \ resolved.

(in-package #:player.compose)

(defun free-swing (sphere)
  "The state the lone SPHERE (POSITION . VELOCITY) swings to in one step: on
by its velocity, stopping at an extreme, then turning back; at rest at 0 it
stays."
  (destructuring-bind (p . v) sphere
    (cond ((and (/= v 0) (<= -1 (+ p v) 1)) (cons (+ p v) v))
          ((/= v 0) (cons p 0))            ; at an extreme, moving out: stop
          ((/= p 0) (cons p (- p)))        ; stopped at an extreme: fall back
          (t (cons 0 0)))))

(defun contact-blocks (spheres)
  "The runs of neighbouring spheres at position 0 in SPHERES (a list), as
lists of (START . END) indexes, END exclusive."
  (let ((blocks '()) (start nil))
    (loop for (p) in spheres
          for i from 0
          do (cond ((and (= p 0) (null start)) (setf start i))
                   ((and (/= p 0) start) (push (cons start i) blocks) (setf start nil))))
    (when start (push (cons start (length spheres)) blocks))
    (nreverse blocks)))

(defun approaching-p (velocities)
  "Do two neighbours in VELOCITIES (a list) approach each other: the left one
faster to the right than the right one?"
  (loop for (a b) on velocities while b thereis (> a b)))

(defun physical-successor (spheres)
  "The sphere states SPHERES (a list, leftmost first) one step later: each
contact block whose velocities approach exchanges them pair by pair until
none approach (which sorts them, ascending), the other spheres swing freely."
  (let ((next (mapcar #'free-swing spheres))
        (vector (coerce spheres 'simple-vector)))
    (loop for (start . end) in (contact-blocks spheres)
          for velocities = (loop for i from start below end collect (cdr (svref vector i)))
          when (approaching-p velocities)
            do (loop for v in (sort (copy-list velocities) #'<)
                     for i from start
                     do (setf (nth i next) (cons 0 v))))
    next))

(defun resolved-predicate ()
  "RESOLVED: the edges from a cradle node to the node the physics gives."
  (make-edge-predicate
   (lambda (source target)
     (equal (cradle-spheres target) (physical-successor (cradle-spheres source))))
   "resolved"))

(defun transmit-stage (g4)
  "G18 = G4 \\ (0, x) then (0, x), x /= 0: a sphere at 0 keeps its velocity
without moving, as the middle spheres of a collision do."
  (restrict g4 (pred-and (pred-edge '(0 . x) '(0 . x))
                         (lambda (source target) (declare (ignore target)) (/= 0 (cdr source))))))

(defun physics-single-stages (single)
  "The stages the physical cradle adds to the single sphere's alist SINGLE:
:G18 and :G^1+ = G^1 + G18."
  (let* ((g18 (transmit-stage (cdr (assoc :g4 single))))
         (g^1+ (graph-sum (cdr (assoc :g^1 single)) g18)))
    (list (cons :g18 g18) (cons :g^1+ g^1+))))
