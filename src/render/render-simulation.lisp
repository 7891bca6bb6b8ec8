;;;; render-simulation.lisp -- a simulated scenario drawn offscreen to
;;;; numbered PNG frames, a contact sheet of frames spread over the whole
;;;; scenario, and optionally a video piped through ffmpeg (what `player
;;;; render` runs).

(in-package #:player.render)

(defparameter *ffmpeg-program* "ffmpeg"
  "The ffmpeg executable --video runs: a name looked up in PATH, or a path.")

(defparameter *sheet-columns* 4 "Thumbnails per row of the contact sheet.")
(defparameter *sheet-rows* 3 "Rows of thumbnails of the contact sheet, at most.")
(defparameter *thumbnail-width* 320 "The widest a contact-sheet thumbnail may be, in pixels.")

;;;# Checking what the user asked for

(defparameter *max-image-side* 4096 "The widest and tallest image, in pixels, that Player renders.")

(defun read-size (text)
  "The width and height (two values) TEXT, like \"640x480\" or \"640X480\",
gives, or NIL when it is not two integers from 1 to *MAX-IMAGE-SIDE*."
  (let* ((x (position #\x (string-downcase text)))
         (width (and x (ignore-errors (parse-integer text :end x))))
         (height (and x (ignore-errors (parse-integer text :start (1+ x))))))
    (if (and width height (<= 1 width *max-image-side*) (<= 1 height *max-image-side*))
        (values width height)
        nil)))

(defun image-size (size)
  "SIZE, a list (WIDTH HEIGHT) or a text \"WxH\", as two values; a RENDER-ERROR
unless both are integers from 1 to *MAX-IMAGE-SIDE*."
  (multiple-value-bind (width height)
      (typecase size
        (string (read-size size))
        (cons (and (alexandria:proper-list-p size) (= (length size) 2)
                   (every (lambda (n) (typep n `(integer 1 ,*max-image-side*))) size)
                   (values-list size))))
    (unless width
      (render-fail "bad size ~A: give WIDTHxHEIGHT, two integers from 1 to ~D (e.g. 640x480)"
                   (if (stringp size) (bounded-lisp-text size 60) (bounded-lisp-text size 60)) *max-image-side*))
    (values width height)))

(defun find-ffmpeg ()
  "The path of *FFMPEG-PROGRAM*; a RENDER-ERROR naming the Debian package when it is not installed."
  (let ((path (find-executable *ffmpeg-program*)))
    (or path
        (render-fail "writing a video needs ~A, which is not installed: install the Debian package ffmpeg"
                     *ffmpeg-program*))))

(defun prepare-output-directory (out)
  "OUT (a directory designator) as a directory pathname that exists and takes
files (a probe file is created exclusively, never through a link, and removed).
Nothing in it is removed here: a render replaces its files as a set when it
has made them all (RENDER-SIMULATION).  Signals a RENDER-ERROR naming the
directory otherwise."
  (let ((directory (directory-pathname out)))
    (handler-case (check-writable-directory directory)
      ((or io-error file-error) (e)
        (render-fail "cannot write into the output directory ~A: ~A" (namestring directory)
                     (condition-reason e))))))

(defun old-render-files (directory)
  "The files an earlier render left in DIRECTORY that a new render replaces or removes."
  ;; The links themselves, not what they point to: a planted link is removed, its target never.
  (append (directory (merge-pathnames "frame-*.png" directory) :resolve-symlinks nil)
          (directory (merge-pathnames *audio-file-name* directory) :resolve-symlinks nil)))

;;;# Progress

(defparameter *progress-steps* 10
  "How many lines the progress makes where it cannot be redrawn in place: one every 10 %.")

(defun terminal-stream-p (stream)
  "Is STREAM a terminal, where a line can be redrawn in place with a carriage return?"
  (and (interactive-stream-p stream) t))

(defun progress-text (done total)
  "The progress line: a bar of 30 and DONE/TOTAL frames."
  (let ((filled (floor (* 30 done) (max 1 total))))
    (format nil "[~v,,,'#A~v,,,'.A] ~D/~D frames" filled "" (- 30 filled) "" done total)))

(defparameter *quiet-progress-seconds* 2
  "Seconds a render works before its progress lines start where they cannot be
redrawn in place: a short render in a script leaves its stderr empty (or
holding only its one error line), as the CLI's other progress does.")

(defun show-progress (stream done total &optional (terminal (and stream (terminal-stream-p stream))) since)
  "Show that DONE of TOTAL frames are drawn on STREAM (NIL: nowhere).  On a
TERMINAL the line is redrawn in place (a newline when done); elsewhere (a log,
a pipe) a line is written each time another tenth is done, so a log holds
*PROGRESS-STEPS* lines, not one per frame -- and, given SINCE (the internal
real time the render began), only once it has worked *QUIET-PROGRESS-SECONDS*."
  (when stream
    (cond (terminal
           (format stream "~C~A" #\Return (progress-text done total))
           (when (= done total) (terpri stream)))
          ((and (or (null since)
                    (>= (- (get-internal-real-time) since)
                        (* *quiet-progress-seconds* internal-time-units-per-second)))
                (> (floor (* *progress-steps* done) (max 1 total))
                   (floor (* *progress-steps* (1- done)) (max 1 total))))
           (write-line (progress-text done total) stream)))
    (force-output stream)))

;;;# The contact sheet

(defun thumbnail (pixels width height factor)
  "PIXELS (WIDTH x HEIGHT RGBA, top-down) shrunk by the integer FACTOR, each
thumbnail pixel the mean of its FACTOR x FACTOR block: RGBA bytes and the new size."
  (declare (type octets pixels) (type (integer 1 4096) width height factor)
           (optimize (speed 2) (safety 1)))
  (let* ((w (floor width factor)) (h (floor height factor))
         (out (make-array (* w h 4) :element-type '(unsigned-byte 8)))
         (area (* factor factor)))
    (dotimes (y h (values out w h))
      (dotimes (x w)
        (dotimes (c 4)
          (let ((sum 0))
            (declare (type fixnum sum))
            (dotimes (dy factor)
              (dotimes (dx factor)
                (incf sum (aref pixels (+ c (* 4 (+ (* x factor) dx (* width (+ (* y factor) dy)))))))))
            (setf (aref out (+ c (* 4 (+ x (* w y))))) (round sum area))))))))

(defparameter *digit-glyphs*
  '((#\0 "111" "101" "101" "101" "111") (#\1 "010" "110" "010" "010" "111")
    (#\2 "111" "001" "111" "100" "111") (#\3 "111" "001" "111" "001" "111")
    (#\4 "101" "101" "111" "001" "001") (#\5 "111" "100" "111" "001" "111")
    (#\6 "111" "100" "111" "101" "111") (#\7 "111" "001" "010" "010" "010")
    (#\8 "111" "101" "111" "101" "111") (#\9 "111" "101" "111" "001" "111")
    (#\. "000" "000" "000" "000" "010") (#\s "011" "100" "010" "001" "110")
    (#\Space "000" "000" "000" "000" "000"))
  "A 3x5 pixel font for the times on the contact sheet.")

(defun draw-label (pixels width text x y &key (scale 2))
  "Write TEXT in the 3x5 font, SCALE pixels a dot, dark on a light box, into the
RGBA image PIXELS of WIDTH at column X, row Y (its top left)."
  (let ((box-width (+ 2 (* scale 4 (length text)))) (box-height (+ 2 (* scale 6))))
    (dotimes (dy box-height)
      (dotimes (dx box-width)
        (replace pixels #(245 245 240 255) :start1 (* 4 (+ x dx (* width (+ y dy)))))))
    (loop for char across text
          for left from (+ x 1 scale) by (* 4 scale)
          do (loop for row in (rest (assoc char *digit-glyphs*))
                   for top from (+ y 1 scale) by scale
                   do (loop for dot across row
                            for column from left by scale
                            when (char= dot #\1)
                              do (dotimes (dy scale)
                                   (dotimes (dx scale)
                                     (replace pixels #(30 30 30 255)
                                              :start1 (* 4 (+ column dx (* width (+ top dy))))))))))))

(defun sheet-frame-indices (count)
  "Which of COUNT frames the contact sheet shows: up to columns x rows, evenly
spaced from the first to the last."
  (let ((cells (min count (* *sheet-columns* *sheet-rows*))))
    (remove-duplicates (loop for k below cells
                             collect (if (= cells 1) 0 (round (* k (1- count)) (1- cells)))))))

(defparameter *row-label-scale* 2
  "Pixels a side of a dot of the caption font in a contact sheet's row labels.")

(defun draw-text (pixels width text x y &key (scale *row-label-scale*) (colour #(235 235 228 255)))
  "Write TEXT in the caption font (caption-font.lisp), SCALE pixels a dot, in
COLOUR into the RGBA image PIXELS of WIDTH, its top left at column X, row Y."
  (loop for (column row length) in (caption-text-runs text)
        do (dotimes (dy scale)
             (loop for px from (+ x (* column scale)) below (+ x (* (+ column length) scale))
                   do (replace pixels colour :start1 (* 4 (+ px (* width (+ y (* row scale) dy)))))))))

(defun row-label-width (labels)
  "The pixels the widest of LABELS (strings, or NIL for none) takes in the caption font."
  (* *row-label-scale* (reduce #'max labels :key #'caption-text-width :initial-value 0)))

(defun write-contact-sheet (path thumbnails width height &key row-labels)
  "Write the THUMBNAILS, a list of (PIXELS TIME) each WIDTH x HEIGHT, as a grid
with their times to the PNG file PATH, each row named by its string of
ROW-LABELS, if given, drawn in the caption font in a margin at the left.
Returns PATH."
  (let* ((gap 6)
         (margin (if row-labels (+ gap (row-label-width row-labels)) 0))
         (columns (min *sheet-columns* (length thumbnails)))
         (rows (ceiling (length thumbnails) columns))
         (sheet-width (+ margin gap (* columns (+ width gap))))
         (sheet-height (+ gap (* rows (+ height gap))))
         (sheet (make-array (* 4 sheet-width sheet-height) :element-type '(unsigned-byte 8))))
    (loop for i from 0 below (length sheet) by 4 do (replace sheet #(64 64 68 255) :start1 i))
    (loop for label in row-labels
          for row from 0 below rows
          do (draw-text sheet sheet-width label gap
                        (+ gap (* row (+ height gap)) (max 0 (floor (- height (* +glyph-rows+ *row-label-scale*)) 2)))))
    (loop for (pixels time) in thumbnails
          for k from 0
          do (multiple-value-bind (row column) (floor k columns)
               (let ((x (+ margin gap (* column (+ width gap)))) (y (+ gap (* row (+ height gap)))))
                 (dotimes (line height)
                   (replace sheet pixels :start1 (* 4 (+ x (* sheet-width (+ y line))))
                                         :start2 (* 4 width line) :end2 (* 4 width (1+ line))))
                 (let ((label (format nil "~,2F s" time)))
                   (when (and (>= width (+ 2 (* 8 (length label)))) (>= height 16))
                     (draw-label sheet sheet-width label (+ x 2) (+ y height -16)))))))
    (write-png path sheet-width sheet-height sheet)))

;;;# Video

(defun start-ffmpeg (path width height fps log &optional audio)
  "An ffmpeg process encoding raw RGBA frames of WIDTH x HEIGHT at FPS from its
input into the video file PATH, with the WAV file AUDIO as its sound track when
given, its messages going to the file LOG."
  (register-cleanup                     ; an interrupt kills it
   (sb-ext:run-program (namestring (find-ffmpeg))
                      (append (list "-y" "-loglevel" "error" "-f" "rawvideo" "-pix_fmt" "rgba"
                                    "-s" (format nil "~Dx~D" width height) "-r" (format nil "~A" fps)
                                    "-i" "-")
                              (if audio
                                  (list "-i" (namestring audio) "-map" "0:v" "-map" "1:a" "-c:a" "aac")
                                  (list "-an"))
                              (list "-vf" "pad=ceil(iw/2)*2:ceil(ih/2)*2"
                                    "-pix_fmt" "yuv420p" (namestring path)))
                      :input :stream :output nil :error (namestring log)
                      :if-error-exists :supersede :wait nil)))

(defun finish-ffmpeg (process path log)
  "Close PROCESS's input and wait for it; a RENDER-ERROR quoting LOG when it failed."
  (close (sb-ext:process-input process))
  (sb-ext:process-wait process)
  (unregister-cleanup process)
  (let ((code (sb-ext:process-exit-code process)))
    (unless (eql code 0)
      (render-fail "ffmpeg could not write ~A (exit ~A): ~A" path code
                   (string-trim '(#\Space #\Newline)
                                (or (ignore-errors (alexandria:read-file-into-string log)) ""))))
    (ignore-errors (delete-file log))))

;;;# Rendering a simulation

(defun render-simulation (simulation &key (out "render/") (size '(640 480)) fps video
                                          (progress *error-output*) (antialias :fxaa))
  "Draw SIMULATION offscreen at FPS (default its own) from time 0 to its end into
OUT: frame-0001.png, frame-0002.png ... and sheet.png, a contact sheet of frames
evenly spaced over the scenario with their times; speech.wav, the audio track
\(speech and sound effects), when anything sounds; with VIDEO (a path) also a
video encoded by ffmpeg, the audio track muxed in.  SIZE is (WIDTH HEIGHT) or
\"WxH\".  A progress bar goes to PROGRESS (a stream, or NIL).  Returns the paths
written: the frames, the sheet, speech.wav when written, then the video.  Signals a RENDER-ERROR for an unwritable OUT, a
missing ffmpeg or libOSMesa, or a bad SIZE; an ARGUMENT-ERROR for the other
arguments of the wrong kind."
  (check-argument 'render-simulation 'simulation simulation #'simulation-p "a simulation (from simulate)")
  (check-argument 'render-simulation :out out #'pathname-designator-p
                  "a directory's path (a string or pathname, not wild)")
  (when fps (check-fps 'render-simulation fps))
  (check-argument 'render-simulation :video video (lambda (x) (or (null x) (pathname-designator-p x)))
                  (format nil "NIL or ~A" *path-phrase*))
  (check-argument 'render-simulation :progress progress #'output-stream-designator-p
                  "an output stream, T or NIL")
  (check-argument 'render-simulation :antialias antialias (lambda (x) (member x '(:fxaa :msaa nil)))
                  ":fxaa, :msaa or NIL")
  (when (eq progress t) (setf progress *standard-output*))
  (multiple-value-bind (width height) (image-size size)
    (let* ((fps (or fps (simulation-fps simulation)))
           ;; The grid, each critical time shown by the frame moved onto it.
           (times (simulation-frame-times simulation fps))
           (count (length times))
           (final (progn (when video (find-ffmpeg)) (prepare-output-directory out)))
           (video (and video (merge-pathnames video)))
           (chosen (sheet-frame-indices count))
           (factor (max 1 (ceiling width *thumbnail-width*)))
           (terminal (and progress (terminal-stream-p progress)))
           (started (get-internal-real-time))
           (frames '()) (thumbnails '()) (process nil) (drawn nil) (audio nil))
      ;; Every file is made in a private folder inside FINAL, then they replace
      ;; the old render's files as a set: a failed render leaves the old one whole.
      (with-output-set (output final :stale #'old-render-files)
        (let ((log (merge-pathnames "ffmpeg.log" output))
              (movie (and video (video-temporary video))))
          (unwind-protect
               (progn
                 ;; The track first (playing the performance to its end), so ffmpeg can take it.
                 (setf audio (write-simulation-audio simulation (/ count (float fps 1d0))
                                                     (merge-pathnames *audio-file-name* output)))
                 (unwind-protect
                      (with-offscreen-context ((context) width height)
                        (let ((renderer (make-renderer width height :antialias antialias)))
                          (when video (setf process (start-ffmpeg movie width height fps log audio)))
                          (dotimes (index count)
                            (let ((time (aref times index)))
                              (render-scene renderer (simulation-scene-at simulation time))
                              (let ((pixels (renderer-pixels renderer))
                                    (path (merge-pathnames (format nil "frame-~4,'0D.png" (1+ index)) output)))
                                (push (write-png path width height pixels) frames)
                                (when (member index chosen)
                                  (push (list (thumbnail pixels width height factor) time) thumbnails))
                                (when process
                                  (write-sequence pixels (sb-ext:process-input process)))))
                            (show-progress progress (1+ index) count terminal started))
                          (delete-renderer renderer)
                          (setf drawn t)))
                   ;; A frame failed: do not leave ffmpeg waiting for the rest.
                   (when (and process (not drawn))
                     (kill-child process)
                     (unregister-cleanup process)))
                 (when process (finish-ffmpeg process video log))
                 (write-contact-sheet (merge-pathnames "sheet.png" output) (reverse thumbnails)
                                      (floor width factor) (floor height factor))
                 (when video (commit-video movie video)))
            (when movie                 ; ffmpeg's half-written file, when it failed
              (ignore-errors (sb-posix:unlink movie))
              (unregister-cleanup movie)))))
      (flet ((placed (path) (merge-pathnames (file-namestring path) final)))
        (append (mapcar #'placed (nreverse frames))
                (list (placed "sheet.png"))
                (and audio (list (placed audio)))
                (and video (list video)))))))

(defun video-temporary (video)
  "A new empty file beside VIDEO, with VIDEO's extension (ffmpeg chooses the format
by it), for ffmpeg to write; renamed over VIDEO when the encoding succeeds."
  (output-target video nil)             ; a folder, FIFO or device there is refused
  (multiple-value-bind (fd name)
      (create-exclusive-file (make-pathname :name nil :type nil :version nil :defaults video)
                             (file-namestring video) :suffix (format nil "tmp.~A" (or (pathname-type video) "mp4")))
    (sb-posix:close fd)
    (register-cleanup name)
    name))

(defun commit-video (movie video)
  "Rename ffmpeg's finished MOVIE over VIDEO."
  (handler-case (sb-posix:rename movie (sb-ext:native-namestring video))
    (sb-posix:syscall-error (e) (io-fail video e)))
  (unregister-cleanup movie))

;;;# Policies side by side

(defun render-policy-sheet (spec policies &key initial events until (fps 24) (seed 0) scripts body
                                               (size '(640 480)) (out "render/") (columns 6) silent)
  "Play the scenario EVENTS (as for SIMULATE) once per policy of POLICIES, every
event that arrives while another plays following that policy, and draw one
row per policy of COLUMNS frames evenly spaced over the longest run, named by
its policy at its left, into OUT/policies.png (SILENT as for SIMULATE).  Returns its path.  Signals what SIMULATE and
RENDER-SIMULATION signal."
  (check-argument 'render-policy-sheet 'policies policies
                  (lambda (x) (and (alexandria:proper-list-p x) x
                                   (every (lambda (p) (member p *when-busy-policies*)) x)))
                  (format nil "a non-empty list of ~{~A~^, ~}" (mapcar #'lisp-text *when-busy-policies*)))
  (check-argument 'render-policy-sheet :columns columns (lambda (x) (typep x '(integer 1 24)))
                  "an integer from 1 to 24")
  (let* ((simulations (mapcar (lambda (policy)
                                (simulate spec :initial initial :events events :until until :when-busy policy
                                               :fps fps :seed seed :scripts scripts :body body
                                               :silent silent))
                              policies))
         (end (reduce #'max simulations :key #'simulation-end))
         (times (loop for k below columns
                      collect (if (= columns 1) 0d0 (* end (/ k (float (1- columns) 1d0)))))))
    (multiple-value-bind (width height) (image-size size)
      (let ((output (prepare-output-directory out))
            (factor (max 1 (ceiling width *thumbnail-width*)))
            (thumbnails '()))
        (with-offscreen-context ((context) width height)
          (let ((renderer (make-renderer width height)))
            (dolist (simulation simulations)
              (dolist (time times)
                (render-scene renderer (performance-frame (simulation-performance simulation) time))
                (push (list (thumbnail (renderer-pixels renderer) width height factor) time) thumbnails)))
            (delete-renderer renderer)))
        (let ((*sheet-columns* columns)
              (*sheet-rows* (length policies)))
          (write-contact-sheet (merge-pathnames "policies.png" output) (nreverse thumbnails)
                               (floor width factor) (floor height factor)
                               :row-labels (mapcar (lambda (policy) (string-downcase (symbol-name policy))) policies)))))))
