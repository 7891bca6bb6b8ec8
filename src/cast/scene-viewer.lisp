;;;; scene-viewer.lisp -- `view` on a scene: every member drawn in one
;;;; window, live.  Keys send the scene's own events, then each event of the
;;;; first member's spec to all members (all/EV); an address typed at the
;;;; terminal (left/ev-search) reaches only the members it names.  Trace lines
;;;; print as their time comes, prefixed "MEMBER: ".

(in-package #:player.cast)

(defstruct (scene-viewer (:include viewer) (:constructor %make-scene-viewer))
  "A VIEWER of a scene: its ENSEMBLE (timed controllers, body presenters), the
SIMULATION gathering the members' frames, and how many trace lines of each
member have been PRINTED-LINES (a hash table from member names)."
  ensemble simulation (printed-lines (make-hash-table :test 'eq)))

(defun ensemble-controllers (ensemble)
  "ENSEMBLE's controllers, in member order."
  (mapcar #'performer-controller (ensemble-performers ensemble)))

(defmethod view-send-event ((viewer scene-viewer) event)
  (let ((ensemble (scene-viewer-ensemble viewer)))
    (handler-case
        (send-scene-event ensemble event
                          :at (reduce #'max (mapcar #'controller-time (ensemble-controllers ensemble))
                                      :initial-value (viewer-now viewer)))
      (scene-error () (error 'unknown-event :name (princ-to-string event))))))

(defmethod advance-viewer ((viewer scene-viewer))
  (dolist (controller (ensemble-controllers (scene-viewer-ensemble viewer)))
    (advance controller (max (viewer-now viewer) (controller-time controller)))))

(defmethod viewer-clips ((viewer scene-viewer))
  ;; A scene viewer has no performance of its own: each member has one.
  (loop for (nil . member) in (scene-simulation-members (scene-viewer-simulation viewer))
        append (replay-clips (simulation-performance member))))

(defmethod viewer-scene ((viewer scene-viewer) time)
  (simulation-scene-at (scene-viewer-simulation viewer) time))

(defmethod print-due-trace ((viewer scene-viewer) &optional (time (viewer-now viewer)))
  (let ((printed (scene-viewer-printed-lines viewer)))
    (dolist (performer (ensemble-performers (scene-viewer-ensemble viewer)))
      (let* ((name (performer-name performer))
             (presenter (controller-presenter (performer-controller performer)))
             (lines (trace-line-vector presenter))
             (dropped (trace-dropped presenter))
             (count (max (gethash name printed 0) dropped)))
        (loop while (< (- count dropped) (length lines))
              do (let ((line (aref lines (- count dropped))))
                   (unless (trace-line-due-p presenter line time)
                     (return))
                   (write-scene-trace-line name line)
                   (incf count)))
        (setf (gethash name printed) count))))
  (finish-output))

(defmethod view-title ((viewer scene-viewer))
  (format nil "~A -- ~{~A~^, ~}~:[~; [paused]~]" (viewer-name viewer)
          (mapcar (lambda (p) (lisp-text (performer-name p)))
                  (ensemble-performers (scene-viewer-ensemble viewer)))
          (viewer-paused-at viewer)))

(defun scene-event-keys (cast)
  "The key map of CAST's viewer: its scene events, then all/EV for each event
of its first member's spec, as an alist from characters (NIL past the last
key: typed by name) to addresses."
  (event-key-map
   (loop for address in (append (mapcar (lambda (e) (lisp-text (car e))) (cast-events cast))
                                (mapcar (lambda (event) (format nil "all/~A" (lisp-text (event-name event))))
                                        (spec-events (find-spec (cast-member-spec (first (cast-members cast)))))))
         ;; Symbols, so the key map prints them bare.
         collect (intern (string-upcase address) '#:player-user))))

(defun view-scene (cast &key initial body scripts frames screenshot (size '(640 480)) (seed 0) keys)
  "Open a window and play every member of CAST (a cast or a scene's name) live
on its body, as VIEW-SPEC does for one spec (INITIAL, BODY, SCRIPTS, FRAMES,
SCREENSHOT, SIZE, SEED, KEYS; the key map is SCENE-EVENT-KEYS).  Signals what
VIEW-SPEC signals."
  (let* ((cast (designated-cast cast 'view-scene))
         (event-keys (scene-event-keys cast)))
    (check-argument 'view-scene :frames frames (lambda (x) (or (null x) (typep x '(integer 1))))
                    "NIL or a positive integer")
    (let ((problem (scripted-keys-problem keys event-keys)))
      (when problem (error 'player-error-with-message :message problem)))
    (let* ((presenters (member-presenters cast scripts body seed))
           (ensemble (make-ensemble cast :initial initial :timed t
                                         :presenter (lambda (member)
                                                      (gethash (cast-member-name member) presenters)))))
      (show-viewer (lambda (window)
                     (%make-scene-viewer :window window :name (lisp-text (cast-name cast))
                                         :controller (performer-controller (first (ensemble-performers ensemble)))
                                         :ensemble ensemble :simulation (ensemble-simulation ensemble 30)
                                         :keys event-keys :script (sort (copy-list keys) #'< :key #'car)))
                   (lisp-text (cast-name cast)) event-keys
                   :size size :frames frames :screenshot screenshot))))
