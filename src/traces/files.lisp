;;;; files.lisp -- a recording as a file: the (:recording ...) header, the
;;;; trace lines one per line, then the frames one per line.  Every line is
;;;; one form, so the file reads back through READ-DATA-FILE as data: no code
;;;; runs on reading, and an error names the file and line.

(in-package #:player.traces)

;;;# Paths relative to the recording

(defun directory-components (path)
  "The directory names of the absolute PATH, outermost first."
  (rest (pathname-directory path)))

(defun relative-file-name (file directory)
  "The name of the existing FILE relative to the existing DIRECTORY, with ..
where it leaves DIRECTORY (\"../../specs/peedy.lisp\"); FILE's absolute name
when the two share no directory."
  (let* ((file (truename file))
         (from (directory-components (truename directory)))
         (to (directory-components file))
         (common (or (mismatch from to :test #'equal) (length from))))
    (if (zerop common)
        (native-namestring file)
        (format nil "~{~A/~}~{~A/~}~A"
                (make-list (- (length from) common) :initial-element "..")
                (nthcdr common to) (file-namestring file)))))

(defun recorded-file-name (file recording-file)
  "FILE (a path, or NIL) as a recording written to RECORDING-FILE stores it:
relative to RECORDING-FILE's directory, or absolute when FILE does not exist."
  (when file
    (if (probe-file file)
        (relative-file-name file (directory-namestring (merge-pathnames recording-file)))
        (native-namestring (merge-pathnames file)))))

;;;# Writing

(defun write-header (recording stream)
  "Write RECORDING's header to STREAM, one field per line."
  (with-recording-syntax ()
    (loop for (key value) on (rest (recording-header recording)) by #'cddr
          for first = t then nil
          do (format stream "~:[~% ~;(:recording~] ~S ~S" first key value))
    (format stream ")~%")))

(defun write-recording (recording file)
  "Write RECORDING to FILE (a path; its directories are made): a comment, the
header, the trace lines, then the frames.  The recording's SPEC-FILE and
SCRIPTS are written as given; RECORD-SCENARIO makes them relative to FILE.
Returns FILE's truename.  Signals a PLAYER-ERROR when FILE cannot be written."
  (check-argument 'write-recording 'recording recording #'recording-p "a recording (from record-scenario)")
  (check-argument 'write-recording 'file file #'pathname-designator-p *path-phrase*)
  (with-atomic-output-file (out file :follow-links t :make-directories t)
        (format out ";;;; A scenario recorded by `bin/player record`; replay it with~%~
                     ;;;; `bin/player verify SPEC-FILE ~A`.~%" (file-namestring file))
        (write-header recording out)
        (format out ";;; The trace, as `bin/player run` prints it.~%~{~A~%~}" (recording-lines recording))
        (when (recording-frames-p recording)
          (format out ";;; The body frames, as `bin/player simulate --frames` writes them.~%")
          (dolist (frame (recording-frames recording))
            (write-line (frame-text frame) out))))
  (truename file))

;;;# Reading

(defun frame-form-p (form)
  "Is FORM shaped as a frame: (:frame INDEX :time SECONDS ...), a proper list?"
  (and (proper-list-p form) (eq (first form) :frame) (integerp (second form))
       (eq (third form) :time) (realp (fourth form))))

(defun add-recorded-form (recording form line)
  "Add FORM, read at LINE of RECORDING's file, to RECORDING: a trace line
before any frame, or a frame when frames were recorded; else a RECORDING-ERROR."
  (let ((file (recording-file recording)))
    (cond ((and (consp form) (eq (first form) :frame))
           (unless (recording-frames-p recording)
             (recording-fail file line "a frame, but the header says :frames nil"))
           (unless (frame-form-p form)
             (recording-fail file line "a frame must read (:frame INDEX :time SECONDS ...), not ~A"
                             (bounded-lisp-text form 80)))
           (push form (recording-frames recording))
           (push line (recording-frame-line-numbers recording)))
          ((recording-frames recording)
           (recording-fail file line "a trace line after the frames: ~A" (bounded-lisp-text form 80)))
          ((and (canonical-trace-line form) (find-if #'control-character-p (canonical-trace-line form)))
           (recording-fail file line "a trace line holds a control character (a line break in a name would forge lines): ~A"
                           (bounded-lisp-text form 80)))
          ((canonical-trace-line form)
           (push (canonical-trace-line form) (recording-lines recording))
           (push line (recording-line-numbers recording)))
          (t (recording-fail file line "not a trace line such as (:event ev :time 0): ~A"
                             (bounded-lisp-text form 80))))))

(defun read-recording (file)
  "The RECORDING in FILE, written by WRITE-RECORDING (or `bin/player record`).
The file is read as data (READ-DATA-FILE: nothing in it runs).  Signals a
RECORDING-ERROR naming FILE and the line at fault when FILE is missing, not
readable as data, has no valid (:recording ...) header first, or holds
something other than trace lines followed by frames."
  (check-argument 'read-recording 'file file #'pathname-designator-p *path-phrase*)
  (multiple-value-bind (entries text)
      (read-data-file file :what "recording" :allow-in-package nil
                           :fail (lambda (position message kind)
                                   ;; A missing file's message names it already.
                                   (if (member kind '(:missing :not-regular))
                                       (error 'recording-error :file file :message message)
                                       (recording-fail file (and position (position-line file position))
                                                       "~A" message))))
    (when (null entries)
      (recording-fail file nil "the file is empty: a recording begins with its header (:recording ...)"))
    (destructuring-bind ((header header-position &rest more) &rest body) entries
      (declare (ignore more))
      (let ((recording (header-recording header file (line-of text header-position)))
            (counted 0) (line 1))
        ;; Lines counted on from the form before, so a long recording reads in linear time.
        (loop for (form position) in body
              do (incf line (count #\Newline text :start counted :end position))
                 (setf counted position)
                 (add-recorded-form recording form line))
        (when (and (recording-frames-p recording) (null (recording-frames recording)))
          (recording-fail file nil "the header says :frames t, but no frame follows the trace"))
        (setf (recording-lines recording) (nreverse (recording-lines recording))
              (recording-line-numbers recording) (nreverse (recording-line-numbers recording))
              (recording-frames recording) (nreverse (recording-frames recording))
              (recording-frame-line-numbers recording) (nreverse (recording-frame-line-numbers recording)))
        recording))))
