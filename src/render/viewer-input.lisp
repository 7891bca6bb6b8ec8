;;;; viewer-input.lisp -- what the viewer takes from the user: keys that send
;;;; events, pause, orbit and zoom; the mouse; event names typed at the
;;;; terminal; the keys a script presses (--keys); and the key map printed at the start.

(in-package #:player.render)

;;;# Input

(defun orbit-by (viewer yaw pitch &optional (zoom 1d0))
  "Turn the camera YAW and PITCH radians around the characters and scale its distance by ZOOM."
  (let ((orbit (renderer-orbit (viewer-renderer viewer))))
    (setf (orbit-yaw orbit) (+ (orbit-yaw orbit) yaw)
          (orbit-pitch orbit) (max -1.45d0 (min 1.45d0 (+ (orbit-pitch orbit) pitch)))
          (orbit-distance orbit) (max 0.1d0 (min 10d0 (* (orbit-distance orbit) zoom))))))

(defun press-key (viewer key)
  "Act on KEY: an event key (a character in the key map), or a control key's name."
  (let ((step (/ pi 36)))
    (case key
      (:space (toggle-pause viewer))
      (:escape (glfw-close-window (viewer-window viewer)))
      (:home (let ((orbit (renderer-orbit (viewer-renderer viewer))))
               (setf (orbit-yaw orbit) 0d0 (orbit-pitch orbit) 0d0 (orbit-distance orbit) 1d0)))
      (:left (orbit-by viewer (- step) 0d0))
      (:right (orbit-by viewer step 0d0))
      (:up (orbit-by viewer 0d0 (- step)))
      (:down (orbit-by viewer 0d0 step))
      ((#\+ #\=) (orbit-by viewer 0d0 0d0 0.9d0))
      (#\- (orbit-by viewer 0d0 0d0 (/ 0.9d0)))
      (t (let ((entry (and (characterp key) (assoc (char-downcase key) (viewer-keys viewer)))))
           (when entry (view-send-event viewer (cdr entry))))))))

(defun handle-input (viewer input)
  "Act on one INPUT record from GLFW-POLL-INPUT."
  (destructuring-bind (kind &rest data) input
    (ecase kind
      (:key (destructuring-bind (code action mods) data
              (declare (ignore mods))
              (let ((name (and (not (and (viewer-key-handler viewer)
                                         (funcall (viewer-key-handler viewer) viewer code action)))
                               (car (rassoc code *view-control-keys*)))))
                (when (and name (or (= action +glfw-press+)
                                    (and (= action +glfw-repeat+) (member name '(:left :right :up :down)))))
                  (press-key viewer name)))))
      (:char (let ((char (code-char (first data))))
               (unless (or (null char) (char= char #\Space))
                 (press-key viewer char))))
      (:button (destructuring-bind (button action mods) data
                 (declare (ignore mods))
                 (when (= button +glfw-mouse-button-left+)
                   (setf (viewer-drag viewer) (and (= action +glfw-press+) :start)))))
      (:cursor (destructuring-bind (x y) data
                 (let ((drag (viewer-drag viewer)))
                   (when (consp drag)
                     (orbit-by viewer (* -0.01d0 (- x (car drag))) (* -0.01d0 (- y (cdr drag)))))
                   (when drag (setf (viewer-drag viewer) (cons x y))))))
      (:scroll (orbit-by viewer 0d0 0d0 (expt 0.9d0 (second data)))))))

(defun play-script-keys (viewer)
  "Press the scripted keys whose time (wall-clock seconds since the start) has come."
  (loop while (and (viewer-script viewer) (<= (car (first (viewer-script viewer))) (viewer-wall-time viewer)))
        do (press-key viewer (cdr (pop (viewer-script viewer))))))

;;;# The key map

(defun print-key-map (keys &optional (terminal t))
  "Print KEYS, an alist from characters to event names (NIL for an event that
has no key: it is typed by name), and the other controls; TERMINAL says
event names typed at the terminal are read too."
  (with-output-lock ()
    (format t "; keys (in the window)~:[~;, or an event name typed here and Enter~]:~%" terminal)
    (loop for (char . event) in keys
          do (if char
                 (format t "~C ~A~%" char (lisp-text event))
                 (format t "  ~A~:[ (no key; not readable without a terminal)~;~]~%" (lisp-text event) terminal)))
    (write-line *view-help*)
    (finish-output)))

(defun event-key-map (names)
  "The key map of a viewer sending the events NAMES: an alist giving each of
the first ones a key of *VIEW-EVENT-KEYS*, in order, and the rest NIL (they
are typed by name)."
  (loop for name in names
        for k from 0
        collect (cons (and (< k (length *view-event-keys*)) (char *view-event-keys* k)) name)))

(defun view-event-keys (spec)
  "The key map of SPEC's viewer: an alist from characters to event names, in
spec order, every event past the keys there are under NIL (see EVENT-KEY-MAP)."
  (event-key-map (mapcar #'event-name (spec-events spec))))

(defun scripted-keys-problem (keys event-keys)
  "Why the scripted KEYS ((SECONDS . KEY) ...) cannot be pressed in a viewer
with EVENT-KEYS, as a message; NIL when they all can."
  (loop for (nil . key) in keys
        unless (or (assoc key *view-control-keys*) (and key (assoc key event-keys)) (member key '(#\+ #\= #\-)))
          return (format nil "the scripted key ~A is neither an event's (~{~A~}) nor +, - or one of ~{~(~A~)~^, ~}"
                         key (remove nil (mapcar #'car event-keys)) (mapcar #'car *view-control-keys*))))
