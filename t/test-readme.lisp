;;;; test-readme.lisp -- the docs are tested: README.md and every doc/**/*.md.
;;;;
;;;; What a fenced block is, by its language (the word after ```), and what the
;;;; test does with it:
;;;;   lisp     evaluated: every block of a page in order, all in one fresh
;;;;            package (IN-PACKAGE forms switch, as at a REPL), output
;;;;            discarded; a block that signals an error is one failure naming
;;;;            its page and line.  Afterwards the package is deleted, specs the
;;;;            blocks defined are removed and specs they redefined restored.
;;;;            REPL setup forms are not evaluated: (asdf:load-system ...),
;;;;            since the test runs in a loaded Player, and forms with the
;;;;            placeholder path "/path/to/" (the reader's checkout goes there).
;;;;   sh       commands, run as written: each line (a line ending in \
;;;;            continues on the next; # starts a comment) that starts with
;;;;            `bin/player` runs through /bin/sh in a fresh directory holding
;;;;            links to the checkout's specs/, examples/, t/ and doc/ (one
;;;;            directory per page, so a page's commands see each other's
;;;;            files), and must exit 0; a line that starts with `make` must name
;;;;            a target of the Makefile (not run: `make test` is this run);
;;;;            any other line is a failure.
;;;;   console  a session: lines starting with "$ " are commands, run as in sh
;;;;            blocks; the lines after one are its output (stdout and stderr
;;;;            together), each of which, but "...", must appear in it, in
;;;;            order, where "..." inside a line stands for any text.  The
;;;;            command must exit 0, unless a line of its output starts with
;;;;            "player: error:", when it must fail.
;;;;   text, cpp, and a fence with no language: shown, not run (output, syntax,
;;;;            excerpts), unless a marker below says otherwise; a "$ " command
;;;;            line in one is a failure (it belongs in a console block).
;;;; Commands in running text, `bin/player ...` in backquotes, are checked
;;;; without running: the command and its options must exist and the values
;;;; parse, unless the span holds an upper-case placeholder (SPEC, FILE) or "...".
;;;;
;;;; An HTML comment on the line before a fence, <!-- readme-test: KIND (REASON) -->,
;;;; changes what happens to the block:
;;;;   skip            not run (an excerpt, or a window that needs a display);
;;;;   script-library  read as data by the script-library reader, with the
;;;;                   scripts it plays or starts but does not define stubbed;
;;;;   trace           a sample trace: each line but "..." (which inside a
;;;;                   line stands for any text) must appear, in order, in the
;;;;                   trace of `bin/player run specs/peedy.lisp --initial
;;;;                   alert=snore --events ev-search`;
;;;;   file            REASON is a path of the checkout whose text the block is;
;;;;   output          a console block whose output lines are checked (the
;;;;                   default for console blocks; the marker says so to readers);
;;;;   c++-interface   each line of the block must be a line of the header
;;;;                   `emit-c++ --timed` writes for specs/peedy.lisp;
;;;;   c++-host        a complete host program: compiled with g++ against that
;;;;                   controller and run, it must exit 0.
;;;; doc/cli.md must be exactly what `bin/player help --markdown` prints; every
;;;; relative link of a page must name a file of the checkout, and so must every
;;;; code span that starts with one of its folders (`src/control/timeline/`).

(in-package #:player-tests)

(def-suite* readme :in player-tests)

(defun readme-lines (&optional (page "README.md"))
  "PAGE (a path relative to the checkout; README.md by default) as a vector of lines."
  (with-open-file (in (checkout-file page) :external-format :utf-8)
    (coerce (loop for line = (read-line in nil) while line collect line) 'vector)))

(defun doc-pages ()
  "The tested pages, relative to the checkout: README.md, then doc/**/*.md in order."
  (cons "README.md"
        (sort (mapcar (lambda (path) (enough-namestring path *root*))
                      (directory (checkout-file "doc/**/*.md")))
              #'string<)))

(defun marker-line-p (line)
  "True when LINE is a readme-test marker comment."
  (alexandria:starts-with-subseq "<!-- readme-test:" (string-trim " " line)))

(defun readme-blocks (lines)
  "The fenced blocks of LINES as (LINE LANGUAGE MARKER BODY): LINE the 1-based
number of the opening fence, MARKER the marker line just before it or NIL, BODY
the lines between the fences."
  (loop with i = 0
        while (< i (length lines))
        if (alexandria:starts-with-subseq "```" (aref lines i))
          collect (let ((end (or (position-if (lambda (l) (alexandria:starts-with-subseq "```" l))
                                              lines :start (1+ i))
                                 (length lines))))
                    (prog1 (list (1+ i) (subseq (aref lines i) 3)
                                 (and (> i 0) (marker-line-p (aref lines (1- i))) (aref lines (1- i)))
                                 (coerce (subseq lines (1+ i) end) 'list))
                      (setf i (1+ end))))
        else do (incf i)))

(defun parse-marker (marker)
  "The kind (a string) and reason of MARKER, <!-- readme-test: KIND (REASON) -->;
NIL when it is not of that form or the kind is unknown or the reason empty."
  (let* ((text (string-trim " " marker))
         (open (position #\( text))
         (close (position #\) text :from-end t))
         (kind (and open (string-trim " " (subseq text (length "<!-- readme-test:") open)))))
    (when (and open close (alexandria:ends-with-subseq "-->" text)
               (member kind '("skip" "script-library" "trace" "file" "output"
                              "c++-interface" "c++-host")
                       :test #'string=)
               (string/= "" (string-trim " " (subseq text (1+ open) close))))
      (values kind (subseq text (1+ open) close)))))

(defun setup-form-p (form)
  "True when FORM is (asdf:load-system ...) or contains a string or pathname with
the placeholder \"/path/to/\"."
  (labels ((walk (x)
             (typecase x
               (cons (or (walk (car x)) (walk (cdr x))))
               (pathname (walk (namestring x)))
               (string (search "/path/to/" x)))))
    (or (and (consp form) (eq (first form) 'asdf:load-system))
        (walk form))))

(defun evaluate-block (body)
  "Read and evaluate the forms of BODY (lines) one by one in *PACKAGE*, skipping
setup forms and discarding their output."
  (with-input-from-string (in (format nil "~{~A~%~}" body))
    (loop with *standard-output* = (make-broadcast-stream)
          for form = (read in nil in)
          until (eq form in)
          unless (setup-form-p form) do (eval form))))

(defun check-library-block (body)
  "Parse BODY (lines) as a script library beside specs/peedy-scripts.lisp, adding
a one-second stub for every script it plays or starts without defining it."
  (let* ((forms (with-input-from-string (in (format nil "~{~A~%~}" body))
                  (with-standard-io-syntax
                    (let ((*read-eval* nil) (*package* (find-package '#:player-user)))
                      (loop for form = (read in nil in) until (eq form in) collect form)))))
         (used (loop for form in forms
                     append (loop for item in (cddr form)
                                  when (and (consp item) (eq (first item) :start))
                                    collect (second item)
                                  when (and (consp item) (member :play item))
                                    collect (second (member :play item)))))
         (defined (mapcar #'second forms))
         (stubs (loop for name in (set-difference used defined :test #'string=)
                      collect `(,(intern "DEFSCRIPT" '#:player-user) ,name (:duration 1)))))
    (player.performance::parse-script-library-forms (append forms stubs)
                                        :source (checkout-file "specs/peedy-scripts.lisp"))))

(defun call-with-readme-sandbox (function)
  "Call FUNCTION with *PACKAGE* a fresh package using CL and PLAYER; then delete
the package, remove the specs FUNCTION defined and restore those it redefined
or removed."
  (let ((saved (mapcar (lambda (name) (cons name (find-spec name))) (list-specs)))
        (package (make-package (string (gensym "PLAYER-README-TEST-")) :use '(#:cl #:player))))
    (unwind-protect
         (let ((*package* package))
           (funcall function))
      (dolist (name (list-specs))
        (unless (assoc name saved :test #'string=)
          (remove-spec name)))
      (loop for (name . spec) in saved
            unless (eq spec (find-spec name nil))
              do (player.spec::register-spec spec))
      (delete-package package))))

(defun page-blocks (page)
  "The fenced blocks of PAGE (see README-BLOCKS), each with its kind (from its
marker, or NIL) appended: (LINE LANGUAGE MARKER BODY KIND)."
  (loop for block in (readme-blocks (readme-lines page))
        collect (append block (list (and (third block) (parse-marker (third block)))))))

(test readme-markers
  "Every readme-test marker of every page is well formed and stands just before a fence."
  (dolist (page (doc-pages))
    (let* ((lines (readme-lines page))
           (blocks (readme-blocks lines)))
      (is (= (count-if #'marker-line-p lines) (count-if #'third blocks))
          "~A: every readme-test marker must be on the line just before a fence" page)
      (dolist (block blocks)
        (when (and (third block) (not (parse-marker (third block))))
          (fail "~A line ~D: malformed marker ~A (want <!-- readme-test: KIND (REASON) -->)"
                page (first block) (third block)))))))

(test readme-lisp-blocks
  "Every ```lisp block of the README and of doc/ runs, unless a marker with a
reason says otherwise; a block marked file is that file's text."
  (dolist (page (doc-pages))
    (call-with-readme-sandbox
     (lambda ()
       (loop for (line language marker body kind) in (page-blocks page)
             do (cond ((equal kind "file")
                       (check-file-block page line (nth-value 1 (parse-marker marker)) body))
                      ((and (string= language "lisp") (not (equal kind "skip")))
                       (handler-case (progn (if (equal kind "script-library")
                                                (check-library-block body)
                                                (evaluate-block body))
                                            (pass))
                         (error (condition)
                           (fail "~A line ~D: ~A" page line condition))))))))))

(defun check-file-block (page line path body)
  "Check that BODY (lines), PAGE's block at LINE, is the text of the checkout's file PATH."
  (let ((file (checkout-file (string-trim " " path))))
    (if (probe-file file)
        (is (equal (coerce (readme-lines (string-trim " " path)) 'list) body)
            "~A line ~D: the block is not the text of ~A" page line path)
        (fail "~A line ~D: ~A does not exist" page line path))))

(defun readme-command-trace ()
  "The trace lines `bin/player run specs/peedy.lisp --initial alert=snore
--events ev-search` prints, computed through the Lisp API."
  (let* ((spec (first (load-spec (checkout-file "specs/peedy.lisp"))))
         (controller (make-controller (compile-spec spec) :initial-state '((alert . snore))
                                                          :presenter (make-trace-presenter))))
    (is (eq t (send-event controller 'ev-search)))
    (trace-of controller)))

(defun sample-line-matches-p (sample line)
  "True when LINE is SAMPLE, where each \"...\" of SAMPLE stands for any text."
  (let ((pieces (loop with start = 0
                      for dots = (search "..." sample :start2 start)
                      collect (subseq sample start dots)
                      while dots do (setf start (+ dots 3))))
        (start 0))
    (loop for (piece . more) on pieces
          for first = t then nil
          for at = (if more
                       (search piece line :start2 start)
                       (let ((at (- (length line) (length piece))))
                         (and (>= at start) (string= piece line :start2 at) at)))
          always (and at (or (not first) (zerop at)))
          do (setf start (+ at (length piece))))))

(test readme-sample-trace
  "The sample trace lines of the block marked trace appear, in order, in the real trace."
  (let* ((found (loop for page in (doc-pages)
                      for block = (find "trace" (page-blocks page) :key #'fifth :test #'equal)
                      when block return (cons page block)))
         (page (car found))
         (sample (cdr found))
         (trace (call-with-readme-sandbox #'readme-command-trace))
         (remaining trace))
    (is-true sample "no page has a block marked <!-- readme-test: trace (...) -->")
    (loop for text in (fourth sample)
          for number from (1+ (or (first sample) 0))
          for wanted = (string-trim " " text)
          unless (member wanted '("" "...") :test #'string=)
            do (let ((found (member wanted remaining :test #'sample-line-matches-p)))
                 (is-true found "~A line ~D: ~A is not in the trace (after the lines ~
                                 before it):~%~{  ~A~%~}" page number wanted trace)
                 (when found (setf remaining (rest found)))))))

;;;# Commands

(defun command-lines (body)
  "The commands of an sh block's BODY (lines): continuation lines joined, comments
and blank lines dropped."
  (let ((commands '()) (pending ""))
    (dolist (raw body (nreverse commands))
      (let* ((hash (search " #" raw))
             (line (string-right-trim " " (if (and hash (not (search "\"" raw))) (subseq raw 0 hash) raw)))
             (continued (alexandria:ends-with-subseq "\\" line))
             (text (concatenate 'string pending
                                (string-trim " " (if continued (subseq line 0 (1- (length line))) line)))))
        (cond (continued (setf pending (concatenate 'string text " ")))
              (t (setf pending "")
                 (unless (or (string= text "") (char= (char text 0) #\#))
                   (push text commands))))))))

(defun command-directory (page)
  "A fresh directory for PAGE's commands, with links to the checkout's specs/,
examples/, t/ and doc/."
  (let ((directory (format nil "/tmp/player-doc-test-~D-~A/" (sb-posix:getpid)
                           (substitute #\- #\/ page))))
    (uiop:delete-directory-tree (pathname directory) :validate t :if-does-not-exist :ignore)
    (ensure-directories-exist directory)
    (dolist (name '("specs" "examples" "t" "doc") directory)
      (sb-ext:run-program "/bin/ln" (list "-s" (namestring (checkout-file name))
                                          (concatenate 'string directory name))))))

(defun run-doc-command (command directory)
  "Run COMMAND (a line starting with bin/player) through /bin/sh in DIRECTORY with
the checkout's bin/player; return (VALUES OUTPUT EXIT-CODE), OUTPUT stdout and
stderr together."
  (ensure-player-core)
  (let* ((line (concatenate 'string (namestring (checkout-file "bin/player"))
                            (subseq command (length "bin/player"))))
         (out (make-string-output-stream))
         (process (sb-ext:run-program "/bin/sh" (list "-c" line) :output out :error :output
                                                                :input nil :search nil
                                                                :directory directory)))
    (values (get-output-stream-string out) (sb-ext:process-exit-code process))))

(defun makefile-targets ()
  "The targets the Makefile defines."
  (with-open-file (in (checkout-file "Makefile"))
    (loop for line = (read-line in nil) while line
          for colon = (position #\: line)
          when (and colon (plusp colon) (alpha-char-p (char line 0)) (not (find #\= line)))
            collect (subseq line 0 colon))))

(defun check-command (page line command directory &optional expected)
  "Check COMMAND of PAGE's block at LINE: run a bin/player command in DIRECTORY,
whose output must hold the EXPECTED lines in order; look up a make target."
  (cond ((alexandria:starts-with-subseq "make " command)
         (is (member (second (split-words command)) (makefile-targets) :test #'string=)
             "~A line ~D: ~A: no such Makefile target" page line command))
        ((alexandria:starts-with-subseq "bin/player " command)
         (multiple-value-bind (output code) (run-doc-command command directory)
           (let ((fails (some (lambda (l) (alexandria:starts-with-subseq "player: error:" l)) expected)))
             (is (if fails (/= 0 code) (= 0 code))
                 "~A line ~D: ~A exited ~D:~%~A" page line command code output))
           (let ((remaining (lines output)))
             (dolist (text expected)
               (unless (string= (string-trim " " text) "...")
                 (let ((found (member text remaining :test #'sample-line-matches-p)))
                   (is-true found "~A line ~D: ~A: the line ~S is not in its output (after the ~
                                   lines before it):~%~A" page line command text output)
                   (when found (setf remaining (rest found)))))))))
        (t (fail "~A line ~D: ~A: a command block may only hold bin/player and make commands"
                 page line command))))

(defun split-words (text)
  "TEXT's words, split at spaces."
  (remove "" (uiop:split-string text :separator " ") :test #'string=))

(defun console-commands (body)
  "A console block's BODY as ((COMMAND . OUTPUT-LINES) ...)."
  (let ((entries '()))
    (dolist (line body (nreverse (mapcar (lambda (e) (cons (car e) (reverse (cdr e)))) entries)))
      (if (alexandria:starts-with-subseq "$ " line)
          (push (list (subseq line 2)) entries)
          (when entries (push line (cdr (first entries))))))))

(defparameter *pages-run-in-the-fast-tier* '("README.md")
  "The pages whose commands `make test-fast` runs (the README's two). The fast
tier only parses the other pages' commands (CHECK-COMMAND-PARSES): running
them, the tutorial's included, is `make test`'s, as the CLI suite runs the
commands themselves in both tiers.")

(defun run-page-commands-p (page)
  "Does this tier run PAGE's commands (rather than only parse them)?"
  (or (eq *test-tier* :full) (member page *pages-run-in-the-fast-tier* :test #'string=)))

(defun check-or-parse-command (page line command directory &optional expected)
  "CHECK-COMMAND when this tier runs PAGE's commands, else CHECK-COMMAND-PARSES
for a bin/player command (a make line is checked either way)."
  (if (or (run-page-commands-p page) (not (alexandria:starts-with-subseq "bin/player " command)))
      (check-command page line command (funcall directory) expected)
      (check-command-parses page line command)))

(test docs-commands
  "Every command of an sh or console block of the README and doc/ runs as written."
  (dolist (page (doc-pages))
    (let ((directory nil))
      (loop for (line language nil body kind) in (page-blocks page)
            unless (equal kind "skip")
              do (flet ((dir () (or directory (setf directory (command-directory page)))))
                   (cond ((string= language "sh")
                          (dolist (command (command-lines body))
                            (check-or-parse-command page line command #'dir)))
                         ((string= language "console")
                          (loop for (command . output) in (console-commands body)
                                do (check-or-parse-command page line command #'dir output)))
                         ((find-if (lambda (text) (alexandria:starts-with-subseq "$ " text)) body)
                          (fail "~A line ~D: a $ command in a ```~A block, which does not run ~
                                 (make it a console block)" page line language)))))
      (when directory
        (uiop:delete-directory-tree (pathname directory) :validate t)))))

(defun inline-commands (lines)
  "The `bin/player ...` code spans of LINES (a page), each as (LINE TEXT); spans
may run across line breaks, as Markdown allows.  Fenced blocks are left out."
  (let ((found '()) (in-fence nil))
    (loop for i from 0 below (length lines)
          for text = (aref lines i)
          do (if (alexandria:starts-with-subseq "```" text)
                 (setf in-fence (not in-fence))
                 (unless in-fence
                   (let ((joined (format nil "~{~A~^ ~}" (coerce (subseq lines i (min (length lines) (+ i 4))) 'list))))
                     (loop for start = (search "`bin/player " text) then (search "`bin/player " text :start2 (1+ start))
                           while start
                           do (let ((end (position #\` joined :start (1+ start))))
                                (when end (push (list (1+ i) (subseq joined (1+ start) end)) found))))))))
    (nreverse found)))

(defun placeholder-command-p (text)
  "Is TEXT a synopsis rather than a command: an upper-case placeholder, ..., or quotes?"
  (or (some #'upper-case-p text) (search "..." text) (find #\" text) (find #\' text)))

(defun shell-words (text)
  "The words of the shell command TEXT, quotes removed, up to the first
unquoted redirection, pipe, comment or command separator (< > | # ; &)."
  (let ((words '()) (word nil) (quote-char nil))
    (flet ((end-word () (when word (push (coerce (nreverse word) 'string) words) (setf word nil))))
      (loop for char across text
            do (cond (quote-char (if (char= char quote-char) (setf quote-char nil) (push char word)))
                     ((find char "\"'") (setf quote-char char) (unless word (setf word '())))
                     ((member char '(#\Space #\Tab)) (end-word))
                     ((and (null word) (find char "<>|#;&")) (return))
                     (t (push char word))))
      (end-word))
    (nreverse words)))

(defun check-command-parses (page line text)
  "Check that the command TEXT (\"bin/player ...\", at LINE of PAGE) names a
command and options that exist, with values that parse, without running it."
  (let ((words (shell-words text)))
    (handler-case
        (let ((name (second words)))
          (cond ((string= name "help")
                 (unless (member (third words) '(nil "--markdown") :test #'equal)
                   (player.cli::find-command (third words))))
                ((null (cddr words))  ; `bin/player record`: the command's name
                 (player.cli::find-command name))
                (t (player.cli::parse-command-arguments (player.cli::find-command name)
                                                        (cddr words))))
          (pass))
      (error (condition)
        (fail "~A line ~D: `~A`: ~A" page line text condition)))))

(test docs-inline-commands
  "Every `bin/player ...` of the docs' running text names a command and options that exist."
  (dolist (page (doc-pages))
    (loop for (line text) in (inline-commands (readme-lines page))
          unless (placeholder-command-p text)
            do (check-command-parses page line text))))

;;;# The CLI page, links, paths and the C++ host

(defparameter *checkout-folders* '("src/" "t/" "specs/" "bench/" "examples/" "bin/" "doc/")
  "The folders whose files the docs name in backquotes, `src/control/timeline/`.")

(defun page-paths (page)
  "The paths of the checkout PAGE names as code spans, as (LINE PATH); globs and
placeholders (`src/<layer>/`) left out."
  (loop for text across (readme-lines page)
        for number from 1
        append (loop for start = (position #\` text) then (position #\` text :start (1+ end))
                     for end = (and start (position #\` text :start (1+ start)))
                     while end
                     for span = (subseq text (1+ start) end)
                     when (and (some (lambda (folder) (alexandria:starts-with-subseq folder span))
                                     *checkout-folders*)
                               (not (find-if (lambda (char) (find char " *<>{}")) span)))
                       collect (list number span))))

(test docs-paths
  "Every file or folder of the checkout the README and doc/ name in backquotes exists."
  (dolist (page (doc-pages))
    (loop for (line path) in (page-paths page)
          do (is-true (probe-file (checkout-file path))
                      "~A line ~D: ~A does not exist (moved? see doc/internals/architecture.md)"
                      page line path))))

(test cli-page-is-generated
  "doc/cli.md is what `bin/player help --markdown` prints now."
  (multiple-value-bind (out err code) (player-command "help" "--markdown")
    (is (= 0 code))
    (is (string= "" err))
    (is (string= out (alexandria:read-file-into-string (checkout-file "doc/cli.md")
                                                       :external-format :utf-8))
        "doc/cli.md is out of date: run bin/player help --markdown > doc/cli.md")))

(defun page-links (page)
  "The relative link targets of PAGE, as (LINE TARGET), anchors dropped."
  (loop for text across (readme-lines page)
        for number from 1
        append (loop for start = (search "](" text) then (search "](" text :start2 (1+ start))
                     while start
                     for end = (position #\) text :start start)
                     for target = (and end (subseq text (+ start 2) end))
                     when (and target (string/= target "")
                               (not (search "://" target)) (char/= (char target 0) #\#))
                       collect (list number (subseq target 0 (position #\# target))))))

(test docs-links
  "Every relative link of the README and of doc/ names a file of the checkout."
  (dolist (page (doc-pages))
    (loop for (line target) in (page-links page)
          do (is-true (probe-file (merge-pathnames target (checkout-file page)))
                      "~A line ~D: the link ~A names no file" page line target))))

(defun marked-block (page kind)
  "The body of PAGE's block marked KIND, or a failure."
  (let ((block (find kind (page-blocks page) :key #'fifth :test #'equal)))
    (is-true block "~A has no block marked <!-- readme-test: ~A (...) -->" page kind)
    (fourth block)))

(test cpp-page-interface-and-host
  "doc/cpp.md's interface is the generated header's, and its host program compiles
against Peedy's timed controller and runs."
  (let* ((directory (format nil "/tmp/player-doc-cpp-~D/" (sb-posix:getpid)))
         (interface (marked-block "doc/cpp.md" "c++-interface"))
         (host (marked-block "doc/cpp.md" "c++-host")))
    (ensure-directories-exist directory)
    (unwind-protect
         (progn
           (player:emit-c++ (plan-spec (first (load-spec (checkout-file "specs/peedy.lisp"))))
                            directory :name "peedy" :namespace "peedy" :timed t)
           (let ((header (lines (alexandria:read-file-into-string
                                 (merge-pathnames "peedy.hpp" directory)))))
             (dolist (line interface)
               (is (member line header :test #'string=)
                   "doc/cpp.md: ~S is not a line of the generated peedy.hpp" line)))
           (alexandria:write-string-into-file (format nil "~{~A~%~}" host)
                                              (merge-pathnames "host.cpp" directory))
           (let* ((out (make-string-output-stream))
                  (flags '("-std=c++17" "-O1" "-Wall" "-Wextra" "-Werror" "-pedantic"))
                  ;; Kept by content, like the C++ suites' builds: the same
                  ;; sources and flags compiled once are not compiled again.
                  (cached (merge-pathnames
                           (format nil "doc-host-~A" (apply #'player.cpp::content-key
                                                            (format nil "~{~A ~}" flags)
                                                            (mapcar (lambda (file)
                                                                      (alexandria:read-file-into-string
                                                                       (merge-pathnames file directory)))
                                                                    '("host.cpp" "peedy.cpp" "peedy.hpp"))))
                           (player.cpp::c++-cache-root)))
                  (compiled (or (probe-file cached)
                                (let ((compile (sb-ext:run-program "/usr/bin/env"
                                                                   (append '("g++") flags
                                                                           '("-I." "host.cpp" "peedy.cpp" "-o" "host"))
                                                                   :directory directory :output out :error :output)))
                                  (is (= 0 (sb-ext:process-exit-code compile))
                                      "doc/cpp.md's host does not compile:~%~A" (get-output-stream-string out))
                                  (when (= 0 (sb-ext:process-exit-code compile))
                                    ;; Copied beside the cache entry, then renamed into
                                    ;; place: an interrupted copy is never taken for a build.
                                    (let ((partial (make-pathname :type "partial" :defaults cached)))
                                      (ensure-directories-exist cached)
                                      (uiop:copy-file (merge-pathnames "host" directory) partial)
                                      (sb-posix:chmod (namestring partial) #o755)
                                      (sb-posix:rename (namestring partial) (namestring cached)))
                                    cached)))))
             (when compiled
               (let ((run (sb-ext:run-program (namestring compiled) '()
                                              :output out :error :output)))
                 (is (= 0 (sb-ext:process-exit-code run))
                     "doc/cpp.md's host exited ~D:~%~A" (sb-ext:process-exit-code run)
                     (get-output-stream-string out))))))
      (uiop:delete-directory-tree (pathname directory) :validate t :if-does-not-exist :ignore))))
