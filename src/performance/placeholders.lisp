;;;; placeholders.lisp -- the performance of a spec that names no script
;;;; library: a script library made up from the spec itself, so a new user's
;;;; first spec renders.  Every script an op needs becomes one built-in gesture
;;;; lasting the op's :duration, chosen from the op's name (the same name
;;;; always makes the same gesture, different names usually different ones);
;;;; every autoscript procedure a slow looping bob of the head.  The body
;;;; presenter draws each op's name as a caption while it plays (see
;;;; captions.lisp here and in render/).  Gestures use only the skeleton's roles
;;;; and the poses shipped for it, so they play on the humanoid, the parrot or
;;;; any skeleton that fills the roles; a gesture the skeleton cannot make is
;;;; left out.

(in-package #:player.performance)

(defparameter *placeholder-gestures*
  '((:nod :head)
    (:shake :head)
    (:beat :right-arm)
    (:brows :brows)
    (:raise (arms-raised wings-spread))
    (:bow (bow-down bow)))
  "The built-in gestures, each (NAME NEED): NEED is a role the skeleton must
fill, :BROWS (brows or a crest), or a list of poses of which the skeleton's
shipped pose library must have one.")

(defparameter *shortest-gesture* 0.2d0
  "Seconds below which an op's placeholder makes no gesture: there is no time to see one.")

(defun name-number (name)
  "A number made from the characters of NAME (case-insensitively), the same in every Lisp session."
  (let ((sum 0))
    (loop for char across (string-downcase (string name))
          for k from 1
          do (setf sum (mod (+ (* 31 sum) (* k (char-code char))) 1000003)))
    sum))

(defun gesture-pose (need skeleton)
  "The first of the poses NEED lists that SKELETON's shipped pose library has, or NIL."
  (let ((library (shipped-pose-library skeleton)))
    (find-if (lambda (name) (find-pose library name nil)) need)))

(defun gesture-possible-p (gesture skeleton)
  "Can SKELETON make GESTURE, an entry of *PLACEHOLDER-GESTURES*?"
  (let ((need (second gesture)))
    (cond ((consp need) (and (gesture-pose need skeleton) t))
          ((eq need :brows) (or (skeleton-role skeleton :left-brow) (skeleton-role skeleton :crest)))
          (t (and (skeleton-role skeleton need) t)))))

(defun placeholder-gesture (name skeleton)
  "The gesture (an entry of *PLACEHOLDER-GESTURES*) an op called NAME makes on SKELETON, or NIL."
  (let ((possible (remove-if-not (lambda (g) (gesture-possible-p g skeleton)) *placeholder-gestures*)))
    (and possible (nth (mod (name-number name) (length possible)) possible))))

(defun gesture-motor-frame (gesture skeleton duration)
  "The motor call making GESTURE on SKELETON over DURATION seconds."
  (let ((d (float duration 1d0)))
    (ecase (first gesture)
      (:nod `(:head :action :nod :count 2 :amplitude 20 :duration ,(* 0.9d0 d)))
      (:shake `(:head :action :shake :count 2 :amplitude 25 :duration ,(* 0.9d0 d)))
      (:beat `(:beat :arm :right :times ,(list (* 0.25d0 d) (* 0.5d0 d) (* 0.75d0 d))
                     :amplitude 3 :stroke ,(min 0.1d0 (* 0.1d0 d)) :retract ,(min 0.25d0 (* 0.2d0 d))))
      (:brows `(:eyebrows :raise 1 :duration ,(* 0.2d0 d) :hold ,(* 0.5d0 d)))
      ((:raise :bow)
       `(:keyframe :keys ((0 :start) (,(* 0.4d0 d) ,(gesture-pose (second gesture) skeleton))
                          (,(* 0.6d0 d) ,(gesture-pose (second gesture) skeleton)) (,d :start)))))))

(defun placeholder-script-form (name duration skeleton &key (gesture-name name))
  "A DEFSCRIPT form: the script NAME lasting DURATION, making the gesture
GESTURE-NAME chooses on SKELETON (none when DURATION is too short)."
  (let ((gesture (and (>= duration *shortest-gesture*) (placeholder-gesture gesture-name skeleton))))
    `(defscript ,name (:duration ,(float duration 1d0)
                       :documentation ,(format nil "Placeholder: ~(~A~)." (if gesture (first gesture) "pause")))
       ,@(and gesture `((:at 0 :motor ,(gesture-motor-frame gesture skeleton duration)))))))

(defun placeholder-loop-form (name skeleton)
  "A looping DEFSCRIPT form for the autoscript procedure NAME: a slow, small
nod of the head every two seconds, under every op's gesture (priority 5)."
  `(defscript ,name (:duration 2 :loop t :documentation "Placeholder: a slow bob of the head.")
     ,@(and (skeleton-role skeleton :head)
            '((:at 0 :motor (:head :action :nod :count 1 :amplitude 5 :duration 2 :priority 5))))))

(defun spec-op-scripts (spec)
  "(SCRIPT-NAME . OP) for each script or director SPEC's ops play, the first op
playing it, in spec order."
  (let ((seen '()))
    (dolist (op (spec-ops spec) (nreverse seen))
      (let ((name (op-script-name op)))
        (when (and name (not (assoc name seen :test #'string-equal)))
          (push (cons name op) seen))))))

(defun make-placeholder-library (spec skeleton)
  "A script library playing every op of SPEC as a placeholder gesture on
SKELETON (see the top of this file): one script per script or director the
ops name, lasting the first such op's :duration, its gesture chosen by the
op's name; one looping script per autoscript procedure."
  (let* ((op-scripts (spec-op-scripts spec))
         (forms (append (loop for (name . op) in op-scripts
                              collect (placeholder-script-form name (op-duration op) skeleton
                                                               :gesture-name (op-name op)))
                        (loop for name in (spec-script-names spec)
                              unless (assoc name op-scripts :test #'string-equal)
                                collect (placeholder-loop-form name skeleton)))))
    (parse-script-library-forms forms)))

;;;# Filling a library's gaps

(defun spec-director-names (spec)
  "The directors SPEC's ops run, each once: no placeholder script stands in for one."
  (remove-duplicates (loop for op in (spec-ops spec)
                           when (eq (op-kind op) :director) collect (op-director op))
                     :test #'string-equal :from-end t))

(defun missing-placeholder-names (library spec)
  "The scripts SPEC's ops and autoscripts play that LIBRARY lacks and a
placeholder can stand in for (every one but a director)."
  (let ((directors (spec-director-names spec)))
    (remove-if (lambda (name) (member name directors :test #'string-equal))
               (missing-scripts library (spec-script-names spec)))))

(defun library-with-placeholders (library spec skeleton)
  "LIBRARY when it has every script SPEC plays; else a copy of it adding, for
each script it lacks, the placeholder MAKE-PLACEHOLDER-LIBRARY makes on
SKELETON, so an author who has written 4 of 12 ops' scripts sees those 4 and
a gesture for the rest (CHECK warns of them).  A missing director stays
missing: CHECK-SPEC-SCRIPTS refuses it.  LIBRARY itself is never changed."
  (let ((missing (missing-placeholder-names library spec)))
    (if (null missing)
        library
        (let ((placeholders (make-placeholder-library spec skeleton))
              (copy (%make-script-library (script-library-source library))))
          (maphash (lambda (name script) (setf (gethash name (script-library-scripts copy)) script))
                   (script-library-scripts library))
          (maphash (lambda (name director) (setf (gethash name (script-library-directors copy)) director))
                   (script-library-directors library))
          (setf (script-library-objects copy) (script-library-objects library)
                (script-library-poses copy) (script-library-poses library)
                (script-library-pose-whens copy) (script-library-pose-whens library)
                (script-library-places copy) (script-library-places library)
                (script-library-skeleton copy) (script-library-skeleton library)
                (script-library-definitions copy)
                (append (script-library-definitions library)
                        (loop for name in missing
                              for script = (find-script placeholders name)
                              do (setf (gethash (string name) (script-library-scripts copy)) script)
                              collect script)))
          copy))))
