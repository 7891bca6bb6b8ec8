;;;; watch.lisp -- noticing that files changed, for `player view --watch`.
;;;; Every half second (at most) each watched file's contents are summed
;;;; (MD5): modification times have a one-second grain, so two saves within a
;;;; second would go unseen.  Spec files and script libraries are small.

(in-package #:player.render)

(defparameter *watch-interval* 0.5d0
  "Seconds between two looks at the watched files.")

(defstruct (file-watcher (:constructor %make-file-watcher))
  "Files and the digest each had at the last look (NIL when unreadable), and when that was."
  (digests '() :type list)
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
  (%make-file-watcher :digests (loop for path in (remove-duplicates (remove nil paths) :test #'equal)
                                     collect (cons path (file-digest path)))
                      :checked-at (float now 1d0)))

(defun watcher-changes (watcher now)
  "The watched files whose contents changed since the last look, when
*WATCH-INTERVAL* seconds have passed since then at NOW (seconds); else NIL.
A file that cannot be read is looked at again next time."
  (when (>= (- now (file-watcher-checked-at watcher)) *watch-interval*)
    (setf (file-watcher-checked-at watcher) (float now 1d0))
    (loop for entry in (file-watcher-digests watcher)
          for digest = (file-digest (car entry))
          when (and digest (not (equalp digest (cdr entry))))
            collect (car entry)
            and do (setf (cdr entry) digest))))
