;;;; outputs.lisp -- writing an output whole or not at all.  The new content
;;;; goes to a temporary file created exclusively beside the output (never
;;;; through a link), is flushed and synced, then renamed over the old file in
;;;; one step; any failure removes the temporary and leaves the old file as it
;;;; was.  A set of outputs (a folder of frames) is replaced the same way:
;;;; the old members go only after every new one exists.

(in-package #:player.base)

(defvar *temporary-counter* 0
  "Makes temporary names unique within this process.")

(defun unguessable (limit)
  "A random integer below LIMIT from a fresh random state (a saved core's own
state is the same at every start, so its names could be guessed and planted)."
  (random limit (make-random-state t)))

(defun output-target (file follow-links)
  "The file an output named FILE replaces: FILE itself, or when FOLLOW-LINKS and
FILE is a link the user named, the file it points to.  An IO-ERROR when FILE
names a directory, FIFO or device."
  (let* ((path (merge-pathnames file))
         (kind (file-kind path :follow nil)))
    (when (and (eq kind :link) follow-links)
      (setf kind (file-kind path))
      (when (member kind '(nil :regular))
        (setf path (or (ignore-errors (truename path)) (io-fail file "it is a link to a missing file")))))
    (unless (member kind '(nil :regular :link))
      (io-fail file (kind-reason kind)))
    path))

(defun create-exclusive-file (directory name &key (mode #o666) (suffix "tmp"))
  "Create a new file in DIRECTORY named after NAME, exclusively and without
following links (O_CREAT|O_EXCL|O_NOFOLLOW), open for writing, its name
ending in SUFFIX.  Returns its
descriptor and its name.  An IO-ERROR when the folder refuses it."
  (loop repeat 100
        for candidate = (format nil "~A.~A.~D-~D-~36R.~A" (os-file-name directory) name
                                (sb-posix:getpid) (incf *temporary-counter*) (unguessable (expt 36 6)) suffix)
        do (handler-case
               (return (values (sb-posix:open candidate (logior sb-posix:o-wronly sb-posix:o-creat
                                                                sb-posix:o-excl sb-posix:o-nofollow)
                                              mode)
                               candidate))
             (sb-posix:syscall-error (e)
               (unless (= (sb-posix:syscall-errno e) sb-posix:eexist)
                 (io-fail (merge-pathnames name directory) e :action "create"))))
        finally (io-fail directory "no unused temporary name" :action "create")))

(defun current-umask ()
  "The process's file-creation mask."
  (let ((mask (sb-posix:umask #o022)))
    (sb-posix:umask mask)
    mask))

(defun existing-mode (path)
  "The permission bits of the regular file PATH, or NIL when there is none."
  (let ((stat (ignore-errors (sb-posix:stat (os-file-name path)))))
    (and stat (logand (sb-posix:stat-mode stat) #o7777))))

(defun stage-output-file (file function &key (element-type 'character) (external-format :utf-8)
                                             (follow-links nil) (make-directories nil))
  "Call FUNCTION with a stream to a new temporary file beside FILE; flush, sync
and close it.  Returns a function that renames the temporary over FILE (keeping
FILE's old permissions), then FUNCTION's values.  The temporary stays
registered for removal until it is renamed; when FUNCTION or the disk fails it
is removed at once and an IO-ERROR names FILE and the reason."
  (let* ((target (output-target file follow-links))
         (directory (make-pathname :name nil :type nil :version nil :defaults target))
         (mode (existing-mode target)))
    (when make-directories
      (handler-case (ensure-directories-exist directory)
        (file-error (e) (io-fail file e :action "create the folder of"))))
    ;; Private while it is written: FILE may hold secrets (mode 0600).
    (multiple-value-bind (fd temporary) (create-exclusive-file directory (file-namestring target) :mode #o600)
      (register-cleanup temporary)
      (let ((stream (sb-sys:make-fd-stream fd :output t :element-type element-type
                                              :external-format external-format :buffering :full
                                              :name (format nil "file ~A" (os-file-name file))))
            (written nil))
        (unwind-protect
             ;; Only the failures of this stream are this file's; FUNCTION's own
             ;; errors (a file it reads) pass through as they are.
             (handler-bind ((stream-error
                              (lambda (e) (when (eq (stream-error-stream e) stream) (io-fail file e)))))
               (let ((values (multiple-value-list (funcall function stream))))
                 (handler-case
                     (progn (finish-output stream)
                            (sb-posix:fsync fd)
                            (sb-posix:fchmod fd (or mode (logandc2 #o666 (current-umask))))
                            (close stream))
                   ((or file-error sb-posix:syscall-error) (e) (io-fail file e)))
                 (setf written t)
                 (values-list
                  (cons (lambda (&optional abort)
                          (unwind-protect
                               (unless abort
                                 (handler-case (sb-posix:rename temporary (os-file-name target))
                                   (sb-posix:syscall-error (e) (io-fail file e))))
                            (ignore-errors (sb-posix:unlink temporary))
                            (unregister-cleanup temporary)))
                        values))))
          (unless written
            (ignore-errors (close stream :abort t))
            (ignore-errors (sb-posix:unlink temporary))
            (unregister-cleanup temporary)))))))

(defun call-with-atomic-output-file (file function &rest options)
  "Call FUNCTION with a stream to a temporary file beside FILE; when it returns,
flush and sync the temporary and rename it over FILE, keeping FILE's old
permissions.  When FUNCTION or the disk fails, the temporary is removed and
FILE is untouched.  OPTIONS: :ELEMENT-TYPE, :EXTERNAL-FORMAT (:UTF-8),
:MAKE-DIRECTORIES (NIL: a missing folder is an error) and :FOLLOW-LINKS: a
FILE that is a link (one the user named) is replaced at its target; without
it a link is replaced by the new file, so nothing is ever written through a
link.  Returns FUNCTION's values.
Signals an IO-ERROR naming FILE and the reason when it cannot be written."
  (destructuring-bind (commit &rest values)
      (multiple-value-list (apply #'stage-output-file file function options))
    (funcall commit)
    (values-list values)))

(defun write-files-together (files-and-texts &rest options)
  "Replace several files as a set: FILES-AND-TEXTS is a list of (FILE . TEXT);
every new content is on the disk before the first file is replaced, so a
failure leaves every old file as it was (a C++ header and its source stay a pair)."
  (let ((commits '()))
    (unwind-protect
         (progn
           (loop for (file . text) in files-and-texts
                 do (push (apply #'stage-output-file file (lambda (out) (write-string text out)) options)
                          commits))
           (setf commits (reverse commits))
           (loop while commits do (funcall (pop commits))))
      (dolist (commit commits) (funcall commit t)))
    (mapcar #'car files-and-texts)))

(defmacro with-atomic-output-file ((stream file &rest options) &body body)
  "Run BODY with STREAM writing FILE's new content; FILE is replaced only when
BODY returns and the content is on the disk (see CALL-WITH-ATOMIC-OUTPUT-FILE)."
  `(call-with-atomic-output-file ,file (lambda (,stream) ,@body) ,@options))

(defun write-file-octets (file octets &rest options)
  "Replace FILE's content with OCTETS, atomically."
  (apply #'call-with-atomic-output-file file (lambda (out) (write-sequence octets out))
         :element-type '(unsigned-byte 8) options))

(defun write-file-string (file string &rest options)
  "Replace FILE's content with STRING (UTF-8), atomically."
  (apply #'call-with-atomic-output-file file (lambda (out) (write-string string out)) options))

(defun check-writable-directory (directory)
  "DIRECTORY (made if missing) when a file can be created in it: a probe file
is created exclusively, without following links, then removed.  An IO-ERROR
naming DIRECTORY and the reason otherwise."
  (let ((directory (directory-pathname directory)))
    (handler-case (ensure-directories-exist directory)
      (file-error (e) (io-fail directory e :action "create the folder")))
    (unless (eq (file-kind directory) :directory)
      (io-fail directory (kind-reason (file-kind directory)) :action "write into"))
    (multiple-value-bind (fd name) (create-exclusive-file directory "probe")
      (sb-posix:close fd)
      (sb-posix:unlink name))
    directory))

;;;# Sets of outputs

(defvar *output-sets* '()
  "While sets of outputs are written: (WORK-FOLDER . DIRECTORY) for each, so an
error about a draft names the file it will replace (FINAL-FILE-NAME).")

(defun final-file-name (file)
  "FILE, or when it is a draft in an output set's work folder, the file in the
set's directory it will become: what an error should name."
  (let* ((path (and (or (pathnamep file) (stringp file)) (pathname file)))
         (set (and path (assoc (pathname-directory path) *output-sets*
                               :key #'pathname-directory :test #'equal))))
    (if set (merge-pathnames (file-namestring path) (cdr set)) file)))

(defun make-private-folder (parent prefix)
  "A new folder in PARENT, mode 0700, created exclusively; registered so an
interrupt removes it.  Returns its directory pathname."
  (loop repeat 100
        for name = (format nil "~A.~A-~D-~36R/" (os-file-name (directory-pathname parent)) prefix
                           (sb-posix:getpid) (unguessable (expt 36 8)))
        do (handler-case (progn (sb-posix:mkdir name #o700)
                                (register-cleanup (pathname name))
                                (return (pathname name)))
             (sb-posix:syscall-error (e)
               (unless (= (sb-posix:syscall-errno e) sb-posix:eexist)
                 (io-fail parent e :action "create a folder in"))))
        finally (io-fail parent "no unused folder name" :action "create a folder in")))

(defun remove-folder (folder)
  "Delete FOLDER and what it holds (links are removed, never followed)."
  (ignore-errors (sb-ext:delete-directory folder :recursive t))
  (unregister-cleanup folder))

(defun call-with-output-set (directory function &key stale)
  "Call FUNCTION with a new private folder inside DIRECTORY to write a set of
files into; when it returns, move each file into DIRECTORY (one rename each,
replacing an old file of that name), then delete the old files STALE (a
function of DIRECTORY returning pathnames) lists that the new set did not
replace.  When FUNCTION fails, the folder goes and DIRECTORY is untouched.
Returns FUNCTION's values."
  (let* ((directory (check-writable-directory directory))
         (work (make-private-folder directory "player-new")))
    (unwind-protect
         (multiple-value-prog1
             ;; An error names the file the user will look for, not its draft in WORK.
             (let ((*output-sets* (acons work directory *output-sets*)))
               (funcall function work))
           (let ((old (and stale (funcall stale directory)))
                 (new '()))
             (dolist (file (directory (merge-pathnames "*.*" work) :resolve-symlinks nil))
               (let ((target (merge-pathnames (file-namestring file) directory)))
                 (handler-case (sb-posix:rename (os-file-name file) (os-file-name target))
                   (sb-posix:syscall-error (e) (io-fail target e)))
                 (push (file-namestring target) new)))
             ;; Only names in DIRECTORY itself: never a file a link there points to.
             (dolist (file old)
               (let ((name (merge-pathnames (file-namestring file) directory)))
                 (unless (member (file-namestring file) new :test #'string=)
                   (ignore-errors (sb-posix:unlink (os-file-name name))))))))
      (remove-folder work))))

(defmacro with-output-set ((folder directory &rest options) &body body)
  "Run BODY with FOLDER, a private folder whose files replace DIRECTORY's as a
set when BODY returns (see CALL-WITH-OUTPUT-SET)."
  `(call-with-output-set ,directory (lambda (,folder) ,@body) ,@options))
