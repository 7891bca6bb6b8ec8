;;;; test-explaining-pictures.lisp -- pictures that explain themselves (issue
;;;; 27, item 6): `render --policies` names each row, the camera keeps a
;;;; character who flies out of the library's shot in frame, and the progress
;;;; bar redraws in place only on a terminal, a line every 10 % elsewhere.

(in-package #:player-tests)

(def-suite* explaining-pictures :in player-tests)

(defparameter *flier-spec*
  "(in-package :player-user)
(defspec flier
  \"A humanoid who flies six metres to his left, out of the library's shot.\"
  (:scripts \"flier-scripts.lisp\")
  (:body humanoid)
  (op fly :duration 2)
  (event ev-fly :op fly))
"
  "A spec whose one event carries the character out of its camera's view.")

(defparameter *flier-scripts*
  "(defobject camera :kind :camera :position (0 1 5))
(defscript fly (:duration 2)
  (:at 0 :animate (:self position) (:keys ((0 :vec3 0 0 0) (2 :vec3 6 0.5 0)))))
"
  "The flier's library: a fixed camera looking at where he starts, and the flight.")

(defmacro with-flier ((spec directory) &body body)
  "Run BODY with SPEC the flier, read from files in the scratch DIRECTORY."
  `(let ((,directory (live-scratch-directory "flier")))
     (unwind-protect
          (progn (edit-file (merge-pathnames "flier.lisp" ,directory) *flier-spec*)
                 (edit-file (merge-pathnames "flier-scripts.lisp" ,directory) *flier-scripts*)
                 (let ((,spec (first (load-spec (merge-pathnames "flier.lisp" ,directory)))))
                   ,@body))
       (uiop:delete-directory-tree ,directory :validate t :if-does-not-exist :ignore))))

;;;# The camera keeps him in frame

(defun joints-in-frame-p (scene view width height)
  "Does every joint of every body of SCENE land inside a WIDTH x HEIGHT frame
seen through VIEW, in front of the eye?"
  (every (lambda (body)
           (let ((transforms (player.body:body-transforms body)))
             (every (lambda (joint)
                      (multiple-value-bind (x y w)
                          (player.render::project-point view (player.body:joint-world-position transforms joint)
                                                        width height)
                        (and (plusp w) (<= 0 x width) (<= 0 y height))))
                    (player.body:skeleton-joints (player.body:body-skeleton body)))))
         (player.render::scene-bodies scene)))

(test camera-keeps-a-flier-in-frame
  (with-flier (spec directory)
    (let* ((simulation (simulate spec :events '(player-user::ev-fly) :silent t))
           (performance (player.performance:simulation-performance simulation)))
      ;; At home the library's camera is kept ...
      (let* ((scene (performance-frame performance 0d0))
             (view (player.render::scene-view scene 4/3)))
        (is (< (player.body:vdistance (player.render::view-eye view) (player.body:vec3 0d0 1d0 5d0)) 1d-9))
        (is-true (joints-in-frame-p scene view 400 300)))
      ;; ... six metres off, he is framed by another.
      (let* ((scene (performance-frame performance 2d0))
             (view (player.render::scene-view scene 4/3)))
        (is-true (joints-in-frame-p scene view 400 300))
        (is (> (player.body:vdistance (player.render::view-eye view) (player.body:vec3 0d0 1d0 5d0)) 1d0))))))

;;;# Policies named

(test policy-sheet-names-each-row
  (with-flier (spec directory)
    (let* ((policies '(:queue :preempt))
           (path (player.render:render-policy-sheet spec policies :events '(player-user::ev-fly) :size '(64 48) :columns 2
                                                    :out (merge-pathnames "sheet/" directory) :silent t))
           (png (first (decode-pngs (list path))))
           (scale player.render::*row-label-scale*)
           (gap 6)
           (margin (+ gap (* scale (reduce #'max policies
                                            :key (lambda (p) (player.render::caption-text-width
                                                              (string-downcase p))))))))
      (destructuring-bind (width height &rest header-and-pixels) png
        (declare (ignore height))
        (let ((pixels (car (last header-and-pixels))))
          ;; Two thumbnails a row, after the margin of labels.
          (is (= width (+ margin gap (* 2 (+ 64 gap)))) "width ~D" width)
          (loop for policy in policies
                for row from 0
                for lit = (loop for (nil nil length) in (player.render::caption-text-runs (string-downcase policy))
                                sum (* length scale scale))
                for top = (+ gap (* row (+ 48 gap)))
                do (is (= lit (loop for y from top below (+ top 48)
                                    sum (loop for x from 0 below margin
                                              count (> (aref pixels (* 4 (+ x (* width y)))) 200))))
                       "row ~D: ~A is not written at its left" row policy)))))))

;;;# Progress

(test progress-redraws-only-on-a-terminal
  (let ((log (with-output-to-string (stream)
               (loop for done from 1 to 240 do (player.render::show-progress stream done 240)))))
    (is (null (find #\Return log)))
    (is (= 10 (length (lines log))) "~A" log)
    (is (search "240/240 frames" (car (last (lines log))))))
  (let ((terminal (with-output-to-string (stream)
                    (loop for done from 1 to 5 do (player.render::show-progress stream done 5 t)))))
    (is (= 5 (count #\Return terminal)))
    (is (= 1 (count #\Newline terminal)))))

(test progress-in-a-log-waits-until-the-render-has-worked-two-seconds
  "A render begun just now writes no progress line in a log; one begun three
seconds ago writes its line every tenth.  On a terminal the bar shows at once."
  (let ((now (get-internal-real-time))
        (earlier (- (get-internal-real-time) (* 3 internal-time-units-per-second))))
    (flet ((log-of (since terminal)
             (with-output-to-string (stream)
               (loop for done from 1 to 20 do (player.render::show-progress stream done 20 terminal since)))))
      (is (string= "" (log-of now nil)))
      (is (= 10 (length (lines (log-of earlier nil)))))
      (is (= 20 (count #\Return (log-of now t)))))))
