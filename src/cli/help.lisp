;;;; help.lisp -- `player help` and `player help CMD` (= `player CMD --help`),
;;;; written from the command table.

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
  (format stream "~%`player help COMMAND` or `player COMMAND --help` describes one command.~%"))

(defun print-help (&optional command-name)
  "Print the global help, or with COMMAND-NAME that command's help (a
USAGE-ERROR for an unknown command)."
  (if command-name
      (print-command-help (find-command command-name))
      (print-global-help)))
