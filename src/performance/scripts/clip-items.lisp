;;;; clip-items.lisp -- the :clip script item: an animation clip of the
;;;; character's imported model, played by the :clip motor function
;;;; (src/rig/clip-driver.lisp), so it requests channels at a priority like
;;;; every motor item and arbitration, cuts and policies treat it alike.
;;;; With :from "FILE" (a BVH or any model Assimp reads, relative to the
;;;; library file like a :sound) the clip is the file's, retargeted onto the
;;;; character whatever its skeleton (src/rig/retarget.lisp); the file is
;;;; read and the clip looked up when the library is read, so a missing or
;;;; unreadable file or an unknown clip is an error at the item's line.

(in-package #:player.performance)

(defparameter *clip-item-options* '(:from :loop :speed :fade :weight :joints :root :priority :for)
  "The options a :clip item takes besides its clip's name.")

(defun clip-item-frame (item name options)
  "The :clip motor frame of ITEM playing the clip NAME with OPTIONS (all but :for)."
  (unless (or (stringp name) (and name (symbolp name) (not (keywordp name))))
    (script-fail item ":clip takes a clip's name (a symbol or string), not ~A" (argument-value-text name)))
  (append (list :clip :name (if (stringp name) name (string-downcase (symbol-name name))))
          (loop for (key value) on options by #'cddr
                unless (eq key :for)
                  append (list key value))))

(defun clip-file-path (item name from)
  "The truename (a string) of the file FROM that ITEM's clip NAME comes from,
resolved against the library's directory, once the file is read and found to
have the clip; a SCRIPT-ERROR at ITEM otherwise."
  (unless (and (stringp from) (plusp (length from)))
    (script-fail item ":from takes a BVH or model file's name in a string, not ~A" (argument-value-text from)))
  (handler-case
      (let ((path (merge-pathnames from (or *library-directory* *default-pathname-defaults*))))
        (clip-file-clip path name)
        (nth-value 1 (clip-file-source path)))
    (player-error (condition)
      (script-fail item "~A" condition))))

(defun parse-clip-item (item at arguments)
  "(:at T :clip NAME [:from \"FILE\"] [:loop B] [:speed S] [:fade SECONDS] [:weight W]
[:joints (JOINT-OR-ROLE ...)] [:root :in-place|:move] [:priority P] [:for D]): a
motor item calling :clip, its :from file resolved to its truename."
  (multiple-value-bind (parts options until) (item-parts item arguments 1 *clip-item-options*)
    (let ((frame (clip-item-frame item (first parts) options)))
      (when (getf options :from)
        ;; A fresh frame: the options may share structure with the item as written.
        (setf frame (list* :clip :from (clip-file-path item (getf (rest frame) :name) (getf options :from))
                           (alexandria:remove-from-plist (rest frame) :from))))
      (when (and (getf options :weight) (not (and (realp (getf options :weight)) (<= 0 (getf options :weight) 1))))
        (script-fail item ":weight is a number from 0 to 1, not ~A" (argument-value-text (getf options :weight))))
      (make-motor-item :at at :until until :form item :frame frame
                       :call (handler-case (parse-motor-frame frame)
                               (spec-error (error)
                                 (script-fail item "~A" (spec-error-message error))))))))

(defun clip-item-length (library item)
  "How long ITEM, a motor item, plays its clip once at its speed, when it calls
a clip (of LIBRARY's model, or :from a file) without :loop; else NIL."
  (let ((call (motor-item-call item)))
    (when (and (eq (motor-call-function call) :clip)
               (not (motor-arg call :loop)))
      (let ((clip (cond ((motor-arg call :from)
                         (ignore-errors (clip-file-clip (motor-arg call :from) (motor-arg call :name))))
                        ((script-library-skeleton library)
                         (find-clip (skeleton-rig (script-library-skeleton library)) (motor-arg call :name))))))
        (and clip (/ (clip-duration clip) (float (motor-arg call :speed) 1d0)))))))

(defun check-clip-items (library script)
  "Signal a SCRIPT-ERROR for a :clip item of SCRIPT, not :from a file, naming a clip LIBRARY's model lacks."
  (let ((skeleton (script-library-skeleton library)))
    (dolist (item (script-items script))
      ;; A clip :from a file was found when the item was read.
      (when (and (motor-item-p item) (eq (motor-call-function (motor-item-call item)) :clip)
                 (not (motor-arg (motor-item-call item) :from)))
        (let ((name (motor-arg (motor-item-call item) :name)))
          (cond ((null skeleton)
                 (script-fail (script-item-form item) "a :clip item needs the library's (model \"FILE\" ...) form; there is none"))
                ((not (find-clip (skeleton-rig skeleton) name))
                 (script-fail (script-item-form item) "~A has no clip ~A (clips: ~{~A~^ ~})"
                              (file-namestring (model-file (rig-model (skeleton-rig skeleton))))
                              (lisp-text name) (rig-clip-names (skeleton-rig skeleton))))))))))
