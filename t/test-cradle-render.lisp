;;;; test-cradle-render.lisp -- Newton's cradle drawn: the script library
;;;; specs/newtons-cradle-scripts.lisp is what the algebra generates, the
;;;; spheres in the scene and in the pixels are where the planned trace puts
;;;; them, and they swing between trace steps rather than jump.

(in-package #:player-tests)

(def-suite* cradle-render :in player-tests)

(defparameter *cradle-size* '(160 120) "The frames these tests draw, small: pixels are checked, not looked at.")

(defun cradle-simulation ()
  "specs/newtons-cradle.lisp played on its script library: ev-lift-two-left."
  (simulate (first (load-spec (checkout-file "specs/newtons-cradle.lisp") :allow-code nil))
            :events '(ev-lift-two-left) :fps 4))

(defun trace-states (simulation)
  "(TIME . POSITIONS) for the start and the end of each op SIMULATION ran:
the spheres' positions (-1, 0, 1, leftmost first) the trace says."
  (cons (cons 0 '(0 0 0 0 0))
        (loop for line in (trace-lines (player.performance::simulation-presenter simulation))
              when (eq (first line) :op)
                collect (let ((name (symbol-name (second line))))
                          (cons (getf line :end)
                                (decode-cradle-name (if (string= name "LIFT-TWO-LEFT")
                                                        "LS-LS-CS-CS-CS"
                                                        (subseq name (+ 4 (search "-TO-" name))))))))))

(defun ball-x (scene k)
  "The world x of ball K (from 1) in SCENE."
  (player.body::vec3-x (player::object-world-position (player::find-object scene (format nil "BALL-~D" k)))))

(defun expected-ball-x (k position)
  "Where the script library puts ball K (from 1) of 5 at POSITION: its pivot's
x plus the string's length times the sine of the swing."
  (+ (player.compose::cradle-pivot-x (1- k) 5)
     (* (player.compose::cradle-geometry :string) (sin (player.compose::cradle-angle position)))))

(defun ball-pixel-p (pixels index)
  "Is pixel INDEX of the RGBA PIXELS the balls' red?"
  (let ((r (aref pixels (* 4 index))) (g (aref pixels (+ 1 (* 4 index)))) (b (aref pixels (+ 2 (* 4 index)))))
    (and (> r 80) (> r (* 2 g)) (> r (* 2 b)))))

(defun ball-centroid (pixels width height)
  "The mean column of the ball-red pixels of PIXELS, and how many there are."
  (let ((sum 0) (count 0))
    (dotimes (index (* width height))
      (when (ball-pixel-p pixels index)
        (incf sum (mod index width))
        (incf count)))
    (values (and (plusp count) (/ sum count 1d0)) count)))

(defun luminance-spread (pixels)
  "The standard deviation of PIXELS' luminance: near 0 for a blank frame."
  (let* ((n (floor (length pixels) 4))
         (values (loop for i below n
                       collect (+ (* 0.3 (aref pixels (* 4 i))) (* 0.59 (aref pixels (+ 1 (* 4 i))))
                                  (* 0.11 (aref pixels (+ 2 (* 4 i)))))))
         (mean (/ (reduce #'+ values) n)))
    (sqrt (/ (reduce #'+ values :key (lambda (v) (expt (- v mean) 2))) n))))

(test cradle-scripts-file-is-generated
  (is (string= (player.compose::cradle-scripts-text)
               (alexandria:read-file-into-string (checkout-file "specs/newtons-cradle-scripts.lisp")
                                                 :external-format :utf-8)))
  ;; a script per op, nothing missing, nothing that cannot play
  (let ((spec (first (load-spec (checkout-file "specs/newtons-cradle.lisp")))))
    (is (null (remove :warning (player.performance::script-diagnostics spec) :key #'player.performance::diagnostic-severity)))
    (is (null (player.performance::missing-scripts (player.performance::spec-script-library spec) (player.performance::spec-script-names spec))))))

(test cradle-scene-follows-trace
  (let* ((simulation (cradle-simulation))
         (performance (player.performance::simulation-performance simulation))
         (states (trace-states simulation)))
    ;; lift, swing down, collide, swing out on the right: six steps, timed
    (is (= 7 (length states)))
    (is (equal '(0 0 0 1 1) (cdr (car (last states)))))
    (loop for (time . positions) in states
          for scene = (player::performance-frame performance time)
          do (loop for position in positions
                   for k from 1
                   do (is (< (abs (- (ball-x scene k) (expected-ball-x k position))) 1d-4)
                          "at ~A s ball ~D is at x ~,3F, not at position ~D" time k (ball-x scene k) position)))
    ;; (the file rounds angles to 1e-4 rad)
    ;; between steps a moving sphere is on its way, not at either end
    (loop for ((time . before) (next . after)) on states
          while after
          do (let ((scene (player::performance-frame performance (/ (+ time next) 2))))
               (loop for b in before for a in after for k from 1
                     do (let ((x (ball-x scene k)) (x0 (expected-ball-x k b)) (x1 (expected-ball-x k a)))
                          (if (= a b)
                              (is (< (abs (- x x0)) 1d-4))
                              (is (< (+ (min x0 x1) 1d-3) x (- (max x0 x1) 1d-3))
                                  "at ~A s ball ~D jumps: ~,3F not between ~,3F and ~,3F" (/ (+ time next) 2) k x x0 x1))))))
    ;; the character is a hidden stand-in: nothing but props is drawn
    (is (notany (lambda (object) (and (typep object 'player::body) (player.render::drawable-p object)))
                (player::scene-objects (player::performance-frame performance 0))))))

(test cradle-frames-follow-trace
  (let* ((simulation (cradle-simulation))
         (performance (player.performance::simulation-performance simulation))
         (states (trace-states simulation))
         (centroids '()))
    (destructuring-bind (width height) *cradle-size*
      (call-with-renderer
       width height
       (lambda (renderer)
         (loop for (time . positions) in states
               do (multiple-value-bind (pixels view) (draw renderer (player::performance-frame performance time))
                    (let ((scene (player::performance-frame performance time)))
                      ;; not blank: shaded, and the balls are there
                      (is (> (luminance-spread pixels) 10))
                      (multiple-value-bind (centroid count) (ball-centroid pixels width height)
                        (is (> count 100) "~D ball pixels at ~A s" count time)
                        (push (cons positions centroid) centroids))
                      ;; each ball's centre, projected, is drawn in the balls' colour
                      (loop for k from 1 to 5
                            do (multiple-value-bind (column row)
                                   (player.render::project-point view (player::object-world-position
                                                                (player::find-object scene (format nil "BALL-~D" k)))
                                                          width height)
                                 (is (ball-pixel-p pixels (+ (floor column) (* width (floor row))))
                                     "ball ~D at ~A s: pixel (~D, ~D) is not ball-coloured" k time
                                     (floor column) (floor row))))))))))
    ;; lifted on the left, the red is left of where it hangs at rest; out on the right, right of it
    (flet ((centroid (positions) (cdr (assoc positions centroids :test #'equal))))
      (let ((rest (centroid '(0 0 0 0 0))))
        (is (< (centroid '(-1 -1 0 0 0)) (- rest 3)))
        (is (> (centroid '(0 0 0 1 1)) (+ rest 3)))))))
