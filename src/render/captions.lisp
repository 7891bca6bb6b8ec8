;;;; captions.lisp -- a line of text drawn over a finished frame: light dots of
;;;; the caption font (caption-font.lisp) on a dark box at the bottom centre.
;;;; Every dot run is a scissored glClear, so no shader, texture or vertex
;;;; buffer is needed and the same code draws offscreen and in the window; a
;;;; caption of twenty letters is a few hundred small clears.

(in-package #:player.render)

(defparameter *caption-box-colour* '(0.12 0.12 0.15) "The caption box's colour (R G B from 0 to 1).")
(defparameter *caption-text-colour* '(0.98 0.97 0.90) "The caption text's colour (R G B from 0 to 1).")

(defstruct (caption-layout (:constructor make-caption-layout (text scale left top box)))
  "Where a caption goes in a frame: TEXT as drawn (cut to fit), SCALE pixels a
dot, the text's LEFT and TOP pixel, and BOX (X Y WIDTH HEIGHT) behind it;
rows count from the top."
  text scale left top box)

(defun layout-caption (text width height)
  "The CAPTION-LAYOUT of TEXT at the bottom centre of a WIDTH x HEIGHT frame:
dots of about a 160th of the height, smaller (down to one pixel) when TEXT is
wide, and TEXT cut short when even that does not fit.  NIL when the frame is
too small for a single glyph."
  (let* ((scale (max 1 (floor height 160)))
         (usable (- width 4)))
    (loop while (and (> scale 1) (> (* scale (+ 4 (caption-text-width text))) usable))
          do (decf scale))
    (let* ((fit (floor (- (floor usable scale) 4 -1) +glyph-advance+))
           (text (if (> (length text) fit) (subseq text 0 (max 0 fit)) text))
           (text-width (* scale (caption-text-width text)))
           (text-height (* scale +glyph-rows+))
           (pad (* 2 scale))
           (box-width (+ text-width (* 2 pad)))
           (box-height (+ text-height (* 2 pad)))
           (box-left (floor (- width box-width) 2))
           (box-top (- height box-height (* 3 scale))))
      (when (and (plusp (length text)) (<= box-width width) (>= box-top 0))
        (make-caption-layout text scale (+ box-left pad) (+ box-top pad)
                             (list box-left box-top box-width box-height))))))

(defun clear-rectangle (left top width height frame-height colour)
  "Fill the rectangle at LEFT, TOP (rows from the top) of the current
framebuffer, FRAME-HEIGHT tall, with COLOUR; scissor testing must be on."
  (gl-scissor left (- frame-height top height) width height)
  (destructuring-bind (red green blue) colour
    (gl-clear-color red green blue 1))
  (gl-clear +gl-color-buffer-bit+))

(defun draw-caption (text width height)
  "Draw TEXT as a caption over the WIDTH x HEIGHT frame in the default
framebuffer (see LAYOUT-CAPTION).  Returns the layout, or NIL when nothing fits."
  (let ((layout (layout-caption text width height)))
    (when layout
      (gl-bind-framebuffer +gl-framebuffer+ 0)
      (gl-viewport 0 0 width height)
      (gl-enable +gl-scissor-test+)
      (destructuring-bind (x y w h) (caption-layout-box layout)
        (clear-rectangle x y w h height *caption-box-colour*))
      (let ((scale (caption-layout-scale layout)))
        (loop for (column row length) in (caption-text-runs (caption-layout-text layout))
              do (clear-rectangle (+ (caption-layout-left layout) (* scale column))
                                  (+ (caption-layout-top layout) (* scale row))
                                  (* scale length) scale height *caption-text-colour*)))
      (gl-disable +gl-scissor-test+)
      layout)))
