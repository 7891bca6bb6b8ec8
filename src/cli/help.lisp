;;;; help.lisp -- `player help` and `player help CMD` (= `player CMD --help`),
;;;; written from the command table; `player help --markdown`, the same table
;;;; as the Markdown page doc/cli.md.

(in-package #:player.cli)

(defun command-synopsis (command)
  "COMMAND's one-line synopsis: player NAME ARGUMENTS [OPTIONS]."
  (format nil "player ~A~{ ~A~}~:[~; [OPTIONS]~]" (command-name command)
          (command-arguments command) (command-options command)))

(defun option-label (option)
  "How help shows OPTION: --fps FPS, or --flag alone."
  (if (eq (option-type option) :flag)
      (option-name option)
      (format nil "~A ~A" (option-name option) (option-metavar option))))

(defun wrap-words (text width)
  "TEXT's words as lines of at most WIDTH characters (a longer word stands alone)."
  (let ((lines '()) (line ""))
    (dolist (word (split-list text :separator #\Space) (nreverse (if (string= line "") lines (cons line lines))))
      (cond ((string= line "") (setf line word))
            ((<= (+ (length line) 1 (length word)) width)
             (setf line (concatenate 'string line " " word)))
            (t (push line lines) (setf line word))))))

(defparameter *help-width* 79 "The widest line help writes.")

(defun print-option-help (option stream)
  "Write OPTION's help: its label, then its help and default, wrapped in a column."
  (let* ((label (option-label option))
         (text (format nil "~A~@[ (default: ~A)~]" (option-help option) (option-default-text option)))
         (lines (wrap-words text (- *help-width* 27))))
    (if (<= (length label) 24)
        (format stream "  ~24A ~A~%" label (first lines))
        (format stream "  ~A~%  ~24A ~A~%" label "" (first lines)))
    (dolist (line (rest lines))
      (format stream "  ~24A ~A~%" "" line))))

(defun print-command-help (command &optional (stream *standard-output*))
  "Write COMMAND's help: synopsis, summary, description, options and output."
  (format stream "usage: ~A~%~%~A.~%" (command-synopsis command) (command-summary command))
  (when (command-description command)
    (format stream "~%~A~%" (command-description command)))
  (when (command-options command)
    (format stream "~%options:~%")
    (dolist (option (command-options command))
      (print-option-help option stream)))
  (when (command-output command)
    (format stream "~%output: ~A~%" (command-output command))))

(defun print-global-help (&optional (stream *standard-output*))
  "Write the list of commands with their synopses and summaries."
  (format stream "usage: player COMMAND [ARGUMENTS] [OPTIONS]~%~%commands:~%")
  (dolist (command *commands*)
    (format stream "  ~A~%      ~A~%" (command-synopsis command) (command-summary command)))
  (format stream "~%`player help COMMAND` or `player COMMAND --help` describes one command.~%")
  (format stream "Every command also takes --max-memory SIZE (e.g. 512M, 4G): its heap, by default~%~
half the machine's memory and at most 2 GB.~%"))

(defun print-help (&optional command-name)
  "Print the global help, or with COMMAND-NAME that command's help (a
USAGE-ERROR for an unknown command), or with \"--markdown\" every command's
help as the Markdown page doc/cli.md."
  (cond ((null command-name) (print-global-help))
        ((string= command-name "--markdown") (print-markdown-help))
        (t (print-command-help (find-command command-name)))))

;;;# The command table as Markdown: doc/cli.md

;;; doc/cli.md is this output, committed; t/test-readme.lisp fails when the two
;;; differ, so the page can never fall behind the table.

(defun markdown-cell (text)
  "TEXT for one cell of a Markdown table: its lines joined by spaces, its pipes escaped."
  (let ((flat (format nil "~{~A~^ ~}" (mapcar (lambda (line) (string-trim " " line))
                                             (split-list text :separator #\Newline)))))
    (with-output-to-string (out)
      (loop for char across flat
            do (when (char= char #\|) (write-char #\\ out))
               (write-char char out)))))

(defun sentence-case (text)
  "TEXT with its first letter in upper case and the rest as written."
  (if (string= text "")
      text
      (concatenate 'string (string (char-upcase (char text 0))) (subseq text 1))))

(defun markdown-paragraph (text)
  "TEXT, as a help description is written (lines indented for the terminal), as one paragraph."
  (format nil "~{~A~^ ~}" (remove "" (mapcar (lambda (line) (string-trim " " line))
                                             (split-list text :separator #\Newline))
                                  :test #'string=)))

(defun print-command-markdown (command stream)
  "Write COMMAND's section of doc/cli.md: synopsis, summary, description, options, output."
  (format stream "~%## ~A~%~%```text~%~A~%```~%~%~A.~%"
          (command-name command) (command-synopsis command)
          (sentence-case (command-summary command)))
  (when (command-description command)
    (format stream "~%~A~%" (markdown-paragraph (command-description command))))
  (when (command-options command)
    (format stream "~%| option | meaning | default |~%| --- | --- | --- |~%")
    (dolist (option (command-options command))
      (format stream "| `~A` | ~A | ~@[`~A`~] |~%" (markdown-cell (option-label option))
              (markdown-cell (option-help option))
              (and (option-default-text option) (markdown-cell (option-default-text option))))))
  (when (command-output command)
    (format stream "~%Output: ~A~%" (markdown-paragraph (command-output command)))))

(defun print-markdown-help (&optional (stream *standard-output*))
  "Write doc/cli.md, the reference of every command, from the command table."
  (format stream "# Command line: `bin/player`~%~%~
<!-- Generated by `bin/player help --markdown` from src/cli/commands.lisp; do not edit. -->~%~%~
Every command, its options with their types and defaults, and where its output~%~
goes are declared once, in `src/cli/`; this page is that table. Options take~%~
their value as the next word or after `=` (`--events=ev-search`). `bin/player~%~
help COMMAND` (or `bin/player COMMAND --help`) prints one command's part.~%~
Every command also takes `--max-memory SIZE` (`512M`, `4G`): the heap it may~%~
use, by default half the machine's memory and at most 2 GB; running out is one~%~
`ran out of memory (limit ...)` error.~%~%~
| command | what it does |~%| --- | --- |~%")
  (dolist (command *commands*)
    (format stream "| [`~A`](#~A) | ~A |~%" (command-name command)
            (remove-if-not (lambda (char) (or (alphanumericp char) (char= char #\-)))
                           (command-name command))
            (markdown-cell (command-summary command))))
  (dolist (command *commands*)
    (print-command-markdown command stream)))
