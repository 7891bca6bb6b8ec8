;;;; cpp-cache.lisp -- the C++ build cache is private: its folders are mode 0700
;;;; and owned by the user, and each compiled driver is run only when its
;;;; content still matches the digest written beside it when it was built.
;;;; A cache another user owns is refused; a changed or planted driver is
;;;; rebuilt, never run.

(in-package #:player.cpp)

(defun cache-fail (directory control &rest arguments)
  "Signal a PLAYER-ERROR about the C++ build cache DIRECTORY."
  (error 'player-error-with-message
         :message (format nil "the C++ build cache ~A ~?; remove it, or set XDG_CACHE_HOME to a folder of yours"
                          (sb-ext:native-namestring directory) control arguments)))

(defun private-directory (directory)
  "DIRECTORY, made if missing, checked to be a real folder (not a link) owned by
this user, and made mode 0700.  A PLAYER-ERROR otherwise."
  (handler-case (ensure-directories-exist directory)
    (file-error (e) (io-fail directory e :action "create the folder")))
  (let ((stat (sb-posix:lstat (sb-ext:native-namestring directory))))
    (unless (eq (file-kind directory :follow nil) :directory)
      (cache-fail directory "is not a folder"))
    (unless (= (sb-posix:stat-uid stat) (sb-posix:getuid))
      (cache-fail directory "belongs to another user (uid ~D)" (sb-posix:stat-uid stat)))
    (unless (zerop (logand (sb-posix:stat-mode stat) #o077))
      (sb-posix:chmod (sb-ext:native-namestring directory) #o700)))
  directory)

(defun file-digest (path)
  "The hex MD5 digest of the regular file PATH's content."
  (format nil "~{~(~2,'0X~)~}" (coerce (sb-md5:md5sum-sequence (file-octets path)) 'list)))

(defun digest-file (executable)
  "Where EXECUTABLE's digest is kept."
  (make-pathname :type "md5" :defaults executable))

(defun verified-executable-p (executable)
  "Is EXECUTABLE a regular file (not a link) owned by this user whose content
matches the digest written when it was built?"
  (let ((stat (ignore-errors (sb-posix:lstat (sb-ext:native-namestring executable))))
        (digest (digest-file executable)))
    (and stat
         (eq (file-kind executable :follow nil) :regular)
         (= (sb-posix:stat-uid stat) (sb-posix:getuid))
         (eq (file-kind digest :follow nil) :regular)
         (string= (string-trim '(#\Newline #\Space) (with-input-file (in digest) (read-line in nil "")))
                  (file-digest executable)))))

(defun install-executable (built executable)
  "Move the freshly BUILT program to EXECUTABLE, then write its digest beside it."
  (let ((digest (file-digest built)))
    (sb-posix:rename (sb-ext:native-namestring built) (sb-ext:native-namestring executable))
    (write-file-string (digest-file executable) (format nil "~A~%" digest))
    executable))

(defun call-with-cached-build (directory build)
  "The verified program DIRECTORY/driver of the private cache: BUILD is called
with a private work folder to compile \"driver\" in when the program is
missing or fails its check.  The work folder is removed however BUILD ends."
  ;; Player's own folder too: whoever owns it could swap the cache beneath us.
  (let ((root (c++-cache-root)))
    (private-directory (make-pathname :directory (butlast (pathname-directory root)) :defaults root)))
  (private-directory (c++-cache-root))
  (private-directory directory)
  (let ((executable (merge-pathnames "driver" directory)))
    (unless (verified-executable-p executable)
      (with-work-folder (work directory "build")
        (funcall build work)
        (install-executable (merge-pathnames "driver" work) executable)))
    executable))
