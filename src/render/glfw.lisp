;;;; glfw.lisp -- a window with a GL context through GLFW 3.3, bound with CFFI.
;;;; Two layers: raw %GLFW- bindings (float traps masked around each call),
;;;; then Lisp functions that check results and signal RENDER-ERRORs.  Input
;;;; arrives through C callbacks that only record what happened; GLFW-POLL-INPUT
;;;; returns those records as a list, so no Lisp decision runs inside a C frame.

(in-package #:player.render)

;;;# Constants, from GLFW/glfw3.h (3.3)

(define-gl-constants
  +glfw-true+ 1  +glfw-false+ 0
  ;; key and button actions
  +glfw-release+ 0  +glfw-press+ 1  +glfw-repeat+ 2
  ;; keys the viewer reads by key code (event keys are read as characters)
  +glfw-key-space+ 32  +glfw-key-escape+ 256  +glfw-key-enter+ 257
  +glfw-key-right+ 262  +glfw-key-left+ 263  +glfw-key-down+ 264  +glfw-key-up+ 265
  +glfw-key-home+ 268
  +glfw-mouse-button-left+ 0  +glfw-mouse-button-right+ 1  +glfw-mouse-button-middle+ 2
  ;; window hints and their values
  +glfw-resizable+ #x00020003  +glfw-visible+ #x00020004  +glfw-samples+ #x0002100D
  +glfw-doublebuffer+ #x00021010
  +glfw-context-version-major+ #x00022002  +glfw-context-version-minor+ #x00022003
  +glfw-opengl-profile+ #x00022008  +glfw-opengl-core-profile+ #x00032001)

;;;# Raw bindings

(defmacro define-glfw-function (name c-name return-type &rest parameters)
  "Define NAME as a call of GLFW function C-NAME with float traps masked.
PARAMETERS are (argument cffi-type) lists.  The library must be loaded first
(LOAD-GLFW-LIBRARY); GLFW-INITIALIZE does it."
  `(defun ,name ,(mapcar #'first parameters)
     ,(format nil "Call ~A." c-name)
     (with-gl-traps-masked
       (cffi:foreign-funcall ,c-name
                             ,@(loop for (argument type) in parameters
                                     append (list type (foreign-argument-form argument type)))
                             ,return-type))))

(define-glfw-function %glfw-init "glfwInit" :int)
(define-glfw-function %glfw-terminate "glfwTerminate" :void)
(define-glfw-function %glfw-set-error-callback "glfwSetErrorCallback" :pointer (callback :pointer))
(define-glfw-function %glfw-default-window-hints "glfwDefaultWindowHints" :void)
(define-glfw-function %glfw-window-hint "glfwWindowHint" :void (hint :int) (value :int))
(define-glfw-function %glfw-create-window "glfwCreateWindow" :pointer
  (width :int) (height :int) (title :string) (monitor :pointer) (share :pointer))
(define-glfw-function %glfw-destroy-window "glfwDestroyWindow" :void (window :pointer))
(define-glfw-function %glfw-make-context-current "glfwMakeContextCurrent" :void (window :pointer))
(define-glfw-function %glfw-swap-buffers "glfwSwapBuffers" :void (window :pointer))
(define-glfw-function %glfw-swap-interval "glfwSwapInterval" :void (interval :int))
(define-glfw-function %glfw-poll-events "glfwPollEvents" :void)
(define-glfw-function %glfw-window-should-close "glfwWindowShouldClose" :int (window :pointer))
(define-glfw-function %glfw-set-window-should-close "glfwSetWindowShouldClose" :void
  (window :pointer) (value :int))
(define-glfw-function %glfw-set-window-title "glfwSetWindowTitle" :void (window :pointer) (title :string))
(define-glfw-function %glfw-get-framebuffer-size "glfwGetFramebufferSize" :void
  (window :pointer) (width :pointer) (height :pointer))
(define-glfw-function %glfw-set-key-callback "glfwSetKeyCallback" :pointer (window :pointer) (callback :pointer))
(define-glfw-function %glfw-set-char-callback "glfwSetCharCallback" :pointer (window :pointer) (callback :pointer))
(define-glfw-function %glfw-set-cursor-pos-callback "glfwSetCursorPosCallback" :pointer
  (window :pointer) (callback :pointer))
(define-glfw-function %glfw-set-mouse-button-callback "glfwSetMouseButtonCallback" :pointer
  (window :pointer) (callback :pointer))
(define-glfw-function %glfw-set-scroll-callback "glfwSetScrollCallback" :pointer
  (window :pointer) (callback :pointer))
(define-glfw-function %glfw-get-time "glfwGetTime" :double)

;;;# Callbacks: they record, the Lisp side decides

(defvar *glfw-input* '()
  "Input records the callbacks collected since the last GLFW-POLL-INPUT, newest first.")

(defvar *glfw-last-error* nil
  "The last error GLFW reported, as (CODE . DESCRIPTION), or NIL.")

(cffi:defcallback glfw-error-callback :void ((code :int) (description :string))
  (setf *glfw-last-error* (cons code description)))

(cffi:defcallback glfw-key-callback :void
    ((window :pointer) (key :int) (scancode :int) (action :int) (mods :int))
  (declare (ignore window scancode))
  (push (list :key key action mods) *glfw-input*))

(cffi:defcallback glfw-char-callback :void ((window :pointer) (codepoint :uint))
  (declare (ignore window))
  (push (list :char codepoint) *glfw-input*))

(cffi:defcallback glfw-cursor-callback :void ((window :pointer) (x :double) (y :double))
  (declare (ignore window))
  (push (list :cursor x y) *glfw-input*))

(cffi:defcallback glfw-button-callback :void ((window :pointer) (button :int) (action :int) (mods :int))
  (declare (ignore window))
  (push (list :button button action mods) *glfw-input*))

(cffi:defcallback glfw-scroll-callback :void ((window :pointer) (dx :double) (dy :double))
  (declare (ignore window))
  (push (list :scroll dx dy) *glfw-input*))

;;;# The Lisp layer

(defparameter *no-display-message*
  "cannot open a window: no display (set DISPLAY or run under xvfb-run)"
  "The RENDER-ERROR message when there is no display to open a window on.")

(defun display-available-p ()
  "True when the environment names an X or Wayland display."
  (flet ((set-p (name) (let ((value (sb-ext:posix-getenv name))) (and value (string/= value "")))))
    (or (set-p "DISPLAY") (set-p "WAYLAND_DISPLAY"))))

(defun glfw-failure (doing)
  "Signal a RENDER-ERROR for a failed DOING: the no-display message when the
environment names no display, else GLFW's own description of the error."
  (if (display-available-p)
      (render-fail "cannot open a window: ~A~@[ (~A)~]" doing (cdr *glfw-last-error*))
      (render-fail "~A" *no-display-message*)))

(defun glfw-initialize ()
  "Load libglfw and initialise GLFW.  Signals a RENDER-ERROR when libglfw3 is
missing or when there is no display to connect to."
  (load-glfw-library)
  (setf *glfw-last-error* nil)
  (%glfw-set-error-callback (cffi:callback glfw-error-callback))
  (when (zerop (%glfw-init))
    (glfw-failure "GLFW could not start")))

(defun glfw-terminate ()
  "Close every window GLFW has open and release it."
  (%glfw-terminate))

(defun make-glfw-window (width height title &key (visible t) (samples 0))
  "A new WIDTH x HEIGHT window called TITLE whose GL 3.3 core context is current,
with the GL functions loaded, vsync on and the input callbacks installed.
SAMPLES is the window framebuffer's samples per pixel (GLFW_SAMPLES): 0 by
default, since the renderer antialiases its own target (FXAA or 4x MSAA) and
window samples only cost time (under llvmpipe at 640x480, 61 frames a second
with 4 against 86 with 0).  Call GLFW-INITIALIZE first.  Signals a
RENDER-ERROR when GLFW cannot make the window or its context."
  (%glfw-default-window-hints)
  (loop for (hint value) in `((,+glfw-context-version-major+ 3) (,+glfw-context-version-minor+ 3)
                              (,+glfw-opengl-profile+ ,+glfw-opengl-core-profile+)
                              (,+glfw-samples+ ,samples) (,+glfw-doublebuffer+ ,+glfw-true+)
                              (,+glfw-visible+ ,(if visible +glfw-true+ +glfw-false+)))
        do (%glfw-window-hint hint value))
  (let ((window (%glfw-create-window width height title (cffi:null-pointer) (cffi:null-pointer))))
    (when (cffi:null-pointer-p window)
      (glfw-failure (format nil "GLFW could not make a ~Dx~D window with a GL 3.3 core context"
                            width height)))
    (%glfw-make-context-current window)
    (%glfw-swap-interval 1)
    (load-gl-functions #'glfw-proc-address)
    (%glfw-set-key-callback window (cffi:callback glfw-key-callback))
    (%glfw-set-char-callback window (cffi:callback glfw-char-callback))
    (%glfw-set-cursor-pos-callback window (cffi:callback glfw-cursor-callback))
    (%glfw-set-mouse-button-callback window (cffi:callback glfw-button-callback))
    (%glfw-set-scroll-callback window (cffi:callback glfw-scroll-callback))
    window))

(defun call-with-glfw-window (function width height title &rest options)
  "Initialise GLFW, call FUNCTION with a new current window (made with WIDTH,
HEIGHT, TITLE and OPTIONS, as for MAKE-GLFW-WINDOW), then destroy the window and
terminate GLFW however FUNCTION exits.  Signals what GLFW-INITIALIZE and
MAKE-GLFW-WINDOW signal."
  (let ((*gl-entry-points* *gl-entry-points*)
        (*glfw-input* '()))
    (glfw-initialize)
    (unwind-protect
         (let ((window (apply #'make-glfw-window width height title options)))
           (unwind-protect (funcall function window)
             (%glfw-destroy-window window)))
      (glfw-terminate))))

(defmacro with-glfw-window ((var width height title &rest options) &body body)
  "Run BODY with VAR bound to a new GLFW window whose GL context is current;
see CALL-WITH-GLFW-WINDOW."
  `(call-with-glfw-window (lambda (,var) ,@body) ,width ,height ,title ,@options))

(defun glfw-poll-input ()
  "Process the window system's pending events and return the input they
carried, oldest first: (:key KEY ACTION MODS), (:char CODEPOINT), (:cursor X Y),
(:button BUTTON ACTION MODS) and (:scroll DX DY) lists, with GLFW's codes."
  (setf *glfw-input* '())
  (%glfw-poll-events)
  (prog1 (nreverse *glfw-input*)
    (setf *glfw-input* '())))

(defun glfw-window-closing-p (window)
  "True when WINDOW has been asked to close (its close button, or GLFW-CLOSE-WINDOW)."
  (/= 0 (%glfw-window-should-close window)))

(defun glfw-close-window (window)
  "Ask WINDOW to close: GLFW-WINDOW-CLOSING-P becomes true."
  (%glfw-set-window-should-close window +glfw-true+))

(defun glfw-framebuffer-size (window)
  "WINDOW's framebuffer size in pixels, as two values WIDTH and HEIGHT."
  (cffi:with-foreign-objects ((width :int) (height :int))
    (%glfw-get-framebuffer-size window width height)
    (values (cffi:mem-ref width :int) (cffi:mem-ref height :int))))

(defun glfw-set-title (window title)
  "Show TITLE, a string, in WINDOW's title bar."
  (%glfw-set-window-title window title))

(defun glfw-swap-buffers (window)
  "Show the frame drawn into WINDOW's back buffer."
  (%glfw-swap-buffers window))

(defun glfw-time ()
  "Seconds since GLFW was initialised, as a double-float."
  (%glfw-get-time))
