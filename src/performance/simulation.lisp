;;;; simulation.lisp -- a scenario played in simulated time: a controller on a
;;;; body presenter takes a list of events, then the performance is sampled at
;;;; a frame rate.  What `bin/player simulate` (and later `render`) runs.

(in-package #:player.performance)

(defstruct (simulation (:constructor %make-simulation))
  "A played scenario: the CONTROLLER, its PRESENTER, the END time (when the last
op finished and the body settled) and FPS.  Frames are sampled from the
presenter's performance at FRAME-TIMES (frame-times.lisp), worked out when first asked."
  controller presenter (end 0d0) (fps 30) (%frame-times nil))

(defparameter *max-fps* 1000
  "The highest frame rate SIMULATE and RENDER-SIMULATION accept.")

(defun check-fps (function fps)
  "FPS when it is a frame rate above 0 and at most *MAX-FPS*; else an ARGUMENT-ERROR of FUNCTION."
  (check-real function :fps fps :above 0 :maximum *max-fps*))

(defun simulate (spec &key initial events until when-busy (fps 30) (seed 0) scripts body stream silent)
  "Play EVENTS on a controller of SPEC from INITIAL (an alist, as for MAKE-CONTROLLER)
with a body presenter (SCRIPTS, BODY and SEED as for MAKE-BODY-PRESENTER; trace
lines to STREAM).  Each entry of EVENTS is a NAME, sent when the events before
it have ended, or (NAME . SECONDS), arriving at that time whatever is running
(a timed controller then resolves it by the event's :when-busy policy, or by
WHEN-BUSY if given); with UNTIL (seconds) the clock stops there.  With
SILENT, :say and :sound items play nothing.  Returns a SIMULATION;
SIMULATION-FRAMES samples it."
  (check-body-presenter-arguments 'simulate spec scripts body seed stream *default-blend-time*)
  (check-argument 'simulate :initial initial #'initial-state-p *initial-state-phrase*)
  (check-argument 'simulate :events events
                  (lambda (x) (and (alexandria:proper-list-p x) (every #'event-entry-p x)))
                  "a proper list of event names (symbols or strings) or (NAME . SECONDS) pairs")
  (when until (check-seconds 'simulate :until until :minimum 0))
  (check-fps 'simulate fps)
  (let* ((presenter (make-body-presenter spec :scripts scripts :body body :seed seed :stream stream
                                                    :silent silent))
         (controller (make-controller (compile-spec (if (spec-p spec) spec (find-spec spec)))
                                      :initial-state initial :presenter presenter
                                      :timed (timed-scenario-p events until))))
    (dolist (entry events)
      (find-compiled-event controller (event-entry-name entry) 'simulate))
    (play-events controller events :until until :when-busy when-busy)
    ;; Played on until the body has settled, so the last frame shows the settled
    ;; pose -- unless the caller stopped the clock with UNTIL.
    (%make-simulation :controller controller :presenter presenter
                      :end (if until
                               (controller-clock controller)
                               (performance-settled-time (presenter-performance presenter)
                                                         (controller-clock controller)))
                      :fps fps)))

(defun controller-simulation (controller &key (fps 30) end)
  "A SIMULATION of what CONTROLLER (made with a body presenter) has played so
far, from 0 to END seconds (default: its clock), sampled at FPS: for a caller
that sent the events itself, as a conversation does, rather than through SIMULATE."
  (check-argument 'controller-simulation 'controller controller
                  (lambda (x) (and (controller-p x) (typep (controller-presenter x) 'body-presenter)))
                  "a controller whose presenter is a body presenter (from make-body-presenter)")
  (check-fps 'controller-simulation fps)
  (when end (check-seconds 'controller-simulation :end end :minimum 0))
  (%make-simulation :controller controller :presenter (controller-presenter controller)
                    :end (float (or end (controller-clock controller)) 1d0) :fps fps))

(defun simulation-performance (simulation)
  "The performance SIMULATION's presenter played."
  (presenter-performance (simulation-presenter simulation)))

(defgeneric simulation-critical-times (simulation)
  (:documentation "The critical times SIMULATION's scripts reach, in seconds,
earliest first: a frame must show each.  A scene of several characters
\(src/cast/) may add a method.")
  (:method ((simulation simulation))
    ;; A simulation without a presenter of its own (a scene's) has none here.
    (and (simulation-presenter simulation)
         (performance-critical-times (simulation-performance simulation) (simulation-end simulation)))))

(defun simulation-frame-times (simulation &optional (fps (simulation-fps simulation)))
  "The times of SIMULATION's frames at FPS (default its own), a vector of
double-floats: the grid of 1/FPS from 0 to its end, each critical time its
scripts reach shown by the nearest frame moved onto it (frame-times.lisp)."
  (check-argument 'simulation-frame-times 'simulation simulation #'simulation-p "a simulation (from simulate)")
  (check-fps 'simulation-frame-times fps)
  (flet ((compute () (critical-frame-times (simulation-end simulation) fps (simulation-critical-times simulation))))
    (if (= fps (simulation-fps simulation))
        (or (simulation-%frame-times simulation)
            (setf (simulation-%frame-times simulation) (compute)))
        (compute))))

(defun simulation-frame-count (simulation)
  "How many frames cover SIMULATION, the first at time 0 and the last at or after its end."
  (check-argument 'simulation-frame-count 'simulation simulation #'simulation-p "a simulation (from simulate)")
  (length (simulation-frame-times simulation)))

(defun simulation-frame-time (simulation index)
  "The time of frame INDEX of SIMULATION."
  (aref (simulation-frame-times simulation) index))

(defgeneric simulation-clips (simulation end)
  (:documentation "The audio clips SIMULATION plays once played to END seconds,
oldest first.  A scene of several characters (src/cast/) adds a method.")
  (:method ((simulation simulation) end)
    (performance-clips (simulation-performance simulation) end)))

(defun write-simulation-audio (simulation end path)
  "Write SIMULATION's audio track from 0 to END seconds, every clip that starts
by then mixed, to the WAV file PATH and return its truename; when nothing
sounds, return NIL and leave PATH alone."
  (let ((clips (remove-if (lambda (clip) (>= (clip-start clip) end))
                          (simulation-clips simulation end))))
    (and clips (write-wav path (mix-clips clips :end end)))))

(defgeneric simulation-scene-at (simulation time)
  (:documentation "The scene of SIMULATION at TIME seconds, to draw or sample (its
objects change with the next call).  A scene of several characters
\(src/cast/) adds a method.")
  (:method ((simulation simulation) time)
    (performance-frame (simulation-performance simulation) time))
  (:method (simulation time)
    (declare (ignore time))
    (check-argument 'simulation-scene-at 'simulation simulation #'simulation-p "a simulation (from simulate)")))

(defun map-simulation-frames (function simulation)
  "Call FUNCTION with each frame's index, time and scene, in order."
  (check-argument 'map-simulation-frames 'function function
                  (lambda (x) (or (functionp x) (and (symbolp x) x (fboundp x))))
                  "a function (or a symbol naming one) of the index, time and scene")
  (check-argument 'map-simulation-frames 'simulation simulation #'simulation-p "a simulation (from simulate)")
  (dotimes (index (simulation-frame-count simulation))
    (let ((time (simulation-frame-time simulation index)))
      (funcall function index time (simulation-scene-at simulation time)))))

(defun simulation-body (simulation)
  "The character's body in SIMULATION's current scene."
  (performance-body (simulation-performance simulation)))

;;;# Output

(defun frame-form (index time scene)
  "Frame INDEX at TIME as an s-expression: every body's placement and every
joint's rotation (as a quaternion and as its DOF angles in degrees), every
other object's parent, position and rotation."
  (flet ((numbers (&rest xs) (mapcar (lambda (x) (/ (round x 1d-6) 1d6)) xs))
         (vector-list (v) (list (vec3-x v) (vec3-y v) (vec3-z v)))
         (quat-list (q) (list (quat-w q) (quat-x q) (quat-y q) (quat-z q))))
    (list :frame index :time (/ (round time 1d-6) 1d6)
          :bodies
          (loop for object in (scene-objects scene)
                when (typep object 'body)
                  collect (let ((pose (body-pose object))
                                ;; The world placement: a cast member's body hangs from its stage.
                                (placement (object-world-transform object)))
                            (list (object-name object)
                                  :position (apply #'numbers (vector-list (transform-translation placement)))
                                  :rotation (apply #'numbers (quat-list (transform-rotation placement)))
                                  :joints
                                  (loop for joint across (skeleton-joints (body-skeleton object))
                                        collect (list (body-joint-name joint)
                                                      :rotation (apply #'numbers (quat-list (joint-local-rotation joint pose)))
                                                      :dofs (loop for dof in (body-joint-dofs joint)
                                                                  for i from (body-joint-dof-start joint)
                                                                  append (list (body-dof-name dof)
                                                                               (first (numbers (aref pose i))))))))))
          :objects
          ;; Read only: each world transform once, however long the chains.
          (with-world-transforms-memoised ()
           (loop for object in (scene-objects scene)
                unless (typep object 'body)
                  collect (let ((parent (object-parent object)))
                            (list (object-name object)
                                  :parent (etypecase parent
                                            (null nil)
                                            (scene-object (object-name parent))
                                            (cons (list (object-name (car parent)) (cdr parent))))
                                  :position (apply #'numbers (vector-list (object-world-position object)))
                                  :rotation (apply #'numbers (quat-list (transform-rotation (object-world-transform object)))))))))))

(defun simulation-duration (simulation)
  "The seconds SIMULATION's frames span: its frame count over its frame rate."
  (/ (simulation-frame-count simulation) (float (simulation-fps simulation) 1d0)))

(defun write-simulation (simulation &key bvh frames audio)
  "Sample SIMULATION once and write the character's motion as BVH to the file BVH
and, to the file FRAMES, one FRAME-FORM per line; with AUDIO, the audio track
\(speech and sounds) to that WAV file when anything sounds (an old one is left
alone otherwise: nothing the caller did not name is deleted).  Returns the paths
written."
  (check-argument 'write-simulation 'simulation simulation #'simulation-p "a simulation (from simulate)")
  (check-argument 'write-simulation :bvh bvh (lambda (x) (or (null x) (pathname-designator-p x)))
                  (format nil "NIL or ~A" *path-phrase*))
  (check-argument 'write-simulation :frames frames (lambda (x) (or (null x) (pathname-designator-p x)))
                  (format nil "NIL or ~A" *path-phrase*))
  (check-argument 'write-simulation :audio audio (lambda (x) (or (null x) (pathname-designator-p x)))
                  (format nil "NIL or ~A" *path-phrase*))
  (let ((poses '()) (placements '()))
    (flet ((sample (frame-stream)
           (map-simulation-frames
            (lambda (index time scene)
              (let ((body (simulation-body simulation)))
                (push (copy-pose (body-pose body)) poses)
                (push (object-world-transform body) placements)
                (when frame-stream
                  (with-standard-io-syntax
                    (let ((*package* (find-package '#:player-user))
                          (*read-default-float-format* 'double-float)
                          (*print-case* :downcase)
                          (*print-readably* nil))
                      (prin1 (frame-form index time scene) frame-stream)
                      (terpri frame-stream))))))
            simulation)))
      ;; The frames file is replaced only once every frame is on the disk, and
      ;; the BVH and the audio are written: the outputs change as a set.
      (let ((commit-frames (if frames
                               (stage-output-file frames #'sample :make-directories t)
                               (progn (sample nil) nil)))
            (committed nil))
        (unwind-protect
             (let ((bvh-paths (and bvh (list (write-bvh-file bvh (body-skeleton (simulation-body simulation))
                                                             (nreverse poses)
                                                             :frame-time (/ 1d0 (simulation-fps simulation))
                                                             :placements (nreverse placements)))))
                   (audio-paths (and audio (remove nil (list (write-performance-audio
                                                              (simulation-performance simulation)
                                                              (simulation-duration simulation) audio))))))
               (when commit-frames (funcall commit-frames) (setf committed t))
               (append bvh-paths (and frames (list (truename frames))) audio-paths))
          (when (and commit-frames (not committed)) (funcall commit-frames t)))))))

(defgeneric simulation-reports (simulation)
  (:documentation "What the drivers reported (reaches that fell short), oldest first, as (TIME TEXT).")
  (:method ((simulation simulation))
    (mapcar (lambda (entry) (list (first entry) (third entry)))
            (reverse (body-reports (simulation-body simulation))))))
