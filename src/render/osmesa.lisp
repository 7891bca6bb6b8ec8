;;;; osmesa.lisp -- offscreen GL contexts drawing into memory Lisp owns.
;;;; OSMesa with llvmpipe needs no display or GPU, so frames render the same
;;;; on a laptop, a headless server and CI.

(in-package #:player.render)

;;; OSMesa's own enums, from GL/osmesa.h (Mesa 11.2 and later).
(defconstant +osmesa-y-up+ #x11 "OSMESA_Y_UP: OSMesaPixelStore's row-order switch.")
(defconstant +osmesa-format+ #x22 "OSMESA_FORMAT attribute.")
(defconstant +osmesa-depth-bits+ #x30 "OSMESA_DEPTH_BITS attribute.")
(defconstant +osmesa-stencil-bits+ #x31 "OSMESA_STENCIL_BITS attribute.")
(defconstant +osmesa-profile+ #x33 "OSMESA_PROFILE attribute.")
(defconstant +osmesa-core-profile+ #x34 "OSMESA_CORE_PROFILE, a value of OSMESA_PROFILE.")
(defconstant +osmesa-compat-profile+ #x35 "OSMESA_COMPAT_PROFILE, a value of OSMESA_PROFILE.")
(defconstant +osmesa-context-major-version+ #x36 "OSMESA_CONTEXT_MAJOR_VERSION attribute.")
(defconstant +osmesa-context-minor-version+ #x37 "OSMESA_CONTEXT_MINOR_VERSION attribute.")

(defstruct (offscreen-context (:constructor %make-offscreen-context))
  "An OSMesa context and the RGBA byte buffer it renders into.  BUFFER holds
WIDTH*HEIGHT*4 foreign bytes, rows top-down (OSMESA_Y_UP is 0).  PROFILE is what
OSMesa granted: a 3.3+ :core or :compat profile, or :legacy for whatever
OSMesaCreateContextExt gives."
  (handle (cffi:null-pointer) :type cffi:foreign-pointer)
  (buffer (cffi:null-pointer) :type cffi:foreign-pointer)
  (width 1 :type (integer 1))
  (height 1 :type (integer 1))
  (profile :core :type (member :core :compat :legacy)))

(defun osmesa-proc-address (name)
  "The address of GL function NAME as OSMesa resolves it (a null pointer if absent)."
  (check-argument 'osmesa-proc-address 'name name #'stringp "a GL function's C name (a string)")
  (with-gl-traps-masked
    (cffi:foreign-funcall "OSMesaGetProcAddress" :string name :pointer)))

;;; ---------------------------------------------------------------------------
;;; Creation

(defun osmesa-context-with-attributes (profile major minor depth-bits stencil-bits)
  "A new OSMesaContext for PROFILE (:core or :compat) at GL MAJOR.MINOR or later,
or a null pointer when OSMesa can't provide it."
  (let ((attributes (list +osmesa-format+ +gl-rgba+
                          +osmesa-depth-bits+ depth-bits
                          +osmesa-stencil-bits+ stencil-bits
                          +osmesa-profile+ (ecase profile
                                             (:core +osmesa-core-profile+)
                                             (:compat +osmesa-compat-profile+))
                          +osmesa-context-major-version+ major
                          +osmesa-context-minor-version+ minor
                          0)))
    (cffi:with-foreign-object (list :int (length attributes))
      (loop for value in attributes
            for i from 0
            do (setf (cffi:mem-aref list :int i) value))
      (with-gl-traps-masked
        (cffi:foreign-funcall "OSMesaCreateContextAttribs"
                              :pointer list :pointer (cffi:null-pointer) :pointer)))))

(defun osmesa-context-legacy (depth-bits stencil-bits)
  "A new OSMesaContext from OSMesaCreateContextExt (any GL version), or a null pointer."
  (with-gl-traps-masked
    (cffi:foreign-funcall "OSMesaCreateContextExt"
                          :uint32 +gl-rgba+ :int depth-bits :int stencil-bits :int 0
                          :pointer (cffi:null-pointer) :pointer)))

(defun create-osmesa-context (profile &key (major 3) (minor 3) (depth-bits 24) (stencil-bits 8))
  "A new OSMesaContext and the profile granted, trying PROFILE, then the other
profile, then OSMesaCreateContextExt (old Mesa has no OSMesaCreateContextAttribs).
Signals a RENDER-ERROR when every attempt fails."
  (load-osmesa-library)
  (let ((attribs-p (cffi:foreign-symbol-pointer "OSMesaCreateContextAttribs")))
    (dolist (try (if (eq profile :compat) '(:compat :core) '(:core :compat)))
      (let ((handle (and attribs-p
                         (osmesa-context-with-attributes try major minor depth-bits stencil-bits))))
        (when (and handle (not (cffi:null-pointer-p handle)))
          (return-from create-osmesa-context (values handle try))))))
  (let ((handle (osmesa-context-legacy depth-bits stencil-bits)))
    (when (cffi:null-pointer-p handle)
      (render-fail "OSMesa could not create a GL context (GL ~D.~D with ~D depth bits)"
                   major minor depth-bits))
    (values handle :legacy)))

(defun make-offscreen-context (width height &key (profile :core))
  "A new offscreen context of WIDTH x HEIGHT pixels, current on this thread, with
the GL functions loaded.  PROFILE (:core or :compat) is the one tried first.
Signals a RENDER-ERROR when OSMesa is missing or refuses the size.  Free it with
DESTROY-OFFSCREEN-CONTEXT, or use WITH-OFFSCREEN-CONTEXT."
  (unless (and (typep width '(integer 1)) (typep height '(integer 1)))
    (render-fail "an offscreen frame must be at least 1x1 pixels, not ~Sx~S" width height))
  (multiple-value-bind (handle granted) (create-osmesa-context profile)
    (let ((context (%make-offscreen-context
                    :handle handle :width width :height height :profile granted
                    :buffer (cffi:foreign-alloc :uint8 :count (* width height 4)
                                                       :initial-element 0))))
      (let ((made nil))
        (unwind-protect (setf made (make-offscreen-context-current context))
          (unless made (destroy-offscreen-context context))))
      context)))

(defun make-offscreen-context-current (context)
  "Bind CONTEXT's buffer, make it current, ask for top-down rows, load GL functions."
  (let ((width (offscreen-context-width context))
        (height (offscreen-context-height context)))
    (with-gl-traps-masked
      (when (zerop (cffi:foreign-funcall "OSMesaMakeCurrent"
                                         :pointer (offscreen-context-handle context)
                                         :pointer (offscreen-context-buffer context)
                                         :uint32 +gl-unsigned-byte+
                                         :int width :int height :uint8))
        (render-fail "OSMesa refused a ~Dx~D frame (too large?)" width height))
      ;; Row 0 of the buffer is then the top of the image, as PNG wants it.
      (cffi:foreign-funcall "OSMesaPixelStore" :int +osmesa-y-up+ :int 0 :void))
    (load-gl-functions #'osmesa-proc-address)
    (gl-viewport 0 0 width height)
    context))

(defun destroy-offscreen-context (context)
  "Release CONTEXT's OSMesa context and buffer; safe to call twice."
  (with-gl-traps-masked
    (unless (cffi:null-pointer-p (offscreen-context-handle context))
      ;; Unbind first so OSMesa never holds a pointer to the buffer freed below.
      (cffi:foreign-funcall "OSMesaMakeCurrent" :pointer (cffi:null-pointer)
                            :pointer (cffi:null-pointer) :uint32 0 :int 0 :int 0 :uint8)
      (cffi:foreign-funcall "OSMesaDestroyContext"
                            :pointer (offscreen-context-handle context) :void)
      (setf (offscreen-context-handle context) (cffi:null-pointer))))
  (unless (cffi:null-pointer-p (offscreen-context-buffer context))
    (cffi:foreign-free (offscreen-context-buffer context))
    (setf (offscreen-context-buffer context) (cffi:null-pointer)))
  nil)

(defvar *offscreen-context* nil
  "The offscreen context WITH-OFFSCREEN-CONTEXT made current, or NIL.")

(defun call-with-offscreen-context (function width height &rest options)
  "Call FUNCTION with a fresh current offscreen context of WIDTH x HEIGHT, made
with OPTIONS (see MAKE-OFFSCREEN-CONTEXT), and destroy the context afterwards.
An enclosing offscreen context is made current again on the way out."
  (let* ((outer *offscreen-context*)
         (*gl-entry-points* *gl-entry-points*)
         (*offscreen-context* (apply #'make-offscreen-context width height options)))
    (unwind-protect (funcall function *offscreen-context*)
      (destroy-offscreen-context *offscreen-context*)
      (when outer
        (make-offscreen-context-current outer)))))

(defmacro with-offscreen-context (((var) width height &rest options) &body body)
  "Run BODY with VAR bound to a current WIDTH x HEIGHT offscreen context whose GL
functions are loaded; OPTIONS as for MAKE-OFFSCREEN-CONTEXT (:profile :compat).
Signals a RENDER-ERROR when OSMesa is missing or can't make the context."
  `(call-with-offscreen-context (lambda (,var) (declare (ignorable ,var)) ,@body)
                                ,width ,height ,@options))

;;; ---------------------------------------------------------------------------
;;; Reading the buffer directly

(defun offscreen-context-pixels (context)
  "A copy of CONTEXT's RGBA buffer, rows top-down, after GL has finished drawing.
Faster than READ-FRAME-PIXELS (no flip) but shows only the default framebuffer."
  (gl-finish)
  (let* ((size (* 4 (offscreen-context-width context) (offscreen-context-height context)))
         (pixels (make-array size :element-type '(unsigned-byte 8))))
    (cffi:with-pointer-to-vector-data (destination pixels)
      (cffi:foreign-funcall "memcpy" :pointer destination
                            :pointer (offscreen-context-buffer context) :size size :pointer))
    pixels))
