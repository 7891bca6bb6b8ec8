;;;; test-scene-set.lisp -- scenes share one set (issue 27, item 5): the
;;;; props, camera and lights of a scene are drawn once, at the scene's
;;;; origin, from the first member's library; members bring their bodies and
;;;; their own props (what their scripts carry, and what hangs from them),
;;;; side by side and framed together.  Scenes, ensembles,
;;;; dialogues and conversations print on one line at the REPL.

(in-package #:player-tests)

(def-suite* scene-set :in player-tests)

(defun anim-duet ()
  "A scene of two members of the anim fixture, ANIM1 and ANIM2, in a row."
  (player.cast:replicate-cast (first (load-spec (fixture "anim.lisp"))) 2))

(defun objects-named (scene name)
  "SCENE's visible objects called NAME."
  (remove-if-not (lambda (object) (and (string-equal (string (player.body:object-name object)) name)
                                       (player.body:property-value object 'player.body:visible)))
                 (player.body:scene-objects scene)))

(test scene-draws-one-set
  (let* ((cast (anim-duet))
         (simulation (player.cast:simulate-scene cast :events '("anim2/ev-pick") :fps 10))
         (start (player.performance:simulation-scene-at simulation 0d0)))
    ;; One camera, not one a member; two bodies, each with his own ball (the
    ;; members' scripts pick it up), where his world has it: the library's
    ;; (-0.3 0.9 0.3) from his place, -0.3 and 0.3.
    (is (= 2 (length (objects-named start "ball"))))
    (is (= 1 (length (objects-named start "camera"))))
    (is (= 2 (count :body (player.body:scene-objects start) :key #'player.body:object-kind)))
    (is (equal '(-0.6d0 0d0)
               (sort (mapcar (lambda (ball) (/ (round (player.body:vec3-x (player.body:object-world-position ball)) 1d-9) 1d9))
                             (objects-named start "ball"))
                     #'<)))
    ;; The members stand apart, and the camera sees them both.
    (let ((bodies (remove :body (player.body:scene-objects start) :key #'player.body:object-kind :test-not #'eq)))
      (is (> (player.body:vdistance (player.body:object-world-position (first bodies))
                                    (player.body:object-world-position (second bodies)))
             0.3d0)))
    (let ((view (player.render::scene-view start 4/3)))
      (dolist (body (remove :body (player.body:scene-objects start) :key #'player.body:object-kind :test-not #'eq))
        (multiple-value-bind (x y w)
            (player.render::project-point view (player.body:joint-world-position
                                                (player.body:body-transforms body)
                                                (aref (player.body:skeleton-joints (player.body:body-skeleton body)) 0))
                                             400 300)
          (is (and (plusp w) (<= 0 x 400) (<= 0 y 300)) "~A is out of the picture" body))))
    ;; ANIM2 picked his ball up: he holds it, and ANIM1's lies where it was.
    (let* ((end (player.performance:simulation-scene-at simulation 1.5d0))
           (balls (objects-named end "ball")))
      (is (= 2 (length balls)))
      (is (= 1 (count-if #'player.cast::hangs-from-body-p balls))))))

(defun one-line-p (text prefix)
  "Is TEXT one line starting with PREFIX?"
  (and (not (find #\Newline text)) (eql 0 (search prefix text))))

(test scenes-and-dialogues-print-on-one-line
  (let* ((cast (anim-duet))
         (ensemble (player.cast:make-ensemble cast))
         (dialogue (first (load-dialogue (checkout-file "specs/peedy-dialogue.lisp"))))
         (conversation (make-conversation dialogue)))
    (is (one-line-p (prin1-to-string cast) "#<CAST anim: anim1 anim2") "~A" (prin1-to-string cast))
    (is (one-line-p (prin1-to-string (first (player.cast:cast-members cast))) "#<CAST-MEMBER anim1: anim at (")
        "~A" (prin1-to-string (first (player.cast:cast-members cast))))
    (is (one-line-p (prin1-to-string ensemble) "#<ENSEMBLE anim: anim1 t=0 anim2 t=0")
        "~A" (prin1-to-string ensemble))
    (is (one-line-p (prin1-to-string dialogue) "#<DIALOGUE ") "~A" (prin1-to-string dialogue))
    (is (search "states" (prin1-to-string dialogue)))
    (is (one-line-p (prin1-to-string conversation) "#<CONVERSATION ") "~A" (prin1-to-string conversation))
    (is (search "0 turns" (prin1-to-string conversation)) "~A" (prin1-to-string conversation))))

(test scene-file-names-its-own-set
  ;; (set "stage.lisp") in the scene: its objects are the set, and the
  ;; members bring only their own props (each his ball).
  (let ((directory (live-scratch-directory "scene-set")))
    (unwind-protect
         (progn
           (edit-file (merge-pathnames "anim.lisp" directory) (file-text (fixture "anim.lisp")))
           (edit-file (merge-pathnames "anim-scripts.lisp" directory) (file-text (fixture "anim-scripts.lisp")))
           (edit-file (merge-pathnames "stage.lisp" directory)
                      (format nil "(defobject lamp :kind :prop :position (1 0 0))~%~
                                   (defobject camera :kind :camera :position (0 1 6))~%"))
           (edit-file (merge-pathnames "duo.lisp" directory)
                      (format nil "(in-package :player-user)~%~
                                   (defscene duo (anim :as a) (anim :as b) (set \"stage.lisp\"))~%"))
           (let* ((cast (first (player.cast:load-scene-file (merge-pathnames "duo.lisp" directory))))
                  (frame (player.performance:simulation-scene-at (player.cast:simulate-scene cast :fps 10) 0d0)))
             (is (= 2 (length (player.cast:cast-members cast))))
             (is (= 1 (length (objects-named frame "lamp"))))
             (is (= 2 (length (objects-named frame "ball"))))
             (is (= 1 (count :camera (player.body:scene-objects frame) :key #'player.body:object-kind)))
             (is (< (player.body:vdistance (player.body:object-world-position (first (objects-named frame "lamp")))
                                           (player.body:vec3 1d0 0d0 0d0))
                    1d-9))))
      (uiop:delete-directory-tree directory :validate t :if-does-not-exist :ignore))))

(test scene-frames-keep-their-objects
  ;; ANIM2 picks his ball up and puts it down: each member's ball shows
  ;; throughout, and every frame has the same objects, so an export sees each one throughout.
  (let* ((simulation (player.cast:simulate-scene (anim-duet) :events '("anim2/ev-pick" "anim2/ev-drop") :fps 10))
         (end (player.performance:simulation-end simulation))
         (frames (loop for time in (list 0d0 0.8d0 end)
                       collect (let ((scene (player.performance:simulation-scene-at simulation time)))
                                 (list (copy-list (player.body:scene-objects scene))
                                       (length (objects-named scene "ball")))))))
    (is (every (lambda (frame) (equal (first frame) (first (first frames)))) frames))
    (is (equal '(2 2 2) (mapcar #'second frames)) "~S" (mapcar #'second frames))))
