;;;; cradle.lisp -- issue 16's figures: how long (newton-cradle n) takes to
;;;; build for n = 3, 4, ... and the sizes of the graphs on the way (the merge
;;;; G17 ⊗ ... ⊗ G17, then G^n after the collision restriction).

(in-package #:player-bench)

(defparameter *cradle-sizes* '(3 4 5 6 7 8)
  "The cradles timed, smallest first.")

(defparameter *cradle-budget* 600
  "Seconds a cradle build may be expected to take: one predicted to take
longer (the last build times the growth of the one before) is not started.")

(defparameter *cradle-bytes-per-edge* 600
  "About how many bytes of heap a build needs per edge of its merge at its
peak (at n = 6 about 180 stay allocated afterwards; n = 7, 2.9 M edges,
exhausts SBCL's default 1 GB heap, so `make bench` runs with 20 GB; n = 8,
20 M edges, took 286 s and kept 5.5 GB). A build predicted to need more than 3/4 of
the heap, or more than the memory the machine has free, is not started:
running out of heap ends SBCL.")

(defun available-memory ()
  "Bytes of memory the machine has available (Linux's MemAvailable), or the
heap's size where /proc/meminfo cannot say."
  (or (ignore-errors
       (with-open-file (stream "/proc/meminfo")
         (loop for line = (read-line stream nil)
               while line
               when (eql 0 (search "MemAvailable:" line))
                 return (* 1024 (parse-integer line :start 13 :junk-allowed t)))))
      (sb-ext:dynamic-space-size)))

(defun build-cradle (n)
  "Build the paper's N-sphere cradle eagerly from nothing (the stage cache
emptied first): seconds taken. (The eager NEWTON-CRADLE builds a larger merge
again, from G^1+; the lazy rows below time it the way it is meant to be used.)"
  (clrhash player.compose::*cradle-stages*)
  (sb-ext:gc :full t)
  (let ((start (now)))
    (player:cradle-paper n)
    (- (now) start)))

(defun bench-cradle ()
  "Rows: the build time and graph sizes of (newton-cradle n) for *CRADLE-SIZES*,
stopping before a build predicted to take more than *CRADLE-BUDGET* seconds."
  (let ((previous nil) (growth 10) (edges nil) (edge-growth 10))
    (dolist (n *cradle-sizes*)
      (let ((predicted (and previous (* previous growth)))
            (bytes (and edges (* edges edge-growth *cradle-bytes-per-edge*))))
        (when (or (and predicted (> predicted *cradle-budget*))
                  (and bytes (> bytes (min (* 3/4 (sb-ext:dynamic-space-size)) (available-memory)))))
          (note "(newton-cradle ~D) not built: predicted ~D s (~,1Fx the last build; budget ~D s) and ~
                 ~,1F GB of heap (~,1Fx the last merge's edges; heap ~,1F GB, ~,1F GB free); graph expressions in ~
                 spec files stop at n = ~D (player.compose::*max-cradle-spheres*)"
                n (round predicted) growth *cradle-budget* (/ bytes 1d9) edge-growth
                (/ (sb-ext:dynamic-space-size) 1d9) (/ (available-memory) 1d9) player.compose::*max-cradle-spheres*)
          (return))
        (format t "~&  newton-cradle ~D...~%" n) (finish-output)
        (let* ((seconds (build-cradle n))
               (merged (player:cradle-stage n :merged))
               (cradle (player:cradle-paper n)))
          (when previous (setf growth (max 1 (/ seconds (max previous 1d-3)))))
          (when edges (setf edge-growth (max 1 (/ (player:graph-edge-count merged) edges))))
          (setf previous seconds
                edges (player:graph-edge-count merged))
          (row (format nil "16. (cradle-paper ~D): merge ~D nodes, ~D edges; G^~D ~D nodes, ~D edges"
                       n (player:graph-node-count merged) (player:graph-edge-count merged)
                       n (player:graph-node-count cradle) (player:graph-edge-count cradle))
               (format-seconds seconds) "-" t))))
    (clrhash player.compose::*cradle-stages*)
    (sb-ext:gc :full t)))

;;; Issue 30: the cradle built on demand, and a CTL check on it

(defun lifted-cradle-node (n left)
  "The N-sphere cradle node with LEFT spheres lifted at rest on the left."
  (apply #'player:cradle-node (append (make-list left :initial-element '(-1 . 0))
                                      (make-list (- n left) :initial-element '(0 . 0)))))

(defun bench-lazy-cradle ()
  "Rows: the reachable graph of (lazy-cradle 8) from two lifted, built on
demand from nothing, and the CTL check of deadlock-freedom on it (medians);
the same graph for n = 10, and for n = 8 from every lifted set."
  (flet ((reachable (n starts)
           ;; (newton-cradle n) is built on demand above n = 6
           (apply #'player:graph-reachable (player:newton-cradle n :lazy t) starts)))
    (let* ((start (lifted-cradle-node 8 2))
           (times (loop repeat 5
                        collect (progn (clrhash player.compose::*cradle-stages*)
                                       (let ((t0 (now))) (reachable 8 (list start)) (- (now) t0)))))
           (graph (reachable 8 (list start)))
           (bytes (let ((before (sb-ext:get-bytes-consed)))
                    (reachable 8 (list start))
                    (- (sb-ext:get-bytes-consed) before))))
      (row (format nil "30. cradle n = 8 reachable graph, lazily (2 lifted: ~D states; ~,1F MB consed)"
                   (player:graph-node-count graph) (/ bytes 1d6))
           (format-seconds (median times)) "< 5 s" (< (median times) 5))
      (let ((check (seconds-per-call (lambda () (player:verify graph '(ag (ex t)) :start start)))))
        (row "30. CTL check of deadlock-freedom on it, (AG (EX t))" (format-seconds check) "< 1 s" (< check 1)))
      (let* ((starts (loop for k from 0 to 8 collect (lifted-cradle-node 8 k)))
             (t0 (now))
             (all (reachable 8 starts))
             (seconds (- (now) t0))
             (check (seconds-per-call (lambda () (player:verify all '(ag (ex t)))) :batches 3)))
        (row (format nil "30. cradle n = 8, lazily, from 0-8 lifted on the left: ~D states" (player:graph-node-count all))
             (format-seconds seconds) "-" t)
        (row "30. CTL (AG (EX t)) on that graph" (format-seconds check) "< 1 s" (< check 1)))
      (let* ((starts (loop for k from 0 to 8 collect (lifted-cradle-node 8 k)))
             (t0 (now))
             (all (apply #'player:lazy-reachable (player:guarded-cradle 8) starts))
             (seconds (- (now) t0)))
        (row (format nil "30. same, guarded: free swing while well behaved (~D states)" (player:graph-node-count all))
             (format-seconds seconds) "-" t))
      (let* ((t0 (now))
             (ten (reachable 10 (list (lifted-cradle-node 10 3))))
             (seconds (- (now) t0)))
        (row (format nil "30. cradle n = 10 reachable graph, lazily (3 lifted: ~D states)" (player:graph-node-count ten))
             (format-seconds seconds) "possible" t)))))
