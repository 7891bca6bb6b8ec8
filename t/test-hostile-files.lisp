;;;; test-hostile-files.lisp -- files that must not hang, lose or betray the
;;;; user (issue 31, items 2 and 4): FIFOs and devices are never read as data,
;;;; outputs are replaced whole and never through a planted link, nothing the
;;;; user did not name is deleted, the C++ cache runs only what it built, and
;;;; SIGINT/SIGTERM end a command promptly with its children.  Each hostile case
;;;; runs bin/player in a child process, with a time bound and its one
;;;; expected error line.

(in-package #:player-tests)

(def-suite* hostile-files :in player-tests)

;;;# Running bin/player with a time bound

(defun scratch-folder (name)
  "A fresh, empty folder for one test, /tmp/player-files-PID-NAME/."
  (let ((folder (pathname (format nil "/tmp/player-files-~D-~A/" (sb-posix:getpid) name))))
    (uiop:delete-directory-tree folder :validate t :if-does-not-exist :ignore)
    (ensure-directories-exist folder)))

(defmacro with-scratch-folder ((folder name) &body body)
  "Run BODY with FOLDER, a fresh scratch folder removed afterwards."
  `(let ((,folder (scratch-folder ,name)))
     (unwind-protect (progn ,@body)
       (uiop:delete-directory-tree ,folder :validate t :if-does-not-exist :ignore))))

(defun start-player (arguments &key directory environment input)
  "Start bin/player with ARGUMENTS in DIRECTORY (default the checkout), its
output and errors going to files in /tmp; INPUT, a string, is its standard
input (:STREAM, a pipe left open; NIL, none).  Returns the process and the two files."
  (ensure-player-core)
  (let* ((tag (format nil "/tmp/player-files-~D-~36R" (sb-posix:getpid) (random (expt 36 6))))
         (out (concatenate 'string tag ".out"))
         (err (concatenate 'string tag ".err")))
    (values (sb-ext:run-program (namestring (checkout-file "bin/player")) arguments
                                :output out :error err :if-output-exists :supersede
                                :if-error-exists :supersede :wait nil :search nil
                                :input (if (stringp input) (make-string-input-stream input) input)
                                :environment (append environment (sb-ext:posix-environ))
                                :directory (namestring (or directory *root*)))
            out err)))

(defun wait-for-process (process seconds)
  "Wait up to SECONDS for PROCESS to end; kill it when it has not.  True when it ended in time."
  (loop with deadline = (+ (get-internal-real-time) (* seconds internal-time-units-per-second))
        while (and (sb-ext:process-alive-p process) (< (get-internal-real-time) deadline))
        do (sleep 0.05))
  (cond ((sb-ext:process-alive-p process)
         (sb-ext:process-kill process sb-unix:sigkill)
         (sb-ext:process-wait process)
         nil)
        (t t)))

(defun take-file (path)
  "The text of PATH, which is then deleted; \"\" when there is none."
  (prog1 (or (ignore-errors (uiop:read-file-string path)) "")
    (ignore-errors (delete-file path))))

(defun bounded-player (seconds arguments &rest options)
  "Run bin/player with ARGUMENTS (OPTIONS as for START-PLAYER), killed after
SECONDS.  Returns stdout, stderr, the exit code (NIL when it was killed) and
whether it ended in time."
  (multiple-value-bind (process out err) (apply #'start-player arguments options)
    (let ((in-time (wait-for-process process seconds)))
      (values (take-file out) (take-file err)
              (and in-time (sb-ext:process-exit-code process)) in-time))))

(defun check-one-error-line (seconds fragment arguments &rest options)
  "bin/player ARGUMENTS (OPTIONS as for START-PLAYER) must end within SECONDS
with status 1 and one error line containing FRAGMENT, with no Lisp object in it."
  (multiple-value-bind (out err code in-time) (apply #'bounded-player seconds arguments options)
    (declare (ignore out))
    (is-true in-time "~S did not end within ~D s" arguments seconds)
    (is (eql 1 code) "exit ~A for ~S: ~A" code arguments err)
    (is (= 1 (length (lines err))) "~S: stderr is not one line: ~S" arguments err)
    (is (eql 0 (search "player: error: " err)) "stderr ~S" err)
    (is (search fragment err) "~S: stderr ~S lacks ~S" arguments err fragment)
    (is (not (search "#<" err)) "a Lisp object in ~S" err)))

(defun file-md5 (path)
  "PATH's content digest, or NIL when it cannot be read."
  (ignore-errors (sb-md5:md5sum-file path)))

(defun make-fifo (path)
  "Make a FIFO at PATH; return PATH's name."
  (let ((name (namestring path)))
    (sb-posix:mkfifo name #o600)
    name))

;;;# FIFOs, devices and folders are never read

(defun write-sound-spec (folder sound)
  "A spec in FOLDER whose one script plays the file SOUND; returns the spec's path."
  (with-open-file (out (merge-pathnames "snd-scripts.lisp" folder) :direction :output)
    (format out "(defscript hum (:duration 1) (:at 0 :sound ~S))~%" sound))
  (with-open-file (out (merge-pathnames "snd.lisp" folder) :direction :output)
    (format out "(in-package :player-user)~%(defspec snd (:scripts \"snd-scripts.lisp\") (:body humanoid)~%  (op hum :duration 1) (event ev-hum :op hum))~%"))
  (namestring (merge-pathnames "snd.lisp" folder)))

(test fifos-devices-and-folders-are-refused-at-once
  (with-scratch-folder (folder "fifo")
    (let ((fifo (make-fifo (merge-pathnames "fifo.wav" folder)))
          (zero (namestring (merge-pathnames "zero.lisp" folder))))
      (sb-posix:symlink "/dev/zero" zero)
      (check-one-error-line 20 "not a regular file" (list "check" fifo))
      (check-one-error-line 20 "not a regular file" (list "run" zero))
      (check-one-error-line 20 "not a regular file" (list "run" (namestring folder)))
      ;; check prints the library's error as a diagnostic, then its one error line.
      (multiple-value-bind (out err code in-time) (bounded-player 30 (list "check" (write-sound-spec folder fifo)))
        (is-true in-time "check hung on a :sound FIFO")
        (is (eql 1 code))
        (is (search "it is a FIFO" out) "~A" out)
        (is (= 1 (length (lines err)))))
      (check-one-error-line 30 "it is a FIFO" (list "chat" (namestring (checkout-file "specs/peedy-dialogue.lisp"))
                                                   "--wav" fifo))
      (check-one-error-line 20 "not a regular file"
                            (list "chat" (namestring (checkout-file "specs/peedy-dialogue.lisp"))
                                  "--memory" zero)))))

(test inputs-are-opened-without-blocking
  (with-scratch-folder (folder "open")
    (let ((fifo (make-fifo (merge-pathnames "f" folder))))
      (dolist (path (list fifo "/dev/zero" (namestring folder)))
        (let ((error (handler-case (progn (player.base:file-octets path) nil)
                       (player.base:io-error (e) e))))
          (is (typep error 'player.base:io-error) "~A was read" path)
          (is (not (search "#<" (princ-to-string error))))))
      (is (equal "it is a FIFO, not a regular file"
                 (handler-case (player.base:check-regular-file fifo)
                   (player.base:io-error (e) (player.base:io-error-reason e))))))))

(test watch-skips-what-is-not-a-regular-file-and-recovers
  (with-scratch-folder (folder "watch")
    (let* ((spec (merge-pathnames "spec.lisp" folder))
           (name (namestring spec)))
      (with-open-file (out spec :direction :output) (write-line "(one)" out))
      (let ((watcher (player.render::make-file-watcher (list spec) 0d0))
            (player.render::*watch-interval* 0d0))
        (flet ((changes (now)
                 ;; On a thread of its own, so a blocking read fails the test instead of hanging it.
                 (let* ((result :blocked)
                        (thread (sb-thread:make-thread
                                 (lambda () (setf result (player.render::watcher-changes watcher now))))))
                   (loop repeat 100 while (sb-thread:thread-alive-p thread) do (sleep 0.05))
                   (if (sb-thread:thread-alive-p thread)
                       (progn (sb-thread:terminate-thread thread) :blocked)
                       result))))
          (delete-file spec)
          (make-fifo spec)
          (is (null (changes 1d0)) "a FIFO in the spec's place is skipped")
          (delete-file spec)
          (sb-posix:symlink "/dev/zero" name)
          (is (null (changes 2d0)) "a link to /dev/zero is skipped")
          (delete-file spec)
          (with-open-file (out spec :direction :output) (write-line "(two)" out))
          ;; A change counts once the file has held still for one look (watch.lisp).
          (is (null (changes 3d0)) "a good file is first seen once")
          (is (equal (list spec) (changes 4d0)) "a good file is seen again"))))))

;;;# Outputs: whole, never through a link, only what was named

(test a-failed-write-leaves-the-old-file-and-no-temporary
  (with-scratch-folder (folder "atomic")
    (let ((file (merge-pathnames "out.txt" folder)))
      (player.base:write-file-string file "old")
      (signals error (player.base:with-atomic-output-file (out file)
                       (write-string "half" out)
                       (error "the writer failed")))
      (is (equal "old" (uiop:read-file-string file)))
      (is (equal (list file) (directory (merge-pathnames "*.*" folder)))
          "the temporary is gone: ~S" (directory (merge-pathnames "*.*" folder)))
      (sb-posix:chmod (namestring file) #o640)
      (player.base:write-file-string file "new")
      (is (equal "new" (uiop:read-file-string file)))
      (is (= #o640 (logand #o777 (sb-posix:stat-mode (sb-posix:stat (namestring file)))))
          "the old file's permissions are kept"))))

(test outputs-replace-planted-links-instead-of-writing-through-them
  (with-scratch-folder (folder "links")
    (let ((victim (merge-pathnames "victim.txt" folder))
          (out (merge-pathnames "out/" folder)))
      (ensure-directories-exist out)
      (player.base:write-file-string victim "precious")
      (sb-posix:symlink (namestring victim) (namestring (merge-pathnames "mini.hpp" out)))
      (sb-posix:symlink (namestring victim) (namestring (merge-pathnames ".player-render-probe" out)))
      (multiple-value-bind (stdout err code in-time)
          (bounded-player 60 (list "emit-c++" (fixture "mini.lisp") "--out" (namestring out)))
        (declare (ignore stdout))
        (is-true in-time)
        (is (eql 0 code) "emit-c++: ~A" err))
      (is (equal "precious" (uiop:read-file-string victim)) "written through a planted link")
      (is (eq :regular (player.base:file-kind (merge-pathnames "mini.hpp" out) :follow nil))))))

(test simulate-deletes-nothing-it-was-not-told-to-write
  (with-scratch-folder (folder "named")
    (let ((speech (merge-pathnames "speech.wav" folder)))
      (player.base:write-file-string speech "mine")
      (multiple-value-bind (out err code in-time)
          (bounded-player 120 (list "simulate" (fixture "anim.lisp") "--events" "ev-wave" "--fps" "5"
                                    "--frames" (namestring (merge-pathnames "x.frames" folder))))
        (declare (ignore out))
        (is-true in-time)
        (is (eql 0 code) "simulate: ~A" err))
      (is (equal "mine" (uiop:read-file-string speech)) "simulate --frames removed d/speech.wav")
      ;; The frames and the BVH change as a set: a BVH that cannot be written keeps the old frames.
      (let ((frames (merge-pathnames "x.frames" folder)))
        (player.base:write-file-string frames "old frames")
        (ensure-directories-exist (merge-pathnames "x.bvh/" folder))
        (check-one-error-line 120 "x.bvh"
                              (list "simulate" (fixture "anim.lisp") "--events" "ev-wave" "--fps" "5"
                                    "--frames" (namestring frames)
                                    "--bvh" (namestring (merge-pathnames "x.bvh" folder))))
        (is (equal "old frames" (uiop:read-file-string frames)))))))

(test a-set-of-outputs-replaces-the-old-set-only-when-whole
  (with-scratch-folder (folder "set")
    (flet ((names () (sort (mapcar #'file-namestring (directory (merge-pathnames "*.*" folder) :resolve-symlinks nil)) #'string<))
           (stale (directory) (directory (merge-pathnames "frame-*.png" directory) :resolve-symlinks nil)))
      (dolist (name '("frame-0001.png" "frame-0002.png" "notes.txt"))
        (player.base:write-file-string (merge-pathnames name folder) "old"))
      ;; A planted link among the old frames: it goes, what it points to stays.
      (sb-posix:symlink (namestring (merge-pathnames "notes.txt" folder))
                        (namestring (merge-pathnames "frame-0003.png" folder)))
      (signals error (player.base:with-output-set (work folder :stale #'stale)
                       (player.base:write-file-string (merge-pathnames "frame-0001.png" work) "new")
                       (error "frame 2 failed")))
      (is (equal '("frame-0001.png" "frame-0002.png" "frame-0003.png" "notes.txt") (names)))
      (is (equal "old" (uiop:read-file-string (merge-pathnames "frame-0001.png" folder))))
      (player.base:with-output-set (work folder :stale #'stale)
        (player.base:write-file-string (merge-pathnames "frame-0001.png" work) "new"))
      (is (equal '("frame-0001.png" "notes.txt") (names)) "old frames go, other files stay")
      (is (equal "old" (uiop:read-file-string (merge-pathnames "notes.txt" folder))))
      (is (equal "new" (uiop:read-file-string (merge-pathnames "frame-0001.png" folder)))))))
