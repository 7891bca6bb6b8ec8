;;;; test-friction.lisp -- the cradle with friction (src/compose/friction.lisp,
;;;; issue 30 item 5): decelerating components make it slow and come to rest.

(in-package #:player-tests)

(def-suite* friction :in player-tests)

(test friction-comes-to-rest
  ;; From every lifted set of up to 5 spheres, with energy 1 to 3: the cradle
  ;; is never stuck, always comes to rest (AF rest, model-checked), its energy
  ;; never grows, and it loses one unit per half swing.
  (loop for n from 2 to 5
        do (loop for energy from 1 to 3
                 do (let ((graph (friction-cradle n :energy energy))
                          (rest (cons (cradle-start n) 0)))
                      (loop for left from 0 to n
                            do (loop for right from 0 to (- n left)
                                     unless (= 0 left right)
                                       do (let ((start (cons (cradle-start n :left left :right right) energy)))
                                            (is (verify graph `(af (match ,rest)) :start start)
                                                "~D spheres, ~D/~D lifted, energy ~D" n left right energy)
                                            (is (verify graph '(ag (ex t)) :start start))
                                            (let ((reached (lazy-reachable graph start)))
                                              (is (every (lambda (edge) (<= (cdr (cdr edge)) (cdr (car edge))))
                                                         (graph-edges reached))))))))))
  ;; the run of two lifted with energy 2: swings lower each time, then rests
  (let* ((graph (friction-cradle 5 :energy 2))
         (run (loop for node = (cons (cradle-start 5 :left 2) 2) then (first (lazy-successors graph node))
                    repeat 30 collect node))
         (amplitudes (mapcar (lambda (node) (friction-amplitude node 2)) run)))
    (is (apply #'>= amplitudes))
    (is (equal (cons (cradle-start 5) 0) (car (last run))))
    (is (= 2 (count-if (lambda (pair) (player.compose::turns-back-p (car (first pair)) (car (second pair))))
                       (loop for (a b) on run while b collect (list a b))))))
  (signals argument-error (friction-cradle 3 :energy 0)))
