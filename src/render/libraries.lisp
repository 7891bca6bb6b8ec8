;;;; libraries.lisp -- the renderer's conditions and its two foreign libraries.
;;;; libOSMesa renders offscreen (frames, tests, CI); libglfw opens a window.
;;;; Both are loaded on first use, not when Player loads, so a machine without
;;;; them can still plan, simulate and write BVH files.

(in-package #:player.render)

(define-condition render-error (player-error-with-message)
  ()
  (:documentation "The renderer failed: a library is missing, a GL context could
not be made, a shader did not compile, or a frame could not be written."))

(defun render-fail (control &rest arguments)
  "Signal a RENDER-ERROR whose message is CONTROL applied to ARGUMENTS."
  (error 'render-error :message (apply #'format nil control arguments)))

(defmacro with-gl-traps-masked (&body body)
  "Run BODY with SBCL's floating-point traps masked.
Mesa (and the LLVM code llvmpipe generates) computes with NaNs and infinities
on purpose; unmasked, SBCL would turn those into Lisp errors inside C frames."
  `(sb-int:with-float-traps-masked (:invalid :divide-by-zero :overflow :inexact)
     ,@body))

;;; ---------------------------------------------------------------------------
;;; Loading

(defvar *osmesa-library-names* '("libOSMesa.so.8" "libOSMesa.so.6")
  "Sonames tried, in order, for OSMesa; .so.8 is Mesa's gallium OSMesa.")

(defvar *glfw-library-names* '("libglfw.so.3")
  "Sonames tried, in order, for GLFW 3.")

(defvar *loaded-render-libraries* '()
  "Alist from a list of sonames to the CFFI library loaded from one of them.
Keyed by the whole list, so rebinding a names variable forces a fresh attempt.")

(defun try-load-library (soname)
  "The CFFI foreign library for SONAME, or NIL when the dynamic linker can't find it."
  (handler-case (cffi:load-foreign-library soname)
    (cffi:load-foreign-library-error () nil)))

(defun load-render-library (sonames label package)
  "Load the first of SONAMES that the dynamic linker finds, once per list.
Signals a RENDER-ERROR naming LABEL and the Debian PACKAGE when none is found."
  (or (cdr (assoc sonames *loaded-render-libraries* :test #'equal))
      (let ((library (some #'try-load-library sonames)))
        (unless library
          (render-fail "~A not found: install the Debian package ~A (tried ~{~A~^, ~})"
                       label package sonames))
        (push (cons sonames library) *loaded-render-libraries*)
        library)))

(defun load-osmesa-library ()
  "Make sure OSMesa is loaded; signals RENDER-ERROR when libosmesa6 is missing."
  (load-render-library *osmesa-library-names* "libOSMesa" "libosmesa6"))

(defun load-glfw-library ()
  "Make sure GLFW 3 is loaded; signals RENDER-ERROR when libglfw3 is missing."
  (load-render-library *glfw-library-names* "libglfw" "libglfw3"))

;;; ---------------------------------------------------------------------------
;;; GL entry-point getters: each context type hands LOAD-GL-FUNCTIONS one of these.

(defun glfw-proc-address (name)
  "The address of GL function NAME in the current GLFW context (a null pointer if absent)."
  (check-argument 'glfw-proc-address 'name name #'stringp "a GL function's C name (a string)")
  (with-gl-traps-masked
    (cffi:foreign-funcall "glfwGetProcAddress" :string name :pointer)))
