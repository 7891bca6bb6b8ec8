;;;; render.lisp -- `player render`: a scenario drawn offscreen to PNG frames.

(in-package #:player.cli)

(define-command "render" (file &key spec no-code initial events at when-busy policies fps seed scripts body size out video cast silent)
    (:summary "play the events in simulated time and draw them offscreen"
     :description "Draws every frame with OSMesa (no display needed), writes a contact sheet
of evenly spaced frames and, with --video, a video made by ffmpeg (Debian
package ffmpeg).  What the character says and the sounds its scripts play go
to DIR/speech.wav and into the video (--silent: nothing sounds, and espeak-ng
is not needed).  A progress bar goes to standard error, redrawn in place
on a terminal; in a log or a pipe, once the render has worked 2 s, a line
every 10 %."
     :arguments ("SPEC-FILE")
     :options ("--spec" "--no-code" "--initial" "--events" "--at" "--when-busy" ("--fps" :default 24) "--seed" "--scripts" "--body" "--silent"
               "--size" "--cast"
               ("--out" :string "DIR" "the directory to write the frames into" :default "render/")
               ("--video" :string "FILE.mp4" "also encode the frames as a video")
               ("--policies" :policies "P1,P2,..."
                "instead, play the scenario once per :when-busy policy (queue, preempt, override, interleave) and draw them side by side, a row each named by its policy, in DIR/policies.png"))
     :output "DIR/frame-0001.png ..., DIR/sheet.png (a contact sheet), DIR/speech.wav and the --video
        file, or with --policies DIR/policies.png alone; the trace and the paths
        written on standard output")
  (when video (find-ffmpeg))
  (check-scenario-times events at)
  (check-frame-budget at fps)
  (let ((scene (command-cast file spec cast (not no-code))))
    (when scene
      (refuse-scene-option "--policies" policies)
      (render-scene-command scene :initial initial :events events :at at :when-busy when-busy
                                  :fps fps :seed seed :scripts scripts :body body :size size
                                  :out out :video video)
      (return-from command-render)))
  (when policies
    (when video (usage-fail "--policies draws one contact sheet; it makes no --video"))
    (let ((path (render-policy-sheet (choose-spec file spec :allow-code (not no-code)) policies
                                     :initial initial :events events :until at :fps fps :seed seed
                                     :scripts scripts :body body :size size :out out :silent silent)))
      (format t "; rows, top to bottom: ~{~(~A~)~^, ~}~%; wrote ~A~%" policies (namestring path))
      (return-from command-render)))
  (let* ((simulation (simulate (choose-spec file spec :allow-code (not no-code))
                               :initial initial :events events :until at :when-busy (policy-keyword when-busy) :fps fps :seed seed
                               :scripts scripts :body body :stream *standard-output* :silent silent))
         (paths (render-simulation simulation :out out :size size :fps fps :video video))
         (frames (remove-if-not #'frame-file-p paths)))
    (print-scenario-summary simulation (length frames) fps)
    (format t "; wrote ~A .. ~A~%" (namestring (first frames)) (file-namestring (car (last frames))))
    (dolist (path (remove-if #'frame-file-p paths))
      (format t "; wrote ~A~%" (namestring path)))))

(defun render-scene-command (scene &key initial events at when-busy fps seed scripts body size out video)
  "`player render` on a scene: every member drawn in each frame."
  (let* ((simulation (simulate-scene scene :initial initial :events events :until at
                                           :when-busy (policy-keyword when-busy) :fps fps :seed seed
                                           :scripts scripts :body body))
         (paths (progn (write-ensemble-trace (scene-simulation-ensemble simulation))
                       (render-simulation simulation :out out :size size :fps fps :video video)))
         (frames (remove-if-not #'frame-file-p paths)))
    (print-scene-summary simulation (length frames) fps)
    (format t "; wrote ~A .. ~A~%" (namestring (first frames)) (file-namestring (car (last frames))))
    (dolist (path (remove-if #'frame-file-p paths))
      (format t "; wrote ~A~%" (namestring path)))))

(defun frame-file-p (path)
  "Is PATH one of the numbered frames render writes (frame-0001.png ...)?"
  (let ((name (pathname-name path)))
    (and name (alexandria:starts-with-subseq "frame-" name) (equal (pathname-type path) "png"))))
