;;;; friction.lisp -- a cradle that slows and comes to rest: the paper's
;;;; "decelerating components".
;;;;
;;;; Clark & Palmer (§5) propose "a Newton's Cradle behaviour which deals with
;;;; friction (possibly by extending the state components with extra
;;;; decelerating components)". The component here is the swing's energy, an
;;;; integer from ENERGY down to 0, in a graph D where it stays or drops by
;;;; one. The cradle with friction is built as the paper builds behaviours:
;;;;   F = (G^n × D) \ decelerates + stopping
;;;; decelerates: the energy drops by one exactly when the spheres turn back at
;;;; an extreme (a half swing done), and at energy 0 no collision happens;
;;;; stopping: at energy 0, spheres all hanging at the bottom stop there. So
;;;; every swing is lower than the last (drawn scaled by the energy, see
;;;; FRICTION-AMPLITUDE) and the cradle comes to rest, whatever was lifted.
;;;; Built on demand (lazy.lisp): the nodes are (CRADLE-NODE . ENERGY).

(in-package #:player.compose)

(defun energy-graph (energy)
  "D: the energies 0 ... ENERGY, each staying or dropping by one."
  (make-graph (loop for e from 0 to energy collect e)
              (loop for e from 0 to energy
                    collect (cons e e)
                    when (plusp e) collect (cons e (1- e)))))

(defun turns-back-p (source target)
  "Does some sphere fall back from an extreme in the cradle move SOURCE -> TARGET?"
  (some (lambda (a b) (and (/= 0 (car a)) (= 0 (cdr a)) (= (cdr b) (- (car a)))))
        (cradle-spheres source) (cradle-spheres target)))

(defun at-bottom-p (node)
  "Are all the spheres of the cradle NODE hanging at position 0?"
  (every (lambda (sphere) (zerop (car sphere))) (cradle-spheres node)))

(defun decelerates-p (source target)
  "The restriction on (CRADLE . ENERGY) moves: energy lost exactly at a turn
back, and no collision once it is spent."
  (destructuring-bind (c . e) source
    (destructuring-bind (c2 . e2) target
      (and (= e2 (if (turns-back-p c c2) (1- e) e))
           (not (and (zerop e) (at-bottom-p c) (not (equal c c2))))))))

(defun friction-cradle (n &key (energy 3))
  "The N-sphere cradle with friction, a LAZY-GRAPH on (CRADLE-NODE . E), E the
swing's energy from ENERGY down to 0 (see the file header): it slows and
comes to rest. An ARGUMENT-ERROR for a bad N or ENERGY."
  (check-argument 'friction-cradle :energy energy (lambda (x) (typep x '(integer 1 100))) "an integer from 1 to 100")
  (let* ((rest (cradle-start n))
         (moving (lazy-restrict (lazy-product (lazy-cradle n) (energy-graph energy)) #'decelerates-p))
         (stopping (make-lazy-graph (lambda (node)
                                      (destructuring-bind (c . e) node
                                        (and (zerop e) (at-bottom-p c) (not (equal c rest))
                                             (list (cons rest 0)))))
                                    :description "stopping")))
    (lazy-sum moving stopping)))

(defun friction-amplitude (node energy)
  "How far the spheres of the friction cradle's NODE (CRADLE . E) swing, as a
fraction of a full swing: E over the starting ENERGY, for drawing."
  (/ (cdr node) energy))
