;;;; test-speed-limits.lisp -- no joint turns faster than its maximum speed
;;;; (issue 29, item 6): a cut never snaps a joint, a skeleton file overrides
;;;; the defaults, and no frame of `make demo`'s scenario breaks a limit.

(in-package #:player-tests)

(def-suite* speed-limits :in player-tests)

(defun elbow-limit (skeleton)
  "The maximum speed (deg/s) of SKELETON's left elbow flexion."
  (aref (player.body::skeleton-speed-limits skeleton)
        (player::dof-index skeleton 'l_elbow :x)))

(test a-cut-never-snaps-a-joint
  ;; A driver asked for :blend 0 would jump the elbow 90 degrees at once.
  (let* ((body (player::make-body 'bob 'humanoid))
         (limit (elbow-limit (player::body-skeleton body)))
         (elbow (player::dof-index (player::body-skeleton body) 'l_elbow :x)))
    (player::body-add-driver
     body (player::make-driver (player::parse-motor-frame
                                '(:test-constant :joint l_elbow :dof :x :angle -90 :blend 0))
                               body 1))
    (is (= 0 (aref (player::body-evaluate body 0.5) elbow)))
    (let ((angle (aref (player::body-evaluate body 1.01) elbow)))
      (is (< (abs (- angle (* -0.01 limit))) 1d-3) "0.01 s after the cut the elbow has turned ~A" angle))
    (is (= -90 (aref (player::body-evaluate body (+ 1.01 (/ 90 limit))) elbow))
        "it gets there as fast as the joint can")
    (let ((player.body::*speed-limits-enabled* nil)
          (body (player::make-body 'ann 'humanoid)))
      (player::body-add-driver
       body (player::make-driver (player::parse-motor-frame
                                  '(:test-constant :joint l_elbow :dof :x :angle -90 :blend 0))
                                 body 1))
      (player::body-evaluate body 0.5)
      (is (= -90 (aref (player::body-evaluate body 1.01) elbow)) "without limits it snaps"))))

(test skeleton-files-override-speed-limits
  (let* ((form (with-open-file (in (merge-pathnames "humanoid.lisp" player.body::*shipped-skeletons-directory*))
                 (let ((*read-eval* nil) (*package* (find-package '#:player-user))) (read in))))
         (skeleton (player.body::parse-skeleton
                    (append form (list (list :speed-limits
                                             (list (intern "L_ELBOW" '#:player-user) 100)
                                             (list (intern "R_ELBOW" '#:player-user) :x 50)))))))
    (is (= 100 (elbow-limit skeleton)))
    (is (= 50 (aref (player.body::skeleton-speed-limits skeleton)
                    (player::dof-index skeleton 'r_elbow :x))))
    (is (= 1500 (elbow-limit (player::load-skeleton 'humanoid))) "the default, from human data")
    (signals player::skeleton-error
      (player.body::parse-skeleton (append form '((:speed-limits (l_elbow -5))))))
    (signals player::skeleton-error
      (player.body::skeleton-speed-limits
       (player.body::parse-skeleton (append form (list (list :speed-limits (list (intern "NO-SUCH-JOINT" '#:player-user) 5)))))))))

(test demo-frames-keep-every-speed-limit
  ;; `make demo`'s scenario, simulated (not rendered), at its 30 fps.
  (let* ((spec (first (load-spec (checkout-file "specs/peedy.lisp"))))
         (simulation (player::simulate spec :initial '((alert . snore) (posture . sit))
                                            :events '(ev-search ev-search ev-bad-speech ev-thanks)
                                            :silent t :stream nil))
         (limits nil) (previous nil) (previous-time 0d0) (worst 0d0) (frames 0))
    (player::map-simulation-frames
     (lambda (index time scene)
       (declare (ignore index))
       (let* ((body (find-if (lambda (o) (typep o 'player::body)) (player::scene-objects scene)))
              (pose (player::body-pose body)))
         (unless limits (setf limits (player.body::skeleton-speed-limits (player::body-skeleton body))))
         (when previous
           (loop for i below (length limits)
                 for speed = (/ (abs (- (aref pose i) (aref previous i))) (- time previous-time))
                 do (setf worst (max worst (/ speed (aref limits i))))))
         (setf previous (copy-seq pose) previous-time time)
         (incf frames)))
     simulation)
    (is (> frames 100))
    (is (<= worst (+ 1 1d-9)) "a joint turned at ~,2F times its maximum speed" worst)))
