;;;; cast.lisp -- scenes on the command line: a SCENE-FILE holding a defscene
;;;; (run, simulate, render and view take it in place of a spec file), or
;;;; --cast SPEC:N, N members of one spec called SPEC1 ... SPECN.  Events are
;;;; then addresses: --events left/ev-search@0,all/ev-thanks@2.

(in-package #:player.cli)

(defparameter *max-cast-size* 1000 "The most members --cast makes.")

(defmethod read-option-value ((type (eql :cast)) text option)
  ;; SPEC:N or N, as (SPEC-NAME-OR-NIL . N).
  (let* ((colon (position #\: text))
         (name (and colon (subseq text 0 colon)))
         (count (ignore-errors (parse-integer text :start (if colon (1+ colon) 0)))))
    (unless (and count (<= 1 count *max-cast-size*) (or (null name) (plusp (length name))))
      (bad-option-value option text (format nil "SPEC:N or N, N a number of members from 1 to ~D (e.g. peedy:2)"
                                            *max-cast-size*)))
    (cons name count)))

(define-option "--cast" :cast "SPEC:N"
  "play N copies of the spec in one scene, members SPEC1 ... SPECN; events are then addressed MEMBER/EVENT or all/EVENT")

(defun scene-file-p (file)
  "Does FILE read as data and hold a defscene form?  NIL when it cannot be
read: the ordinary spec-file path then reports why."
  (block read
    (let ((entries (read-data-file file :what "scene file"
                                        :fail (lambda (&rest arguments)
                                                (declare (ignore arguments))
                                                (return-from read nil)))))
      (some (lambda (entry) (defscene-form-p (first entry))) entries))))

(defun choose-cast-from (casts file name)
  "The scene of CASTS called NAME (a string), or the only one; a USAGE-ERROR otherwise."
  (flet ((names () (mapcar (lambda (c) (lisp-text (cast-name c))) casts)))
    (cond (name (or (find name casts :key (lambda (c) (symbol-name (cast-name c))) :test #'string-equal)
                    (usage-fail "~A defines no scene ~A (it defines ~{~A~^, ~})" file (string-downcase name) (names))))
          ((rest casts) (usage-fail "~A defines several scenes (~{~A~^, ~}); choose one with --spec" file (names)))
          (t (first casts)))))

(defun command-cast (file spec cast allow-code)
  "The scene a command plays: FILE's defscene (SPEC, the --spec option, choosing
among several), or with CAST, (SPEC-NAME . N) from --cast, N copies of
FILE's spec; NIL for an ordinary spec file without --cast."
  (cond ((scene-file-p file)
         (when cast (usage-fail "--cast makes a scene of a spec file; ~A defines a scene already" file))
         (choose-cast-from (load-scene-file file :allow-code allow-code) file spec))
        (cast
         (when (and spec (car cast) (string-not-equal spec (car cast)))
           (usage-fail "--spec ~A and --cast ~A:~D name different specs" spec (car cast) (cdr cast)))
         (replicate-cast (choose-spec file (or (car cast) spec) :allow-code allow-code) (cdr cast)))))

(defun refuse-scene-option (name value)
  "A USAGE-ERROR when the option NAME, given (VALUE true), does not apply to a scene."
  (when value (usage-fail "~A plays one spec; it does not apply to a scene" name)))

(defun run-scene (cast &key initial events at when-busy)
  "`player run` on a scene: each member plays the events addressed to it; the
trace is each member's lines in turn, prefixed \"MEMBER: \"."
  (check-scenario-times events at)
  (let ((ensemble (make-ensemble cast :initial initial
                                      :timed (scene-timed-members cast events at when-busy))))
    (if (or events at)
        (progn (play-scene-events ensemble events :until at :when-busy when-busy)
               (write-ensemble-trace ensemble))
        (write-ensemble-states ensemble))))

(defun print-scene-summary (simulation frame-count fps)
  "PRINT-SCENARIO-SUMMARY for a scene: the members and their places first."
  (loop for member in (cast-members (ensemble-cast (scene-simulation-ensemble simulation)))
        do (format t "; ~A: ~A at (~{~A~^ ~})~%" (lisp-text (cast-member-name member))
                   (lisp-text (cast-member-spec member))
                   (mapcar #'format-number (cast-member-position member))))
  (print-scenario-summary simulation frame-count fps))
