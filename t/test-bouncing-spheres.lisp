;;;; test-bouncing-spheres.lisp -- Clark & Palmer's section 2 as
;;;; specs/bouncing-spheres.lisp writes it (issue 30, item 1): the paper's
;;;; claims on its graphs, no trace through a surface, Figure 3.3's run, and
;;;; the (edge P1 P2 TEST) and (let* ...) forms of graph expressions.

(in-package #:player-tests)

(def-suite* bouncing-spheres :in player-tests)

(defun spheres-bindings ()
  "The (let* BINDINGS ...) bindings of specs/bouncing-spheres.lisp's (:graph ...) option, as read."
  (let* ((forms (with-open-file (in (checkout-file "specs/bouncing-spheres.lisp"))
                  (let ((*package* (find-package '#:player-user)) (*read-eval* nil))
                    (loop for form = (read in nil in) until (eq form in) collect form))))
         (defspec (find-if (lambda (f) (and (consp f) (string= (symbol-name (first f)) "DEFSPEC"))) forms))
         (option (find-if (lambda (f) (and (consp f) (eq (first f) :graph))) defspec)))
    (second (second option))))

(defun spheres-graph (expression)
  "The graph EXPRESSION denotes with the names the spec file binds (S1 ... S5, P1 ... P8)."
  (graph-expression `(let* ,(spheres-bindings) ,expression)))

(defun spheres-name (name)
  "NAME as the spec file's symbol."
  (intern (string-upcase name) '#:player-user))

(test spheres-paper-claims
  (flet ((g (control &rest arguments)
           (spheres-graph (let ((*package* (find-package '#:player-user)))
                            (read-from-string (apply #'format nil control arguments))))))
    ;; S1 = C(Σ): the product of complete graphs is the complete graph on Σ.
    (let ((s1 (g "s1")))
      (is (= 120 (graph-node-count s1)))
      (is (graph-equal s1 (complete-graph (graph-nodes s1)))))
    ;; S \ p \ p' = (S \ p) & (S \ p'), on the paper's graphs and statements.
    ;; Equal on S1; on S3 the same moves, and the intersection's extra states
    ;; (kept by each restriction, by no move of both) are isolated.
    (loop for (s p q) in '(("s1" "p1" "p2") ("s1" "p1" "p3") ("s1" "p2" "p3") ("s2" "p4" "p4"))
          do (is (graph-equal (g "(restrict (restrict ~A ~A) ~A)" s p q)
                              (g "(& (restrict ~A ~A) (restrict ~A ~A))" s p s q))
                 "~A \\ ~A \\ ~A" s p q))
    (loop for (s p q) in '(("s3" "p5" "p7") ("s3" "p6" "p8"))
          do (let ((nested (g "(restrict (restrict ~A ~A) ~A)" s p q))
                   (both (g "(& (restrict ~A ~A) (restrict ~A ~A))" s p s q)))
               (is (equal (graph-edges nested) (graph-edges both)) "~A \\ ~A \\ ~A" s p q)
               (is (subgraph-p nested both))
               (is (every (lambda (node) (or (graph-has-node-p nested node)
                                             (and (null (graph-successors both node))
                                                  (notany (lambda (e) (equal (cdr e) node)) (graph-edges both)))))
                          (graph-nodes both)))))
    ;; Figure 2.3, both ways the paper writes it.
    (is (graph-equal (g "(restrict (restrict (restrict s1 p1) p2) p3)") (g "s2")))
    ;; No trace passes through a surface: every place in S2 (so in S3, S4, S5)
    ;; lies between them; S1 \ p1 alone goes through.
    (flet ((rows (graph) (remove-duplicates (loop for node in (graph-nodes graph)
                                                   append (mapcar #'cdar (tree-flatten node :leafp #'player.compose::grid-sphere-p))))))
      (is (subsetp (rows (g "s2")) '(0 1 2)))
      (is (subsetp (rows (g "(+ s4 s5)")) '(0 1 2)))
      (is (intersection '(-1 3) (rows (g "(restrict s1 p1)")))))
    ;; S2 \ p4, Figure 2.6: a single sphere goes on one way, one successor each.
    (let ((single (g "(restrict s2 p4)")))
      (is (every (lambda (node) (= 1 (length (graph-successors single node)))) (graph-nodes single))))
    ;; "some animations of S4 ... will terminate prematurely since the spheres
    ;; may head towards each other and must stop before colliding"; S4 + S5 never does.
    (let ((start (cons (cons (cons 1 2) (cons 1 1)) (cons (cons 3 2) (cons -1 1)))))
      (is (not (verify (g "s4") '(ag (ex t)) :start start)))
      (is (verify (g "(+ s4 s5)") '(ag (ex t)) :start start)))))

(test spheres-figure-3-3
  ;; From the upper surface: collide, bounce, hit the lower surface, part.
  (let* ((spec (first (load-spec (checkout-file "specs/bouncing-spheres.lisp"))))
         (controller (make-controller (compile-spec spec))))
    (is (eq t (send-event controller 'ev-figure-3-3)))
    (let ((states (loop for line in (trace-lines (controller-presenter controller))
                        when (eq (first line) :op)
                          collect (let ((name (symbol-name (second line))))
                                    (player.compose::grid-name-spheres (subseq name (+ 4 (search "-TO-" name))))))))
      (is (= 3 (length states)))
      (destructuring-bind (collide lower part) states
        (is (equal (car (first collide)) (car (second collide))) "collide: ~S" collide)
        (is (equal '(0 0) (mapcar #'cdar lower)) "lower: ~S" lower)
        (is (equal '(-1 1) (mapcar #'cadr part)) "part: ~S" part)))
    (is (verify spec '(ag (ex t))))
    ;; the committed script library is what the generator writes
    (let ((file (merge-pathnames "player-spheres-scripts.lisp" (uiop:temporary-directory))))
      (player.compose::write-spheres-scripts-file spec file)
      (is (string= (alexandria:read-file-into-string file)
                   (alexandria:read-file-into-string (checkout-file "specs/bouncing-spheres-scripts.lisp"))))
      (delete-file file))))

(test edge-tests-in-graph-expressions
  ;; (edge P1 P2 TEST), not, or, let* and predicate names, as data.
  (is (= 3 (graph-edge-count (graph-expression '(restrict (complete (0 1 2)) (edge x y (= y (mod (+ x 1) 3))))))))
  (is (= 6 (graph-edge-count (graph-expression '(restrict (complete (0 1 2)) (not (edge x y (= x y))))))))
  (is (= 5 (graph-edge-count (graph-expression '(restrict (complete (0 1 2))
                                                 (or (edge x y (= x y)) (edge 0 y (> y 0))))))))
  (is (= 3 (graph-edge-count (graph-expression '(let* ((g (complete (0 1 2))) (same (predicate (edge x y (= x y)))))
                                                 (restrict g same))))))
  (flet ((fails (form word)
           (handler-case (progn (graph-expression form) (fail "~S built" form))
             (graph-expression-error (c) (is (search word (princ-to-string c)) "~A" c)))))
    (fails '(restrict (complete (0 1)) (edge x y (= z 1))) "z")
    (fails '(restrict (complete (0 1)) (edge x y (launch x))) "launch")
    (fails '(restrict (complete (0 1)) (edge x y (= (run-program x) 1))) "run-program")
    (fails '(let* ((g)) g) "let*")))
