;;;; clip-files.lisp -- clips played :from another file: a BVH or any model
;;;; Assimp reads, its clip retargeted onto the body (retarget.lisp).  The
;;;; clip resolver registered here gives the :clip driver such a clip when its
;;;; call names a file.  A file is imported once, and a clip retargeted once
;;;; per skeleton: the imported source is kept per file (truename and write
;;;; date, so an edited file is read again) in a small table, and the
;;;; retargeted clips in a table per skeleton, weak on the skeleton, so a
;;;; skeleton nobody uses any more takes its clips with it.
;;;;
;;;; A clip of the file is named as the (model "FILE") form names it: each
;;;; animation's name made a clip name (CLIP-NAME-FROM-ANIMATION), "animation"
;;;; for an unnamed one.  Assimp names a BVH file's one animation "Motion", so
;;;; a BVH file's clip is "motion".

(in-package #:player.rig)

(defparameter *clip-file-limit* 8
  "How many imported clip files are kept; more empties the table.")

(defvar *clip-files* (make-hash-table :test #'equal)
  "Truename string -> (WRITE-DATE . SKELETON), the imported source of each clip file.")

(defvar *retargeted-clips* (make-hash-table :test #'eq :weakness :key)
  "Target skeleton -> an EQUAL table of (TRUENAME WRITE-DATE NAME) -> retargeted CLIP.")

(defvar *clip-files-lock* (bt:make-lock "player clip files")
  "The lock every read and write of *CLIP-FILES* and *RETARGETED-CLIPS* holds.")

(defun clip-file-truename (path)
  "PATH's truename as a string; a RIG-ERROR naming PATH when there is no such file."
  (let ((found (ignore-errors (probe-file path))))
    (unless (and found (pathname-name found))
      (rig-fail (namestring path) "there is no clip file ~A" (namestring path)))
    (namestring found)))

(defun clip-file-source (path)
  "Two values: the source skeleton (MODEL-SKELETON, with its clips) of the
model or BVH file PATH, imported once per version of the file, and its
truename.  A RIG-ERROR for a missing file; IMPORT-MODEL's MODEL-ERROR for one
Assimp cannot read."
  (let* ((truename (clip-file-truename path))
         (date (file-write-date truename))
         (cached (bt:with-lock-held (*clip-files-lock*) (gethash truename *clip-files*))))
    (values (if (and cached (eql (car cached) date))
                (cdr cached)
                (let ((skeleton (model-skeleton (import-model truename))))
                  (bt:with-lock-held (*clip-files-lock*)
                    (when (>= (hash-table-count *clip-files*) *clip-file-limit*)
                      (clrhash *clip-files*))
                    (setf (gethash truename *clip-files*) (cons date skeleton)))
                  skeleton))
            truename)))

(defun clip-file-clip (path name)
  "The clip NAME of the file PATH as the file has it (on its own skeleton); a
RIG-ERROR listing the file's clips when it has none called NAME."
  (find-clip (skeleton-rig (clip-file-source path)) name t))

(defun retargeted-clip (path name skeleton)
  "The clip NAME of the file PATH retargeted onto SKELETON (RETARGET-CLIP),
made once per skeleton and version of the file.  Signals as CLIP-FILE-SOURCE,
and a RIG-ERROR when the file has no clip NAME."
  (multiple-value-bind (source truename) (clip-file-source path)
    (let ((key (list truename (file-write-date truename) (string-downcase (string name)))))
      (or (bt:with-lock-held (*clip-files-lock*)
            (let ((table (gethash skeleton *retargeted-clips*)))
              (and table (gethash key table))))
          (let ((clip (retarget-clip source name skeleton)))
            (bt:with-lock-held (*clip-files-lock*)
              (setf (gethash key (or (gethash skeleton *retargeted-clips*)
                                     (setf (gethash skeleton *retargeted-clips*)
                                           (make-hash-table :test #'equal))))
                    clip)))))))

(defun resolve-clip-from-file (driver)
  "The clip resolver for a :clip call with :from FILE: its clip retargeted onto
DRIVER's skeleton; NIL for a call without :from.  A MOTOR-ERROR about the call
when the file is missing or unreadable or lacks the clip."
  (let ((from (driver-arg driver :from)))
    (when from
      (handler-case (retargeted-clip from (driver-arg driver :name) (driver-skeleton driver))
        (player-error (condition)
          (driver-frame-fail driver "~A" condition))))))

(pushnew 'resolve-clip-from-file *clip-resolvers*)
