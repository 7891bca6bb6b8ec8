;;;; test-hostile-outputs.lisp -- a full disk loses nothing, the C++ build
;;;; cache runs only what it built, SIGINT and SIGTERM end a command promptly
;;;; with its children, and Swank admits only clients with the secret (issue
;;;; 31, items 1 and 2).  Helpers are in test-hostile-files.lisp.

(in-package #:player-tests)

(in-suite hostile-files)

;;;# A full disk

(defun try-mount-tmpfs (folder kilobytes)
  "Mount a tmpfs of KILOBYTES on FOLDER; true when it could (root, and mount allowed)."
  (and (zerop (sb-posix:getuid))
       (eql 0 (sb-ext:process-exit-code
               (sb-ext:run-program "/bin/mount" (list "-t" "tmpfs" "-o" (format nil "size=~Dk" kilobytes)
                                                      "tmpfs" (namestring folder))
                                   :output nil :error nil)))))

(defun fill-disk (folder)
  "Write a filler file in FOLDER until its file system is full."
  ;; dd, since SBCL deletes a file whose stream is closed after a failed write.
  (sb-ext:run-program "/bin/dd" (list "if=/dev/zero" (format nil "of=~Afiller" (namestring folder)) "bs=1k")
                      :output nil :error nil))

(defun full-disk-arguments (mode arguments)
  "ARGUMENTS of bin/player as run on a full disk: as they are on a full tmpfs
\(MODE :TMPFS), or wrapped in sh with a 1-block RLIMIT_FSIZE (MODE :RLIMIT),
SIGXFSZ ignored so a write fails with EFBIG instead of killing the process."
  (ecase mode
    (:tmpfs (cons (namestring (checkout-file "bin/player")) arguments))
    (:rlimit (list* "/bin/sh" "-c" "trap '' XFSZ; ulimit -f 1; exec \"$0\" \"$@\""
                    (namestring (checkout-file "bin/player")) arguments))))

(defun run-on-full-disk (mode seconds arguments &key input)
  "Run bin/player ARGUMENTS (see FULL-DISK-ARGUMENTS) with a time bound;
stdout, stderr, exit code, in time."
  (ensure-player-core)
  (let* ((all (full-disk-arguments mode arguments))
         (tag (format nil "/tmp/player-files-~D-disk" (sb-posix:getpid)))
         (out (concatenate 'string tag ".out"))
         (err (concatenate 'string tag ".err"))
         (process (sb-ext:run-program (first all) (rest all) :output out :error err :wait nil
                                      :if-output-exists :supersede :if-error-exists :supersede
                                      :input (and input (make-string-input-stream input))
                                      :directory (namestring *root*))))
    (let ((in-time (wait-for-process process seconds)))
      (values (take-file out) (take-file err)
              (and in-time (sb-ext:process-exit-code process)) in-time))))

(defun folder-digests (folder)
  "Each file of FOLDER (and its sub-folders) with its digest, sorted by name."
  (sort (mapcar (lambda (file) (format nil "~A ~{~(~2,'0X~)~}" (file-namestring file) (coerce (file-md5 file) 'list)))
                (remove-if-not #'pathname-name (directory (merge-pathnames "**/*.*" folder))))
        #'string<))

(defparameter *disk-full-commands*
  `(("record" ,(lambda (d) (list "record" (fixture "mini.lisp") "--events" "ev-search" "--out" (funcall d "rec.lisp")))
              ("rec.lisp"))
    ("chat --memory" ,(lambda (d) (list "chat" (namestring (checkout-file "specs/peedy-dialogue.lisp"))
                                        "--memory" (funcall d "memory.lisp")))
                     ("memory.lisp") "hello" ,(format nil "hello~%quit~%"))
    ("emit-c++" ,(lambda (d) (list "emit-c++" (fixture "mini.lisp") "--out" (funcall d "")))
                ("mini.hpp" "mini.cpp"))
    ("simulate" ,(lambda (d) (list "simulate" (fixture "anim.lisp") "--events" "ev-wave" "--fps" "5"
                                   "--frames" (funcall d "x.frames") "--bvh" (funcall d "x.bvh")))
                ("x.frames" "x.bvh" "speech.wav"))
    ("dot" ,(lambda (d) (list "dot" (fixture "mini.lisp") "--out" (funcall d "g.dot"))) ("g.dot"))
    ("verify-graph --dot" ,(lambda (d) (list "verify-graph" (fixture "mini.lisp") "--formula" "(AG (not holding-note))"
                                             "--dot" (funcall d "c.dot")))
                          ("c.dot"))
    ("speak" ,(lambda (d) (list "speak" "hello there" "--out" (funcall d "hello.wav"))) ("hello.wav"))
    ("export" ,(lambda (d) (list "export" (fixture "anim.lisp") "--events" "ev-wave" "--fps" "5"
                                 "--out" (funcall d "a.glb")))
              ("a.glb"))
    ("render" ,(lambda (d) (list "render" (fixture "anim.lisp") "--events" "ev-wave" "--fps" "2"
                                 "--size" "64x48" "--out" (funcall d "")))
              ("frame-0001.png" "frame-0002.png" "sheet.png"))
    ;; The frames go to a folder with room (on a tmpfs), so ffmpeg itself meets the full disk.
    ("render --video" ,(lambda (d) (list "render" (fixture "anim.lisp") "--events" "ev-wave" "--fps" "2" "--silent"
                                         "--size" "64x48" "--out" (namestring (scratch-folder "video-frames"))
                                         "--video" (funcall d "v.mp4")))
                      ("v.mp4")))
  "Each command that writes: its name, its arguments given a function from a
file name to its path in the full folder, the old files it would replace,
and optionally what the old memory user is called and the standard input.")

(defparameter *unavailable-fragments* '("libespeak" "OSMesa" "libosmesa" "not installed")
  "Errors that mean the machine lacks a tool, not that the disk was full.")

(defun old-content (name)
  "What an old output called NAME holds before the full-disk run."
  (if (string= name "memory.lisp")
      (format nil "(user \"someone\" :mood :neutral :conversations 1 :log ())~%")
      (format nil "old ~A, which must survive~%" name)))

(test a-full-disk-loses-no-existing-file
  (let* ((folder (scratch-folder "full"))
         (mode (if (try-mount-tmpfs folder 512) :tmpfs :rlimit))
         (reason (if (eq mode :tmpfs) "no space left on device" "file too large")))
    (unwind-protect
         (loop for (name arguments olds nil input) in *disk-full-commands*
               do (dolist (file (directory (merge-pathnames "*.*" folder)))
                    (when (pathname-name file) (delete-file file)))
                  (dolist (old olds)
                    (with-open-file (out (merge-pathnames old folder) :direction :output :if-exists :supersede)
                      (write-string (old-content old) out)))
                  (when (eq mode :tmpfs) (fill-disk folder))
                  (let ((before (folder-digests folder)))
                    (multiple-value-bind (out err code in-time)
                        (run-on-full-disk mode 60 (funcall arguments (lambda (file) (namestring (merge-pathnames file folder))))
                                          :input input)
                      (declare (ignore out))
                      (unless (some (lambda (fragment) (search fragment err)) *unavailable-fragments*)
                        (is-true in-time "~A did not end in time" name)
                        (is (eql 1 code) "~A: exit ~A: ~A" name code err)
                        (is (= 1 (length (lines err))) "~A: stderr ~S" name err)
                        (is (search reason (string-downcase err)) "~A: ~S does not say ~S" name err reason)
                        (is (not (search "#<" err)) "~A: ~S" name err))
                      (is (equal before (folder-digests folder))
                          "~A changed or lost a file, or left one: ~S -> ~S" name before (folder-digests folder))))
               finally
                  ;; Standard output sent to the full disk: an error, not a quiet end as for a closed pipe.
                  (let ((process (sb-ext:run-program
                                  "/bin/sh" (list "-c" (format nil "~:[~;trap '' XFSZ; ulimit -f 1; ~]exec \"$0\" \"$@\" > ~A"
                                                               (eq mode :rlimit)
                                                               (namestring (merge-pathnames "out.txt" folder)))
                                                  (namestring (checkout-file "bin/player"))
                                                  "plans" (namestring (checkout-file "specs/peedy.lisp")))
                                  :output nil :error :stream :wait nil)))
                    (let ((err (read-line (sb-ext:process-error process) nil "")))
                      (wait-for-process process 30)
                      (is (eql 1 (sb-ext:process-exit-code process)))
                      (is (search "cannot write standard output" err) "~S" err))))
      (when (eq mode :tmpfs)
        (sb-ext:run-program "/bin/umount" (list (namestring folder)) :output nil :error nil))
      (uiop:delete-directory-tree folder :validate t :if-does-not-exist :ignore)
      (uiop:delete-directory-tree (scratch-folder "video-frames") :validate t :if-does-not-exist :ignore))))

;;;# The C++ build cache

(defun cache-environment (folder)
  "The environment entry putting the C++ build cache under FOLDER."
  (list (format nil "XDG_CACHE_HOME=~A" (string-right-trim "/" (namestring folder)))))

(test the-c++-cache-is-private-and-runs-only-what-it-built
  (with-scratch-folder (folder "cache")
    (let* ((environment (cache-environment folder))
           (arguments (list "run" (fixture "mini.lisp") "--backend" "c++" "--events" "ev-search"))
           (trace (multiple-value-bind (out err code) (bounded-player 120 arguments :environment environment)
                    (is (eql 0 code) "first run: ~A" err)
                    out))
           (root (merge-pathnames "player/c++/" folder))
           (drivers (directory (merge-pathnames "*/driver" root))))
      (is (= 1 (length drivers)))
      (dolist (directory (list root (merge-pathnames "player/" folder)
                               (make-pathname :name nil :defaults (first drivers))))
        (is (= #o700 (logand #o777 (sb-posix:stat-mode (sb-posix:stat (namestring directory)))))
            "~A is not private" directory))
      ;; A planted driver (the cache made writable by someone) is rebuilt, never run.
      (with-open-file (out (first drivers) :direction :output :if-exists :supersede)
        (format out "#!/bin/sh~%echo planted~%"))
      (multiple-value-bind (out err code) (bounded-player 120 arguments :environment environment)
        (is (eql 0 code) "second run: ~A" err)
        (is (not (search "planted" out)) "the planted driver ran")
        (is (equal trace out)))
      (when (zerop (sb-posix:getuid))
        (sb-posix:chown (namestring root) 65534 65534)
        (check-one-error-line 60 "belongs to another user" arguments :environment environment)))))

;;;# SIGINT and SIGTERM

(defun processes-working-in (folder)
  "The ids of processes whose current folder is inside FOLDER."
  (let ((prefix (namestring folder)))
    (loop for entry in (directory "/proc/*/")
          for pid = (ignore-errors (parse-integer (car (last (pathname-directory entry)))))
          for cwd = (and pid (ignore-errors (sb-posix:readlink (format nil "/proc/~D/cwd" pid))))
          when (and cwd (eql 0 (search prefix cwd))) collect pid)))

(defun wait-until-true (predicate seconds)
  "Poll PREDICATE every 20 ms for up to SECONDS; its first true value, or NIL."
  (loop repeat (ceiling seconds 0.02)
        thereis (funcall predicate)
        do (sleep 0.02)))

(test sigint-kills-the-compiler-and-removes-the-work-folder
  (with-scratch-folder (folder "sigint")
    (multiple-value-bind (process out err)
        (start-player (list "run" (fixture "mini.lisp") "--backend" "c++" "--events" "ev-search")
                      :environment (cache-environment folder))
      (let ((compiling (wait-until-true (lambda () (processes-working-in folder)) 60)))
        (is-true compiling "g++ was never seen running")
        (when compiling
          (sb-ext:process-kill process sb-unix:sigint)
          (is-true (wait-for-process process 5) "SIGINT did not end the command within 5 s")
          (is (eql 130 (sb-ext:process-exit-code process)))
          (is-true (wait-until-true (lambda () (null (processes-working-in folder))) 2)
                   "g++ outlived the command: ~S" (processes-working-in folder))
          (is (null (directory (merge-pathnames "player/c++/*/.build-*/" folder)))
              "a work folder was left behind")))
      (wait-for-process process 5)
      (take-file out) (take-file err))))

(test sigterm-ends-a-command-waiting-for-input
  (multiple-value-bind (process out err)
      (start-player (list "chat" (namestring (checkout-file "specs/peedy-dialogue.lisp"))) :input :stream)
    ;; It waits on its input, a pipe that stays open: TERM must end it.
    (sleep 3)
    (is-true (sb-ext:process-alive-p process) "chat ended before it was sent SIGTERM")
    (sb-ext:process-kill process sb-unix:sigterm)
    (is-true (wait-for-process process 5) "SIGTERM did not end the command within 5 s")
    (is (eql 143 (sb-ext:process-exit-code process)))
    (ignore-errors (close (sb-ext:process-input process)))
    (take-file out)
    (is (string= "" (take-file err)))))

(test sigterm-and-sigint-end-a-busy-command-leaving-no-draft
  ;; SBCL's own SIGTERM handler could deadlock in EXIT; Player's unwinds.  Tried
  ;; a few times, at different moments of the work.
  (with-scratch-folder (folder "busy")
    (let ((frames (namestring (merge-pathnames "long.frames" folder))))
      (loop for try below (sweep-count 4 2)
            for (signal code) = (if (evenp try) (list sb-unix:sigterm 143) (list sb-unix:sigint 130))
            do (multiple-value-bind (process out err)
                   (start-player (list "simulate" (namestring (checkout-file "specs/peedy.lisp"))
                                       ;; Just under the 36,000-frame budget: a clean machine
                                       ;; wrote 300 s of frames before the signal came.
                                       "--events" "ev-search" "--at" "1199" "--fps" "30" "--frames" frames))
                 (sleep (+ 1 (* 0.3 try)))
                 (when (sb-ext:process-alive-p process)
                   (sb-ext:process-kill process signal)
                   (is-true (wait-for-process process 5) "signal ~D did not end simulate within 5 s" signal)
                   (is (eql code (sb-ext:process-exit-code process)))
                   (is (null (directory (merge-pathnames "*.*" folder)))
                       "left behind: ~S" (directory (merge-pathnames "*.*" folder))))
                 (wait-for-process process 5)
                 (take-file out)
                 (is (string= "" (take-file err))))))))
