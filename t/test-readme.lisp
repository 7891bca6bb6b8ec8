;;;; test-readme.lisp -- the README is tested: its Lisp blocks run, its sample trace is real.
;;;;
;;;; Every ```lisp block of README.md is read and evaluated in order, all in one
;;;; fresh package (IN-PACKAGE forms switch, as at a REPL), output discarded;
;;;; a block that signals an error is one failure naming its line.
;;;; Afterwards the package is deleted, specs the blocks defined are removed and
;;;; specs they redefined are restored.  REPL setup forms are not evaluated:
;;;; (asdf:load-system ...), since the test runs in a loaded Player, and forms
;;;; with the placeholder path "/path/to/" (the reader's checkout goes there).
;;;; An HTML comment on the line before a fence, <!-- readme-test: KIND (REASON) -->,
;;;; changes what happens to the block:
;;;;   skip            not run (an excerpt that is not valid Lisp on its own);
;;;;   script-library  read as data by the script-library reader, with the
;;;;                   scripts it plays or starts but does not define stubbed;
;;;;   trace           a sample trace: each line but "..." (which inside a
;;;;                   line stands for any text) must appear, in order, in the
;;;;                   trace of `bin/player run specs/peedy.lisp --initial
;;;;                   alert=snore --events ev-search`.

(in-package #:player-tests)

(def-suite* readme :in player-tests)

(defun readme-lines ()
  "README.md as a vector of lines."
  (with-open-file (in (checkout-file "README.md") :external-format :utf-8)
    (coerce (loop for line = (read-line in nil) while line collect line) 'vector)))

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
               (member kind '("skip" "script-library" "trace") :test #'string=)
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

(test readme-lisp-blocks
  "Every ```lisp block of README.md runs, unless a marker with a reason says otherwise."
  (let* ((lines (readme-lines))
         (blocks (readme-blocks lines)))
    (is (= (count-if #'marker-line-p lines) (count-if #'third blocks))
        "every readme-test marker must be on the line just before a fence")
    (dolist (block blocks)
      (when (and (third block) (not (parse-marker (third block))))
        (fail "README.md line ~D: malformed marker ~A (want <!-- readme-test: ~
               skip|script-library|trace (REASON) -->)" (first block) (third block))))
    (call-with-readme-sandbox
     (lambda ()
       (loop for (line language marker body) in blocks
             for kind = (and marker (parse-marker marker))
             when (and (string= language "lisp") (not (equal kind "skip")))
               do (handler-case (progn (if (equal kind "script-library")
                                           (check-library-block body)
                                           (evaluate-block body))
                                       (pass))
                    (error (condition)
                      (fail "README.md line ~D: ~A" line condition))))))))

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
  "The README's sample trace lines appear, in order, in the real trace."
  (let* ((sample (find "trace" (readme-blocks (readme-lines))
                       :key (lambda (block) (and (third block) (parse-marker (third block))))
                       :test #'equal))
         (trace (call-with-readme-sandbox #'readme-command-trace))
         (remaining trace))
    (is-true sample "README.md has no block marked <!-- readme-test: trace (...) -->")
    (loop for text in (fourth sample)
          for number from (1+ (or (first sample) 0))
          for wanted = (string-trim " " text)
          unless (member wanted '("" "...") :test #'string=)
            do (let ((found (member wanted remaining :test #'sample-line-matches-p)))
                 (is-true found "README.md line ~D: ~A is not in the trace (after the lines ~
                                 before it):~%~{  ~A~%~}" number wanted trace)
                 (when found (setf remaining (rest found)))))))
