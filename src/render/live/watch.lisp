;;;; watch.lisp -- noticing that files changed, for `player view --watch`.
;;;; Every quarter second (at most) each watched file's contents are summed
;;;; (MD5): modification times have a one-second grain, so two saves within a
;;;; second would go unseen.  Spec files, libraries and skeletons are small.
;;;; A change counts once the file has held still for one look: an editor
;;;; that writes a file in two steps (emptied, then filled) makes one change.

(in-package #:player.render)

(defparameter *watch-interval* 0.25d0
  "Seconds between two looks at the watched files.")

(defstruct (watched-file (:constructor make-watched-file (path digest)))
  "A watched PATH, the DIGEST of its contents last reported (NIL when it
could not be read), and the digest SEEN at the last look when it differed."
  path digest (seen nil))

(defstruct (file-watcher (:constructor %make-file-watcher))
  "WATCHED-FILEs, and when they were last looked at."
  (files '() :type list)
  (checked-at 0d0 :type double-float))

(defparameter *max-watched-bytes* (* 64 1024 1024)
  "The largest watched file whose contents are summed.")

(defun file-digest (path)
  "The MD5 digest of PATH's contents, or NIL when it cannot be read (being saved,
say) or is not a regular file: a FIFO, a device (a link to /dev/zero) or a
folder is skipped without being opened for a blocking read, and looked at
again next time, so the watch recovers when a good file returns."
  (ignore-errors (sb-md5:md5sum-sequence (file-octets path :limit *max-watched-bytes*))))

(defun make-file-watcher (paths &optional (now 0d0))
  "A watcher of PATHS (NILs ignored) whose contents now are the reference, looked at NOW (seconds)."
  (%make-file-watcher :files (loop for path in (remove-duplicates (remove nil paths) :test #'equal)
                                   collect (make-watched-file path (file-digest path)))
                      :checked-at (float now 1d0)))

(defun watcher-paths (watcher)
  "The paths WATCHER watches."
  (mapcar #'watched-file-path (file-watcher-files watcher)))

(defun watcher-changes (watcher now)
  "The watched files whose contents changed since they were last reported and
have held still since the look before, when *WATCH-INTERVAL* seconds have
passed since that look at NOW (seconds); else NIL.  A file that cannot be
read is looked at again next time."
  (when (>= (- now (file-watcher-checked-at watcher)) *watch-interval*)
    (setf (file-watcher-checked-at watcher) (float now 1d0))
    (loop for file in (file-watcher-files watcher)
          for digest = (file-digest (watched-file-path file))
          when (and digest (not (equalp digest (watched-file-digest file)))
                    (prog1 (equalp digest (watched-file-seen file))
                      (setf (watched-file-seen file) digest)))
            collect (watched-file-path file)
            and do (setf (watched-file-digest file) digest
                         (watched-file-seen file) nil))))
