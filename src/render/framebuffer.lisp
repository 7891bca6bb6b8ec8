;;;; framebuffer.lisp -- multisampled render targets and reading frames back.
;;;; OSMesa's own framebuffer has one sample per pixel, so for smooth edges a
;;;; frame is drawn into a 4x multisampled framebuffer object and blitted
;;;; (which averages the samples) into the default framebuffer, where
;;;; READ-FRAME-PIXELS and the window's swap find it.

(in-package #:player.render)

(defstruct (msaa-target (:constructor %make-msaa-target))
  "A multisampled framebuffer object: COLOR is its RGBA8 renderbuffer, DEPTH its
DEPTH24_STENCIL8 one, SAMPLES the samples per pixel actually allocated."
  (framebuffer 0 :type (unsigned-byte 32))
  (color 0 :type (unsigned-byte 32))
  (depth 0 :type (unsigned-byte 32))
  (width 1 :type (integer 1))
  (height 1 :type (integer 1))
  (samples 0 :type (integer 0)))

(defun multisample-renderbuffer (samples format width height)
  "A new renderbuffer of FORMAT with SAMPLES per pixel, WIDTH x HEIGHT."
  (let ((renderbuffer (gl-gen-object #'gl-gen-renderbuffers)))
    (gl-bind-renderbuffer +gl-renderbuffer+ renderbuffer)
    (gl-renderbuffer-storage-multisample +gl-renderbuffer+ samples format width height)
    renderbuffer))

(defun make-msaa-target (width height &optional (samples 4))
  "A WIDTH x HEIGHT framebuffer with SAMPLES per pixel (clamped to GL_MAX_SAMPLES),
bound for drawing with the viewport set.  Signals a RENDER-ERROR when GL calls
it incomplete.  Draw, then RESOLVE-MSAA-TARGET; free with DELETE-MSAA-TARGET."
  (check-real 'make-msaa-target 'width width :integer t :minimum 1 :maximum 16384)
  (check-real 'make-msaa-target 'height height :integer t :minimum 1 :maximum 16384)
  (check-real 'make-msaa-target 'samples samples :integer t :minimum 0 :maximum 64)
  (let* ((samples (max 0 (min samples (gl-get-integer +gl-max-samples+))))
         (target (%make-msaa-target
                  :width width :height height :samples samples
                  :framebuffer (gl-gen-object #'gl-gen-framebuffers)
                  :color (multisample-renderbuffer samples +gl-rgba8+ width height)
                  :depth (multisample-renderbuffer samples +gl-depth24-stencil8+ width height))))
    (gl-bind-framebuffer +gl-framebuffer+ (msaa-target-framebuffer target))
    (gl-framebuffer-renderbuffer +gl-framebuffer+ +gl-color-attachment0+
                                 +gl-renderbuffer+ (msaa-target-color target))
    (gl-framebuffer-renderbuffer +gl-framebuffer+ +gl-depth-stencil-attachment+
                                 +gl-renderbuffer+ (msaa-target-depth target))
    (let ((status (gl-check-framebuffer-status +gl-framebuffer+)))
      (unless (= status +gl-framebuffer-complete+)
        (delete-msaa-target target)
        (render-fail "a ~Dx~D framebuffer with ~D samples is incomplete (status #x~X)"
                     width height samples status)))
    (bind-msaa-target target)))

(defun bind-msaa-target (target)
  "Make TARGET the framebuffer drawn into, with a viewport covering it; returns TARGET."
  (check-argument 'bind-msaa-target 'target target #'msaa-target-p "an MSAA target (from make-msaa-target)")
  (gl-bind-framebuffer +gl-framebuffer+ (msaa-target-framebuffer target))
  (gl-viewport 0 0 (msaa-target-width target) (msaa-target-height target))
  target)

(defun resolve-msaa-target (target)
  "Average TARGET's samples into the default framebuffer and bind that, so
READ-FRAME-PIXELS (or a buffer swap) sees the smoothed frame."
  (check-argument 'resolve-msaa-target 'target target #'msaa-target-p "an MSAA target (from make-msaa-target)")
  (let ((width (msaa-target-width target))
        (height (msaa-target-height target)))
    (gl-bind-framebuffer +gl-read-framebuffer+ (msaa-target-framebuffer target))
    (gl-bind-framebuffer +gl-draw-framebuffer+ 0)
    ;; A multisample resolve must copy 1:1, so NEAREST loses nothing here.
    (gl-blit-framebuffer 0 0 width height 0 0 width height
                         +gl-color-buffer-bit+ +gl-nearest+)
    (gl-bind-framebuffer +gl-framebuffer+ 0)
    target))

(defun delete-msaa-target (target)
  "Free TARGET's framebuffer and renderbuffers and bind the default framebuffer."
  (check-argument 'delete-msaa-target 'target target #'msaa-target-p "an MSAA target (from make-msaa-target)")
  (gl-bind-framebuffer +gl-framebuffer+ 0)
  (gl-delete-object #'gl-delete-framebuffers (msaa-target-framebuffer target))
  (gl-delete-object #'gl-delete-renderbuffers (msaa-target-color target))
  (gl-delete-object #'gl-delete-renderbuffers (msaa-target-depth target))
  (setf (msaa-target-framebuffer target) 0 (msaa-target-color target) 0
        (msaa-target-depth target) 0)
  nil)

;;; ---------------------------------------------------------------------------
;;; Reading frames

(defun flip-rows (pixels row-bytes rows)
  "Reverse the order of the ROWS rows of ROW-BYTES each in PIXELS, in place."
  (declare (type (simple-array (unsigned-byte 8) (*)) pixels)
           (type (integer 0 #.array-dimension-limit) row-bytes rows)
           (optimize (speed 2) (safety 1)))
  (let ((spare (make-array row-bytes :element-type '(unsigned-byte 8))))
    (loop for top of-type (integer 0 #.array-dimension-limit) from 0 by row-bytes
          for bottom of-type (integer 0 #.array-dimension-limit)
            downfrom (* (max 0 (1- rows)) row-bytes) by row-bytes
          while (< top bottom)
          do (replace spare pixels :start2 top)
             (replace pixels pixels :start1 top :start2 bottom :end2 (+ bottom row-bytes))
             (replace pixels spare :start1 bottom)))
  pixels)

(defun read-frame-pixels (width height &key (channels 4))
  "The WIDTH x HEIGHT pixels of the framebuffer bound for reading, as a vector of
(unsigned-byte 8), rows top-down, CHANNELS (4 for RGBA, 3 for RGB) per pixel --
the layout WRITE-PNG takes.  GL reads bottom-up, so the rows are flipped here."
  (check-real 'read-frame-pixels 'width width :integer t :minimum 1 :maximum 16384)
  (check-real 'read-frame-pixels 'height height :integer t :minimum 1 :maximum 16384)
  (check-argument 'read-frame-pixels :channels channels (lambda (x) (member x '(3 4))) "3 (RGB) or 4 (RGBA)")
  (let ((pixels (make-array (* width height channels) :element-type '(unsigned-byte 8))))
    ;; Rows of RGB bytes need not be 4-aligned; tell GL to pack them tightly.
    (gl-pixel-storei +gl-pack-alignment+ 1)
    (cffi:with-pointer-to-vector-data (pointer pixels)
      (gl-read-pixels 0 0 width height (ecase channels (4 +gl-rgba+) (3 +gl-rgb+))
                      +gl-unsigned-byte+ pointer))
    (flip-rows pixels (* width channels) height)))
