;;;; bouncing-spheres.lisp -- Clark & Palmer's first example (section 2): two
;;;; spheres bouncing between two horizontal surfaces, built as the paper
;;;; builds it, with the algebra of transition systems as data.
;;;;
;;;; A sphere's state is ((X . Y) . (DX . DY)): its place on a grid and the
;;;; move that brought it there, one step diagonally (DX, DY each -1 or 1).
;;;; The lower surface is the row Y = 0, the upper Y = 2; Σ has a row beyond
;;;; each (Y = -1 and Y = 3), so the unconstrained sphere can go through them.
;;;; X runs round from 5 back to 0: the paper's surfaces have no ends, and a
;;;; finite grid needs none either.
;;;;
;;;;   S1 = C(Σ), made as C(X) × C(Y) × (C(DX) × C(DY)): a product of complete
;;;;        graphs is the complete graph on the tuples
;;;;   p1   moves of a constant distance: one diagonal step, by the new velocity
;;;;   p2   bounces at the upper surface: never above it (before or after the
;;;;        move: a move from beyond a surface has passed through it), turning
;;;;        down there
;;;;   p3   bounces at the lower surface: never below it, turning up there
;;;;   S2 = (S1 \ p1 \ p2) & (S1 \ p1 \ p3)          the paper's Figure 2.3
;;;;   p4   no zig-zag: the sideways motion is kept, the vertical one too
;;;;        except where a surface turns it (S2 \ p4 is Figure 2.6)
;;;;   S3 = S2 × S2                                   two spheres
;;;;   p5   moves that never collide (nor pass through each other); p6 moves
;;;;        to or from a collision (both spheres in one place)
;;;;   p7   moves in which neither sphere zig-zags; p8 collisions that bounce:
;;;;        out of a collision the spheres exchange their sideways motion
;;;;   S4 = S3 \ p5 \ p7,  S5 = S3 \ p6 \ p8,  and the behaviour S4 + S5
;;;;
;;;; [Reading] The paper's p8 is "the opposite of p7" (some sphere zig-zags).
;;;; Taken literally, S5 has no move into a collision (those zig-zag no
;;;; sphere) and S4 none either (they collide), so spheres could never meet;
;;;; p8 here lets a move into a collision go straight on and makes the move
;;;; out of it the bounce. p6 is the opposite of p5 but for moves in which
;;;; the spheres pass through each other, which neither keeps.
;;;;
;;;; [Reading] "S \ p \ p' = (S \ p) & (S \ p')" holds of the moves; of the
;;;; states only where every state kept by both restrictions is the end of a
;;;; move satisfying both. On S3 with p5, p7 (and p6, p8) the intersection keeps
;;;; a few states no move of it reaches or leaves (a restriction keeps the ends
;;;; of its moves, an intersection the states both keep): the same behaviour,
;;;; plus isolated states (t/test-bouncing-spheres.lisp).
;;;;
;;;; ev-figure-3-3 plays the paper's Figure 3.3: "the spheres start at the
;;;; upper horizontal, collide, bounce off each other, hit the lower
;;;; horizontal and finally bounce off in opposite directions".
;;;; Draw it: make demo-spheres. Prove things about it: bin/player verify-graph.

(in-package :player-user)

(defspec bouncing-spheres
  "Two spheres bouncing between two horizontal surfaces (Clark & Palmer, 1995, section 2): S4 + S5, from the upper surface."
  (:scripts "bouncing-spheres-scripts.lisp")
  (:body none)
  (:graph
   (let* ((s1 (product (product (complete (0 1 2 3 4 5)) (complete (-1 0 1 2 3)))
                       (product (complete (-1 1)) (complete (-1 1)))))
          (p1 (predicate (edge ((x . y) . _) ((x2 . y2) . (dx . dy))
                               (and (= x2 (mod (+ x dx) 6)) (= y2 (+ y dy))))))
          (p2 (predicate (edge ((x . y) . _) ((x2 . y2) . (dx . dy))
                               (and (<= y 2) (<= y2 2) (implies (= y 2) (= dy -1))))))
          (p3 (predicate (edge ((x . y) . _) ((x2 . y2) . (dx . dy))
                               (and (>= y 0) (>= y2 0) (implies (= y 0) (= dy 1))))))
          (s2 (& (restrict (restrict s1 p1) p2) (restrict (restrict s1 p1) p3)))
          (p4 (predicate (edge ((x . y) . (dx . dy)) (_ . (dx2 . dy2))
                               (and (= dx2 dx) (or (= dy2 dy) (= y 0) (= y 2))))))
          (s3 (product s2 s2))
          (p5 (predicate (edge ((a . _) . (b . _)) ((a2 . _) . (b2 . _))
                               (not (or (equal a b) (equal a2 b2) (and (equal a2 b) (equal b2 a)))))))
          (p6 (predicate (edge ((a . _) . (b . _)) ((a2 . _) . (b2 . _))
                               (or (equal a b) (equal a2 b2)))))
          (p7 (predicate (edge (((x . y) . (dx . dy)) . ((u . v) . (du . dv)))
                               ((_ . (dx2 . dy2)) . (_ . (du2 . dv2)))
                               (and (= dx2 dx) (or (= dy2 dy) (= y 0) (= y 2))
                                    (= du2 du) (or (= dv2 dv) (= v 0) (= v 2))))))
          (p8 (predicate (edge (((x . y) . (dx . dy)) . ((u . v) . (du . dv)))
                               ((_ . (dx2 . dy2)) . (_ . (du2 . dv2)))
                               (and (or (= dy2 dy) (= y 0) (= y 2)) (or (= dv2 dv) (= v 0) (= v 2))
                                    ;; out of a collision: the sideways motions exchanged
                                    (implies (and (= x u) (= y v)) (and (= dx2 du) (= du2 dx)))
                                    ;; into one: straight on
                                    (implies (not (and (= x u) (= y v))) (and (= dx2 dx) (= du2 du)))))))
          (s4 (restrict (restrict s3 p5) p7))
          (s5 (restrict (restrict s3 p6) p8)))
     (reachable (+ s4 s5) (((1 . 2) . (1 . 1)) . ((3 . 2) . (-1 . 1)))))
   :start (((1 . 2) . (1 . 1)) . ((3 . 2) . (-1 . 1)))
   :variable spheres :go-events false)
  (event ev-figure-3-3 :state spheres.x0y1nw-x4y1ne))
