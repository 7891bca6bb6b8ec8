;;;; test-polish-scenes.lisp -- the shipped scenes place their members clear
;;;; of the set's pieces (no body inside a piece, none hidden behind one from
;;;; the camera), and each member brings his own note: the scene draws one
;;;; note per member, at his feet or in his hand, never the set's beside his
;;;; (src/cast/scene-set.lisp).

(in-package #:player-tests)

(def-suite* polish-scenes :in player-tests)

(defun shipped-scene-files ()
  "The files of specs/ that define a scene."
  (remove-if-not (lambda (path) (search "(defscene" (alexandria:read-file-into-string path)))
                 (directory (checkout-file "specs/*.lisp"))))

(defun world-box (object)
  "The box around the prop OBJECT's shape where it stands: two lists MIN and MAX of x y z."
  (let* ((shape (player.physics:prop-shape object))
         (half (mapcar (lambda (x) (/ x 2)) (rest shape)))
         (transform (player.body:object-world-transform object))
         (corners (loop for sx in '(-1 1) append
                    (loop for sy in '(-1 1) append
                      (loop for sz in '(-1 1)
                            collect (player.body:transform-point
                                     transform (player.body::make-vec3 (* sx (first half)) (* sy (second half))
                                                                       (* sz (third half)))))))))
    (flet ((coordinates (v) (list (player.body:vec3-x v) (player.body:vec3-y v) (player.body:vec3-z v))))
      (values (reduce (lambda (a b) (mapcar #'min a b)) (mapcar #'coordinates corners))
              (reduce (lambda (a b) (mapcar #'max a b)) (mapcar #'coordinates corners))))))

(defun boxes-meet-p (low-a high-a low-b high-b)
  "Do the boxes (LOW-A HIGH-A) and (LOW-B HIGH-B) share a volume?"
  (every (lambda (la ha lb hb) (and (< la hb) (< lb ha))) low-a high-a low-b high-b))

(defun set-pieces (frame)
  "The set's pieces in the scene FRAME: its visible props with a box shape
that stand above the table top (the members stand on the table), none a
member's own (those hang from a member's stage or body)."
  (remove-if-not (lambda (object)
                   (and (eq :prop (player.body:object-kind object))
                        (player.body:property-value object 'player.body:visible)
                        (null (player.body:object-parent object))
                        (eq :box (first (player.physics:prop-shape object)))
                        (> (second (nth-value 1 (world-box object))) 0.005)))
                 (player.body:scene-objects frame)))

(defun check-members-clear-of-the-set (cast label)
  "Check each member's body of CAST at rest, stretched toward the camera (so
a piece in front of him counts), meets none of the set's pieces; LABEL
names the case in failures."
  (let* ((frame (player.performance:simulation-scene-at (player.cast:simulate-scene cast :fps 10) 0d0))
         (pieces (set-pieces frame))
         (bodies (remove-if-not (lambda (o) (typep o 'player:body)) (player.body:scene-objects frame))))
    (is (>= (length pieces) 2) "~A: only ~D set pieces: no test" label (length pieces))
    (is (= (length (player.cast:cast-members cast)) (length bodies)))
    (dolist (body bodies)
      (multiple-value-bind (low high) (player.render::body-rest-extent body)
        (let ((low (list (player.body:vec3-x low) (player.body:vec3-y low) (player.body:vec3-z low)))
              (high (list (player.body:vec3-x high) (player.body:vec3-y high) 100d0)))
          (dolist (piece pieces)
            (multiple-value-bind (piece-low piece-high) (world-box piece)
              (is (not (boxes-meet-p low high piece-low piece-high))
                  "~A: ~A stands in or behind ~A (~A..~A against ~A..~A)"
                  label (player.body:object-name body) (player.body:object-name piece)
                  low high piece-low piece-high))))))))

(test shipped-scenes-place-their-members-clear-of-the-set
  "In every shipped scene, no member stands in one of the set's pieces or
behind one, and the members stay where its :at puts them."
  (let ((files (shipped-scene-files)))
    (is (plusp (length files)) "no shipped scene: no test")
    (dolist (file files)
      (dolist (cast (load-scene-file file))
        (let ((places (mapcar #'player.cast:cast-member-position (player.cast:cast-members cast))))
          (check-members-clear-of-the-set cast (file-namestring file))
          (is (equal places (mapcar #'player.cast:cast-member-position (player.cast:cast-members cast)))
              "~A: members placed with :at were moved" (file-namestring file)))))))

(test members-in-a-row-stand-clear-of-the-set
  "Peedys placed in a row (--cast peedy:N, no :at), which at 0.6 m apart
about the origin would stand in the jukebox or behind the panel, are moved
clear of them, the row kept whole: its spacing is unchanged."
  (load-spec (checkout-file "specs/peedy.lisp"))
  (dolist (count '(2 3))
    (let ((cast (player.cast:replicate-cast 'peedy count)))
      (check-members-clear-of-the-set cast (format nil "peedy:~D" count))
      (let ((xs (mapcar (lambda (member) (first (player.cast:cast-member-position member)))
                        (player.cast:cast-members cast))))
        (is (every (lambda (a b) (< (abs (- (- b a) 0.6d0)) 1d-9)) xs (rest xs))
            "peedy:~D: the row is no longer 0.6 m apart: ~A" count xs)))))

(defun visible-notes (frame)
  "The notes FRAME draws."
  (remove-if-not (lambda (object) (and (string-equal (symbol-name (player.body:object-name object)) "NOTE")
                                       (player.body:property-value object 'player.body:visible)))
                 (player.body:scene-objects frame)))

(test each-member-brings-his-own-note
  "Two Peedys: a note lies at each one's feet, none in the middle; while the
right one holds his, it is in his hand and the left one's still lies at his
feet -- never his and the set's side by side."
  (let* ((cast (first (load-scene-file (checkout-file "specs/two-peedys.lisp"))))
         (places (mapcar (lambda (member) (first (player.cast:cast-member-position member)))
                         (player.cast:cast-members cast)))
         (simulation (player.cast:simulate-scene cast :events '("right/ev-search") :fps 10)))
    (flet ((note-xs (time)
             (sort (mapcar (lambda (note) (player.body:vec3-x (player.body:object-world-position note)))
                           (visible-notes (player.performance:simulation-scene-at simulation time)))
                   #'<)))
      (let ((start (note-xs 0d0)))
        (is (= 2 (length start)) "~D notes at the start" (length start))
        (loop for x in start for place in places
              do (is (< (abs (- x place)) 0.15) "a note lies at x = ~,2F, the member stands at ~,2F" x place)))
      ;; Asleep, right wakes and stands (4 s), then searches: he takes his
      ;; note at about 6 s (fetch-note's grab) and holds it up.
      (let* ((frame (player.performance:simulation-scene-at simulation 6.8d0))
             (notes (visible-notes frame)))
        (is (= 2 (length notes)) "~D notes while he holds his" (length notes))
        (is (= 1 (count-if #'player.cast::hangs-from-body-p notes)) "not one note in a hand: ~A" notes)
        (is (< (abs (- (player.body:vec3-x (player.body:object-world-position
                                            (find-if-not #'player.cast::hangs-from-body-p notes)))
                       (first places)))
               0.15)
            "the note not held is not at the left one's feet")))))
