;;;; captions.lisp -- lines of text a performance shows over its frames for a
;;;; while (a placeholder's op name while the op plays).  PERFORMANCE-FRAME
;;;; puts the caption of the frame's time on the scene it returns, where the
;;;; renderer draws it; like the rest of a performance, what shows at a time
;;;; depends only on that time.

(in-package #:player.performance)

(defstruct (caption (:constructor make-caption (text start end)))
  "TEXT shown from START until END (seconds; NIL: for ever)."
  (text "" :type string :read-only t)
  (start 0d0 :type double-float :read-only t)
  (end nil :type (or null double-float)))

(defun add-caption (performance text start end)
  "Show TEXT over PERFORMANCE's frames from START until END (NIL: for ever);
returns the CAPTION, whose end CUT-CAPTION may bring forward."
  (let ((caption (make-caption text (float start 1d0) (and end (float end 1d0)))))
    (push caption (performance-captions performance))
    caption))

(defun cut-caption (caption time)
  "End CAPTION at TIME if it would show longer."
  (let ((time (float time 1d0)))
    (when (or (null (caption-end caption)) (> (caption-end caption) time))
      (setf (caption-end caption) (max (caption-start caption) time)))
    caption))

(defun caption-at (performance time)
  "The text of PERFORMANCE's newest caption showing at TIME, or NIL."
  (let ((caption (find-if (lambda (c) (and (<= (caption-start c) time)
                                           (or (null (caption-end c)) (< time (caption-end c)))))
                          (performance-captions performance))))
    (and caption (caption-text caption))))
