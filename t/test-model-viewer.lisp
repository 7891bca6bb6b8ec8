;;;; test-model-viewer.lisp -- an imported, skinned character looks the same
;;;; in the GLFW window (`bin/player view`, under xvfb-run) as offscreen
;;;; through OSMesa (`bin/player render`): one drawing path, two contexts.

(in-package #:player-tests)

(def-suite* model-viewer :in player-tests)

(test wuson-looks-the-same-in-the-window-and-offscreen
  (with-assimp-models
    (with-window-programs ()
      (let ((screenshot (temporary-png "wuson-view"))
            (directory (uiop:ensure-directory-pathname (format nil "/tmp/player-wuson-render-~D/" (random 1000000)))))
        (unwind-protect
             (multiple-value-bind (out err code)
                 (view-command (list (namestring (checkout-file "examples/wuson/wuson.lisp")) "--size" "320x240"
                                     "--frames" "1" "--screenshot" (namestring screenshot)))
               (declare (ignore out))
               (is (= 0 code) "view exits ~D: ~A" code err)
               ;; The first frame offscreen: the scene at time 0, as the window's first.
               (sb-ext:run-program (namestring (checkout-file "bin/player"))
                                   (list "render" (namestring (checkout-file "examples/wuson/wuson.lisp"))
                                         "--size" "320x240" "--fps" "1" "--at" "0" "--out" (namestring directory))
                                   :output nil :error nil)
               (destructuring-bind (window offscreen)
                   (decode-pngs (list screenshot (merge-pathnames "frame-0001.png" directory)))
                 (let* ((a (car (last window))) (b (car (last offscreen)))
                        (pixels (floor (length a) 4))
                        (differing (loop for p below pixels
                                         count (loop for c below 3
                                                     thereis (> (abs (- (aref a (+ c (* 4 p))) (aref b (+ c (* 4 p))))) 24)))))
                   (is (= (length a) (length b)))
                   (is (< differing (* 0.01 pixels)) "~D of ~D pixels differ between the window and offscreen"
                       differing pixels)
                   ;; And the bison is there: many pixels differ from the sky's and floor's.
                   (is (> (body-pixel-share a 320 240) 0.1)))))
          (ignore-errors (delete-file screenshot))
          (uiop:delete-directory-tree directory :validate t :if-does-not-exist :ignore))))))
