;;;; test-render.lisp -- the renderer and `render`: golden images of a fixed
;;;; pose of each skeleton, what the pixels mean (silhouette against the
;;;; projected skeleton, lids, camera moves), the frames, sheet and video the
;;;; render command writes, and its errors.
;;;;
;;;; Golden images live in t/golden/.  After an intended change of the look,
;;;; regenerate them with `make golden` (PLAYER_REGENERATE_GOLDEN=1 while the
;;;; render suite runs), look at them, and commit them.

(in-package #:player-tests)

(def-suite* render :in player-tests)

;;; ---------------------------------------------------------------------------
;;; Scenes and frames

(defun pose-body (body settings)
  "Set BODY's pose to its rest pose with SETTINGS, a list of (JOINT DOF DEGREES),
clamped to the joint limits, and place its joints accordingly."
  (let* ((skeleton (player::body-skeleton body))
         (pose (player::body-pose body)))
    (fill pose 0d0)
    (loop for (joint dof degrees) in settings
          do (setf (aref pose (player::dof-index skeleton joint dof)) (float degrees 1d0)))
    (player::clamp-pose skeleton pose)
    (player::pose-world-transforms skeleton pose :placement (player::object-world-transform body)
                                                 :result (player::body-transforms body))
    body))

(defun figure-scene (skeleton &key settings camera)
  "A scene with one body FIGURE of SKELETON posed by SETTINGS (see POSE-BODY)
and, with CAMERA a list (X Y Z), a camera there looking along -z."
  (let* ((scene (make-instance 'player::scene))
         (body (player::make-body 'figure skeleton :scene scene)))
    (pose-body body settings)
    (when camera
      (let ((object (make-instance 'player::scene-object :name 'camera :kind :camera
                                                         :position (apply #'player.body::make-vec3 camera))))
        (player::define-property object 'fov :number 35)
        (player::add-object scene object)))
    scene))

(defun call-with-renderer (width height function &rest options)
  "Call FUNCTION with a renderer of WIDTH x HEIGHT (OPTIONS as for MAKE-RENDERER)
in a fresh offscreen context."
  (player::with-offscreen-context ((context) width height)
    (let ((renderer (apply #'player.render::make-renderer width height options)))
      (unwind-protect (funcall function renderer)
        (player.render::delete-renderer renderer)))))

(defun draw (renderer scene)
  "SCENE drawn by RENDERER: its pixels and the view used (two values)."
  (let ((view (player.render::render-scene renderer scene)))
    (values (player.render::renderer-pixels renderer) view)))

(defun pixel-difference (a b index)
  "The largest channel difference between the RGB of pixel INDEX in images A and B."
  (loop for c below 3 maximize (abs (- (aref a (+ c (* 4 index))) (aref b (+ c (* 4 index)))))))

(defun changed-box (a b width height &key (threshold 24) (within (constantly t)))
  "The box (LEFT TOP RIGHT BOTTOM, inclusive, rows top-down) of the pixels where
images A and B differ by more than THRESHOLD, and their count (two values);
WITHIN, a function of column and row, limits the count to a region."
  (let ((left width) (top height) (right -1) (bottom -1) (count 0))
    (dotimes (i (* width height))
      (multiple-value-bind (row column) (floor i width)
        (when (and (> (pixel-difference a b i) threshold) (funcall within column row))
          (incf count)
          (setf left (min left column) right (max right column)
                top (min top row) bottom (max bottom row)))))
    (values (and (plusp count) (list left top right bottom)) count)))

;;; ---------------------------------------------------------------------------
;;; Golden images

(defparameter *golden-poses*
  '((humanoid ((l_shoulder z 50) (r_elbow x 40) (skullbase y 15) (temporomandibular open 12)
               (l_index1 curl 60) (l_hip x -15)))
    (parrot ((head y 20) (beak open 15) (crest raise 30) (l_shoulder z 30) (tail spread 20)
             (r_lid close 30))))
  "The fixed pose of each skeleton its golden image shows.")

(defparameter *golden-size* '(160 120) "The golden images' width and height.")

(defun golden-path (skeleton)
  "The golden image file of SKELETON."
  (checkout-file (format nil "t/golden/~(~A~).png" skeleton)))

(defun image-distance (a b)
  "The mean absolute difference of the RGB bytes of images A and B, and the share
of pixels with a channel off by more than 32 (two values)."
  (let ((pixels (floor (length a) 4)) (sum 0) (off 0))
    (dotimes (i pixels)
      (dotimes (c 3) (incf sum (abs (- (aref a (+ c (* 4 i))) (aref b (+ c (* 4 i)))))))
      (when (> (pixel-difference a b i) 32) (incf off)))
    (values (/ sum (* 3.0 pixels)) (/ off (float pixels)))))

(test golden-images
  ;; Tolerance: a mean absolute difference under 2 levels and under 1% of the
  ;; pixels off by more than 32 levels -- room for another Mesa's rounding,
  ;; none for a limb that moved or a colour that changed.
  (destructuring-bind (width height) *golden-size*
    (dolist (entry *golden-poses*)
      (destructuring-bind (skeleton settings) entry
        (let ((pixels (call-with-renderer width height
                                          (lambda (renderer)
                                            (draw renderer (figure-scene skeleton :settings settings))))))
          (cond ((sb-ext:posix-getenv "PLAYER_REGENERATE_GOLDEN")
                 (ensure-directories-exist (golden-path skeleton))
                 (player::write-png (golden-path skeleton) width height pixels)
                 (format t "~&; regenerated ~A~%" (namestring (golden-path skeleton)))
                 (pass))
                ((not (probe-file (golden-path skeleton)))
                 (fail "no golden image ~A: run `make golden`" (golden-path skeleton)))
                (t
                 (destructuring-bind (w h depth colour-type &rest rest)
                     (first (decode-pngs (list (golden-path skeleton))))
                   (declare (ignore depth))
                   (is (equal (list width height 6) (list w h colour-type)))
                   (multiple-value-bind (mean share) (image-distance pixels (car (last rest)))
                     (is (< mean 2) "~A: mean difference ~,2F levels from the golden image" skeleton mean)
                     (is (< share 0.01) "~A: ~,2F% of pixels off by more than 32"
                         skeleton (* 100 share)))))))))))

;;; ---------------------------------------------------------------------------
;;; What the pixels mean

(defun projected-joint-box (view body width height)
  "The box (LEFT TOP RIGHT BOTTOM) around BODY's joints seen through VIEW, each
joint grown by its projected radius."
  (let ((focal (/ (* 0.5 height) (tan (* 0.5 (player.render::view-fov view) (/ pi 180)))))
        (box (list width height 0 0)))
    (loop for joint across (player::skeleton-joints (player::body-skeleton body))
          do (multiple-value-bind (column row w)
                 (player.render::project-point view (player::body-joint-position body (player.body::body-joint-name joint))
                                        width height)
               (let ((r (/ (* focal (player.body::body-joint-radius joint)) w)))
                 (setf box (list (min (first box) (- column r)) (min (second box) (- row r))
                                 (max (third box) (+ column r)) (max (fourth box) (+ row r)))))))
    box))

(test silhouette-matches-the-projected-skeleton
  ;; Without a floor, the pixels differing from the empty background are the
  ;; figure; their box must lie within a few pixels of the joints' projected
  ;; box (joints grown by their radii).  The limbs reach the joint spheres'
  ;; rims; the head, hands and feet may pass them by a little.
  (dolist (skeleton '(humanoid parrot))
    (call-with-renderer
     200 150
     (lambda (renderer)
       (let ((scene (figure-scene skeleton :camera (if (eq skeleton 'parrot) '(0 0.18 0.9) '(0 1 4.5)))))
         (multiple-value-bind (figure view) (draw renderer scene)
           (setf (player::property-value (player::find-object scene 'figure) 'visible) nil)
           (let ((expected (projected-joint-box view (player::find-object scene 'figure) 200 150))
                 (found (changed-box figure (draw renderer scene) 200 150)))
             (is-true found "~A: nothing drawn" skeleton)
             (when found
               (loop for side in '(left top right bottom)
                     for want in expected
                     for got in found
                     do (is (< (abs (- want got)) 6) "~A: silhouette ~(~A~) ~D, projected skeleton ~,1F"
                            skeleton side got want)))))))
     :floor nil)))

(test lids-change-only-the-eyes
  ;; Shutting the lids changes the pixels around the eyes and hardly any other,
  ;; seen from 30 cm (the parrot) or 40 cm (the humanoid) in front of the eyes.
  (loop for (skeleton eyes-joints eye-radius lids camera)
          in '((parrot (l_eye r_eye) 0.013 ((l_lid close 70) (r_lid close 70)) (0 0.29 0.35))
               (humanoid (l_eyeball_joint r_eyeball_joint) 0.012
                ((l_eyelid_joint close 60) (r_eyelid_joint close 60)) (0.004 1.66 0.5)))
        do (call-with-renderer
            240 180
            (lambda (renderer)
              (let* ((open (figure-scene skeleton :camera camera))
                     (shut (figure-scene skeleton :camera camera :settings lids)))
                (multiple-value-bind (open-pixels view) (draw renderer open)
                  (let* ((shut-pixels (draw renderer shut))
                         (body (player::find-object open 'figure))
                         (eyes (loop for eye in eyes-joints
                                     collect (multiple-value-list
                                              (player.render::project-point view (player::body-joint-position body eye)
                                                                     240 180))))
                         (focal (/ 90 (tan (* 0.5 35 (/ pi 180)))))
                         ;; The lid shell reaches 1.15 eyeball radii from the centre.
                         (reach (+ 4 (/ (* focal eye-radius 1.2) (third (first eyes))))))
                    (flet ((near-eye-p (column row)
                             (some (lambda (eye) (< (max (abs (- column (first eye))) (abs (- row (second eye))))
                                                    reach))
                                   eyes)))
                      (multiple-value-bind (box near) (changed-box open-pixels shut-pixels 240 180
                                                                   :within #'near-eye-p)
                        (declare (ignore box))
                        (is (> near 100) "~A: only ~D pixels changed at the eyes" skeleton near))
                      (multiple-value-bind (box far) (changed-box open-pixels shut-pixels 240 180
                                                                  :within (complement #'near-eye-p))
                        (is (< far 10) "~A: ~D pixels changed away from the eyes (within ~A)"
                            skeleton far box))))))))))

(defun changed-centroid (a b width height)
  "The mean column and row (a list) of the pixels where images A and B differ by more than 24."
  (let ((columns 0) (rows 0) (count 0))
    (dotimes (i (* width height) (list (/ columns (max 1 count)) (/ rows (max 1 count))))
      (when (> (pixel-difference a b i) 24)
        (multiple-value-bind (row column) (floor i width)
          (incf columns column) (incf rows row) (incf count))))))

(test camera-move-shifts-the-image
  ;; Moving the camera 10 cm to the right moves the figure, 0.9 m in front of
  ;; it, left by focal length x 0.1 / 0.9 pixels, and neither up nor down.
  (call-with-renderer
   200 150
   (lambda (renderer)
     (flet ((place (x)
              (let* ((scene (figure-scene 'parrot :camera (list x 0.18 0.9)))
                     (figure (draw renderer scene)))
                (setf (player::property-value (player::find-object scene 'figure) 'visible) nil)
                (let ((empty (draw renderer scene)))
                  (list (changed-box figure empty 200 150) (changed-centroid figure empty 200 150))))))
       (destructuring-bind ((here-box here) (there-box there)) (list (place 0) (place 0.1))
         (let ((expected (* (/ 75 (tan (* 0.5 35 (/ pi 180)))) (/ 0.1 0.9))))
           (is (< (abs (- (first here) (first there) expected)) 2)
               "the figure moved ~,1F px left, expected ~,1F" (- (first here) (first there)) expected)
           (is (< (abs (- (first here-box) (first there-box) expected)) 3) "its left edge too")
           (is (< (abs (- (third here-box) (third there-box) expected)) 3) "and its right edge")
           (is (< (abs (- (second here) (second there))) 1) "a sideways move keeps the rows")))))
   :floor nil))

;;; ---------------------------------------------------------------------------
;;; The render command

(defun scratch-directory (name)
  "A fresh, empty directory NAME under /tmp for this test run, as a string ending in /."
  (let ((directory (format nil "/tmp/player-render-tests-~D/~A/" (sb-posix:getpid) name)))
    (ensure-directories-exist directory)
    (mapc #'delete-file (directory (merge-pathnames "*.*" directory)))
    directory))

(defun anim-simulation (&key (fps 4))
  "The anim fixture's scenario (pick up the ball, wave) played at FPS."
  (player::simulate (player.cli::choose-spec (fixture "anim.lisp") nil) :events '("ev-pick" "ev-wave")
                                                                    :fps fps))

(test render-writes-frames-and-a-sheet
  (let* ((simulation (anim-simulation))
         (out (scratch-directory "frames"))
         (count (1+ (ceiling (* 4 (player.performance::simulation-end simulation)))))
         (progress (make-string-output-stream))
         ;; No quiet start: this render may take less than its 2 s.
         (paths (let ((player.render::*quiet-progress-seconds* 0))
                  (player::render-simulation simulation :out out :size "64x48" :progress progress))))
    (is (= (+ count 1) (length paths)) "~D frames and the sheet" count)
    (is (equal (format nil "~Aframe-0001.png" out) (namestring (first paths))))
    (is (equal (format nil "~Asheet.png" out) (namestring (car (last paths)))))
    (is (= (+ count 1) (length (directory (merge-pathnames "*.png" out)))) "nothing else written")
    (let ((decoded (decode-pngs paths)))
      (is (every #'consp decoded) "every file decodes: ~S" (remove-if #'consp decoded))
      (is (every (lambda (png) (equal '(64 48 8 6) (subseq png 0 4))) (butlast decoded)))
      ;; 4 x 3 thumbnails of 64 x 48 with 6 pixel gaps.
      (is (equal (list (+ 6 (* 4 70)) (+ 6 (* 3 54))) (subseq (car (last decoded)) 0 2))))
    (let ((text (get-output-stream-string progress)))
      (is (search (format nil "[##############################] ~D/~D frames" count count) text))
      ;; Not a terminal: a line every 10 %, nothing redrawn in place.
      (is (not (find #\Return text)))
      (is (<= (count #\Newline text) 11)))
    ;; A second render into the same directory replaces the frames of the first.
    (player::render-simulation simulation :out out :size "64x48" :fps 2 :progress nil)
    (is (= (1+ (ceiling (* 2 (player.performance::simulation-end simulation))))
           (length (directory (merge-pathnames "frame-*.png" out)))))))

(test render-pipes-frames-to-ffmpeg
  ;; A stand-in ffmpeg that stores what it is fed: raw RGBA frames, in order.
  (let* ((out (scratch-directory "video"))
         (fake (format nil "~Afake-ffmpeg" out))
         (simulation (anim-simulation :fps 2)))
    (with-open-file (script fake :direction :output)
      (format script "#!/bin/sh~%for last; do :; done~%cat > \"$last\"~%"))
    (sb-ext:run-program "/bin/chmod" (list "+x" fake))
    (let* ((player.render::*ffmpeg-program* fake)
           (paths (player::render-simulation simulation :out out :size "32x24" :video (format nil "~Aclip.mp4" out)
                                                        :progress nil))
           (frames (- (length paths) 2)))
      (is (equal (format nil "~Aclip.mp4" out) (namestring (car (last paths)))))
      (with-open-file (in (car (last paths)) :element-type '(unsigned-byte 8))
        (is (= (* frames 32 24 4) (file-length in)) "~D frames of raw RGBA" frames)))))

(test render-command-prints-the-trace-and-paths
  (let* ((out (scratch-directory "command"))
         (text (with-output-to-string (*standard-output*)
                 (let ((*error-output* (make-broadcast-stream)))
                   (player.cli::run-command-line (list "render" (fixture "anim.lisp") "--events" "ev-pick"
                                                   "--size" "48x36" "--fps" "4" "--out" out))))))
    (is (search "(:event ev-pick :time 0)" text))
    (is (search (format nil "; wrote ~Aframe-0001.png .. frame-" out) text))
    (is (search (format nil "; wrote ~Asheet.png" out) text))))

(defun render-error-text (function)
  "The report of the RENDER-ERROR or USAGE-ERROR FUNCTION signals, or NIL."
  (handler-case (progn (funcall function) nil)
    ((or player::render-error player::usage-error) (e) (princ-to-string e))))

(test render-bad-input
  (dolist (size '("0x10" "640" "5000x480" "axb" "64x-1" "640x480x3" ""))
    (is (search "bad size" (or (render-error-text (lambda () (player.render::image-size size))) ""))
        "size ~S" size)
    (is (null (player.render::read-size size)) "size ~S" size))
  (is (equal '(640 480) (multiple-value-list (player.render::image-size "640x480"))))
  (is (equal '(4096 1) (multiple-value-list (player.render::image-size "4096X1"))))
  (is (equal '(32 24) (multiple-value-list (player.render::image-size '(32 24)))))
  (is (search "bad size" (render-error-text (lambda () (player.render::image-size '(0 24))))))
  (let ((simulation (anim-simulation :fps 2))
        (file (format nil "~Aa-file" (scratch-directory "errors"))))
    (is (search "bad size" (render-error-text (lambda () (player::render-simulation simulation :size "0x5")))))
    (with-open-file (stream file :direction :output) (write-line "not a directory" stream))
    (let ((text (render-error-text (lambda () (player::render-simulation simulation :out (format nil "~A/frames/" file)
                                                                                    :progress nil)))))
      (is (search (format nil "cannot write into the output directory ~A/frames/" file) (or text ""))
          "got ~S" text))
    (let* ((player.render::*ffmpeg-program* "player-no-such-ffmpeg")
           (out (scratch-directory "no-ffmpeg"))
           (text (render-error-text (lambda () (player::render-simulation simulation :out out :video "x.mp4")))))
      (is (search "install the Debian package ffmpeg" (or text "")) "got ~S" text)
      (is (null (directory (merge-pathnames "*.png" out))) "it fails before rendering"))))

(test render-command-line-errors
  (dolist (case '((("--size" "big") "--size takes WIDTHxHEIGHT" 2)
                  (("--out" "/proc/no-such-dir") "cannot write into the output directory" 1)
                  (("--body" "robot") "unknown skeleton robot" 1)))
    (destructuring-bind (options text status) case
      (multiple-value-bind (out err code)
          (apply #'player-command "render" (fixture "anim.lisp") "--events" "ev-pick" options)
        (declare (ignore out))
        (is (= status code) "~A: exit ~D" options code)
        (is (= 1 (length (lines err))) "one line: ~A" err)
        (is (search text err) "~S in ~A" text err)))))
