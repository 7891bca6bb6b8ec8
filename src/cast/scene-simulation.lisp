;;;; scene-simulation.lisp -- a scene of several characters played in
;;;; simulated time (what `simulate`, `render` and `view` run on a scene).
;;;; Each member plays on a performance of its own, its whole world (body,
;;;; props, camera) standing at the member's place, so a member moves exactly
;;;; as it would alone; a frame of the scene gathers every member's bodies
;;;; into one set (scene-set.lisp), seen by the set's camera, or by one
;;;; framing them all when it would lose one.

(in-package #:player.cast)

(defstruct (scene-simulation (:include simulation) (:constructor %make-scene-simulation))
  "A played scene: its ENSEMBLE, MEMBERS (an alist from each member's name to
its own SIMULATION) and the COMPOSITE scene frames are gathered into.  END is
the last member's end."
  ensemble members (composite (make-instance 'scene))
  ;; The performance of the scene's own set, or NIL (the first member's
  ;; world is the set), and the set's copies of its objects (scene-set.lisp).
  (set nil)
  (proxies (make-hash-table :test 'eq :weakness :key))
  ;; The names of the props the members' scripts carry: each member's own.
  (carried '()))

(defun member-presenters (cast scripts body seed)
  "A table from each member's name in CAST to a body presenter placing its
world at the member's position (SCRIPTS, BODY and SEED as for
MAKE-BODY-PRESENTER), the members placed in a row first moved clear of the
set (PLACE-CAST-CLEAR-OF-SET).  Each spec's library is read and checked
once (MEMBER-PROBES), so a big cast reads it once."
  (let ((probes (member-probes cast scripts body seed))
        (presenters (make-hash-table :test 'eq)))
    (place-cast-clear-of-set cast probes)
    (dolist (member (cast-members cast) presenters)
      (let ((spec (find-spec (cast-member-spec member))))
        (setf (gethash (cast-member-name member) presenters)
              (make-body-presenter spec :scripts (presenter-library (gethash spec probes))
                                        :body body :seed seed
                                        :name (cast-member-name member)
                                        :origin (apply #'vec3 (cast-member-position member))
                                        :check nil))))))

(defun simulate-scene (cast &key initial events until when-busy (fps 30) (seed 0) scripts body)
  "Play EVENTS (addresses as for PLAY-SCENE-EVENTS) on every member of CAST (a
cast or a scene's name) in simulated time, each on its body placed at its
position, from INITIAL; UNTIL, WHEN-BUSY, FPS, SEED, SCRIPTS and BODY as for
SIMULATE.  Returns a SCENE-SIMULATION, which RENDER-SIMULATION draws and
WRITE-SCENE-SIMULATION writes.  Signals what SIMULATE signals, and an
UNKNOWN-MEMBER-ERROR for an address naming no member."
  (let ((cast (designated-cast cast 'simulate-scene)))
    (check-argument 'simulate-scene :events events
                    (lambda (x) (and (alexandria:proper-list-p x) (every #'event-entry-p x)))
                    "a proper list of event addresses (symbols or strings) or (ADDRESS . SECONDS) pairs")
    (when until (check-seconds 'simulate-scene :until until :minimum 0))
    (check-fps 'simulate-scene fps)
    ;; Addresses first: a wrong one fails before any library is read.
    (split-scene-events cast events)
    (let* ((presenters (member-presenters cast scripts body seed))
           (ensemble (make-ensemble cast :initial initial
                                         :timed (scene-timed-members cast events until when-busy)
                                         :presenter (lambda (member)
                                                      (gethash (cast-member-name member) presenters)))))
      (play-scene-events ensemble events :until until :when-busy when-busy)
      (ensemble-simulation ensemble fps))))

(defun ensemble-simulation (ensemble fps)
  "A SCENE-SIMULATION of ENSEMBLE, whose members' presenters are body
presenters, sampled at FPS and ending when its last member's clock does;
every member's frames (and BVH) cover that whole time."
  (let* ((members (loop for performer in (ensemble-performers ensemble)
                        for controller = (performer-controller performer)
                        collect (cons (performer-name performer)
                                      (%make-simulation :controller controller
                                                        :presenter (controller-presenter controller)
                                                        :end (controller-clock controller) :fps fps))))
         (end (reduce #'max members :key (lambda (m) (simulation-end (cdr m))))))
    (dolist (member members)
      (setf (simulation-end (cdr member)) end))
    (%make-scene-simulation :ensemble ensemble :members members :fps fps :end end
                            :set (set-performance (ensemble-cast ensemble))
                            :carried (members-carried-objects ensemble))))

(defun members-carried-objects (ensemble)
  "The names of the props the scripts of ENSEMBLE's members carry (see
LIBRARY-CARRIED-OBJECTS), each library asked once."
  (let ((libraries (remove-duplicates
                    (loop for performer in (ensemble-performers ensemble)
                          for presenter = (controller-presenter (performer-controller performer))
                          when (typep presenter 'body-presenter)
                            collect (presenter-library presenter)))))
    (remove-duplicates (mapcan #'library-carried-objects libraries)
                       :test #'string= :key #'symbol-name)))

(defun scene-simulation-member (simulation member)
  "The SIMULATION of SIMULATION's MEMBER (a member's name), or NIL."
  (check-argument 'scene-simulation-member 'simulation simulation #'scene-simulation-p
                  "a scene simulation (from simulate-scene)")
  (check-argument 'scene-simulation-member 'member member #'string-designator-p "a member's name (a symbol or string)")
  (cdr (assoc (string member) (scene-simulation-members simulation)
              :key #'symbol-name :test #'string-equal)))

(defmethod simulation-scene-at ((simulation scene-simulation) time)
  (let ((composite (scene-simulation-composite simulation))
        (members (loop for (nil . member) in (scene-simulation-members simulation)
                       collect (simulation-scene-at member time)))
        (set (scene-simulation-set simulation)))
    (setf (scene-objects composite)
          (gather-scene-objects (if set (performance-frame set time) (first members)) members
                                (scene-simulation-proxies simulation)
                                (scene-simulation-carried simulation)))
    composite))

(defmethod simulation-critical-times ((simulation scene-simulation))
  ;; Every member's: a frame of the scene shows each (frame-times.lisp).
  (sort (loop for (nil . member) in (scene-simulation-members simulation)
              append (copy-list (simulation-critical-times member)))
        #'<))

(defmethod simulation-reports ((simulation scene-simulation))
  (loop for (name . member) in (scene-simulation-members simulation)
        append (loop for (time text) in (simulation-reports member)
                     collect (list time (format nil "~A: ~A" (lisp-text name) text)))))

(defun member-file (path member type)
  "The file of PATH for MEMBER: PATH/MEMBER.TYPE when PATH is a directory (ends
in /), else PATH's name followed by -MEMBER, with PATH's type or else TYPE."
  (let ((path (pathname path)) (name (string-downcase (symbol-name member))))
    (if (pathname-name path)
        (make-pathname :name (format nil "~A-~A" (pathname-name path) name)
                       :type (or (pathname-type path) type) :defaults path)
        (make-pathname :name name :type type :defaults path))))

(defun write-scene-simulation (simulation &key bvh frames)
  "Write one BVH file per body of SIMULATION, a SCENE-SIMULATION: with BVH a
directory (ending in /), DIR/MEMBER.bvh; with a file, NAME-MEMBER.bvh beside it;
likewise one frames file per member (see WRITE-SIMULATION).  Each body's root
carries its member's place.  Returns the paths written."
  (check-argument 'write-scene-simulation 'simulation simulation #'scene-simulation-p
                  "a scene simulation (from simulate-scene)")
  (check-argument 'write-scene-simulation :bvh bvh (lambda (x) (or (null x) (pathname-designator-p x)))
                  (format nil "NIL or ~A" *path-phrase*))
  (check-argument 'write-scene-simulation :frames frames (lambda (x) (or (null x) (pathname-designator-p x)))
                  (format nil "NIL or ~A" *path-phrase*))
  (loop for (name . member) in (scene-simulation-members simulation)
        append (write-simulation member
                                 :bvh (and bvh (member-file bvh name "bvh"))
                                 :frames (and frames (member-file frames name "frames")))))

(defun scene-simulation-trace (simulation &optional (stream *standard-output*))
  "Write SIMULATION's trace, each member's lines in turn, prefixed \"MEMBER: \"."
  (write-ensemble-trace (scene-simulation-ensemble simulation) stream))

(defmethod simulation-clips ((simulation scene-simulation) end)
  ;; Every member speaks into the one track of the scene.
  (sort (loop for (nil . member) in (scene-simulation-members simulation)
              append (simulation-clips member end))
        #'< :key #'clip-start))
