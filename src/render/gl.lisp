;;;; gl.lisp -- OpenGL bindings called through per-context entry points.
;;;; No GL function is linked by name: each context type (OSMesa offscreen,
;;;; GLFW window) hands LOAD-GL-FUNCTIONS a getter, the resolved pointers go
;;;; in a table, and every binding calls its pointer from that table.  So one
;;;; drawing module serves both contexts, and a call made with no context
;;;; loaded is a RENDER-ERROR instead of a jump through a null pointer.

(in-package #:player.render)

;;; ---------------------------------------------------------------------------
;;; The entry-point table

(defvar *gl-function-names* (make-array 0 :adjustable t :fill-pointer t)
  "The C name of every bound GL function, in the order they were defined.
A binding's position here is its index into *GL-ENTRY-POINTS*.")

(defvar *gl-entry-points* #()
  "Simple-vector of foreign pointers for the current context, parallel to
*GL-FUNCTION-NAMES*; a null pointer where the context lacks the function.")

(defun gl-function-index (c-name)
  "The index of GL function C-NAME in the table, registering it on first sight."
  (or (position c-name *gl-function-names* :test #'string=)
      (vector-push-extend c-name *gl-function-names*)))

(defun load-gl-functions (getter)
  "Resolve every bound GL function with GETTER, a function from a C name to a
foreign pointer, and make the result the current table.  Call it with the
context current; WITH-OFFSCREEN-CONTEXT does.  Returns the number resolved."
  (check-argument 'load-gl-functions 'getter getter
                  (lambda (x) (or (functionp x) (and (symbolp x) x (fboundp x))))
                  "a function (or a symbol naming one) from a C name to a foreign pointer")
  (let ((table (map 'simple-vector getter *gl-function-names*)))
    (setf *gl-entry-points* table)
    (count-if-not #'cffi:null-pointer-p table)))

(defun missing-gl-function (index)
  "Signal a RENDER-ERROR for the GL function at INDEX, unresolved in the current table."
  (render-fail "~A is not available: ~:[no GL context has been loaded~;the current GL context lacks it~]"
               (aref *gl-function-names* index) (plusp (length *gl-entry-points*))))

(declaim (inline gl-entry-point))
(defun gl-entry-point (index)
  "The foreign pointer of the GL function at INDEX; RENDER-ERROR when unresolved."
  (let ((table *gl-entry-points*))
    (if (< index (length table))
        (let ((pointer (svref table index)))
          (if (cffi:null-pointer-p pointer) (missing-gl-function index) pointer))
        (missing-gl-function index))))

(eval-when (:compile-toplevel :load-toplevel :execute)
  (defun foreign-argument-form (argument type)
    "ARGUMENT converted for a foreign parameter of TYPE: reals become single
floats for :float, so callers may pass 1 or 0.5d0."
    (case type
      (:float `(float ,argument 1f0))
      (t argument))))

(defmacro define-gl-function (name c-name return-type &rest parameters)
  "Define NAME as a Lisp function calling GL function C-NAME through the current
table, with float traps masked.  PARAMETERS are (argument cffi-type) lists."
  `(defun ,name ,(mapcar #'first parameters)
     ,(format nil "Call ~A in the current GL context." c-name)
     (with-gl-traps-masked
       (cffi:foreign-funcall-pointer
        (gl-entry-point (load-time-value (gl-function-index ,c-name) t))
        ()
        ,@(loop for (argument type) in parameters
                append (list type (foreign-argument-form argument type)))
        ,return-type))))

;;; ---------------------------------------------------------------------------
;;; Enums, with the names the GL headers give them.

(defmacro define-gl-constants (&rest names-and-values)
  "Define each +GL-...+ constant in NAMES-AND-VALUES with the C name as its docstring."
  `(progn
     ,@(loop for (name value) on names-and-values by #'cddr
             collect `(defconstant ,name ,value
                        ,(substitute #\_ #\- (string-upcase (string-trim "+" (string name))))))))

(define-gl-constants
  +gl-false+ 0  +gl-true+ 1  +gl-zero+ 0  +gl-one+ 1  +gl-no-error+ 0
  ;; glClear, glBlitFramebuffer masks
  +gl-depth-buffer-bit+ #x0100  +gl-stencil-buffer-bit+ #x0400  +gl-color-buffer-bit+ #x4000
  ;; glEnable capabilities and their parameters
  +gl-cull-face+ #x0B44  +gl-depth-test+ #x0B71  +gl-blend+ #x0BE2  +gl-multisample+ #x809D
  +gl-scissor-test+ #x0C11
  +gl-never+ #x0200  +gl-less+ #x0201  +gl-equal+ #x0202  +gl-lequal+ #x0203  +gl-always+ #x0207
  +gl-src-alpha+ #x0302  +gl-one-minus-src-alpha+ #x0303
  +gl-front+ #x0404  +gl-back+ #x0405  +gl-front-and-back+ #x0408  +gl-cw+ #x0900  +gl-ccw+ #x0901
  ;; primitives and data types
  +gl-points+ 0  +gl-lines+ 1  +gl-line-loop+ 2  +gl-line-strip+ 3
  +gl-triangles+ 4  +gl-triangle-strip+ 5  +gl-triangle-fan+ 6
  +gl-unsigned-byte+ #x1401  +gl-unsigned-short+ #x1403  +gl-unsigned-int+ #x1405  +gl-float+ #x1406
  ;; pixels
  +gl-rgb+ #x1907  +gl-rgba+ #x1908  +gl-rgba8+ #x8058
  +gl-unpack-alignment+ #x0CF5  +gl-pack-alignment+ #x0D05
  ;; glGetString, glGetIntegerv, glGetError
  +gl-vendor+ #x1F00  +gl-renderer+ #x1F01  +gl-version+ #x1F02
  +gl-shading-language-version+ #x8B8C  +gl-max-samples+ #x8D57  +gl-samples+ #x80A9
  +gl-invalid-enum+ #x0500  +gl-invalid-value+ #x0501  +gl-invalid-operation+ #x0502
  +gl-out-of-memory+ #x0505  +gl-invalid-framebuffer-operation+ #x0506
  ;; shaders and programs
  +gl-fragment-shader+ #x8B30  +gl-vertex-shader+ #x8B31
  +gl-compile-status+ #x8B81  +gl-link-status+ #x8B82  +gl-info-log-length+ #x8B84
  ;; buffers
  +gl-array-buffer+ #x8892  +gl-element-array-buffer+ #x8893
  +gl-stream-draw+ #x88E0  +gl-static-draw+ #x88E4  +gl-dynamic-draw+ #x88E8
  ;; framebuffers
  +gl-nearest+ #x2600  +gl-linear+ #x2601  +gl-depth-component24+ #x81A6
  +gl-depth24-stencil8+ #x88F0  +gl-depth-stencil-attachment+ #x821A
  +gl-read-framebuffer+ #x8CA8  +gl-draw-framebuffer+ #x8CA9  +gl-framebuffer-complete+ #x8CD5
  +gl-color-attachment0+ #x8CE0  +gl-depth-attachment+ #x8D00
  +gl-framebuffer+ #x8D40  +gl-renderbuffer+ #x8D41)

;;; ---------------------------------------------------------------------------
;;; Bindings.  GLenum, GLuint and GLbitfield are :uint32; GLint and GLsizei
;;; :int32; GLboolean :uint8; GLsizeiptr and GLintptr :intptr.

;; State
(define-gl-function gl-viewport "glViewport" :void (x :int32) (y :int32) (width :int32) (height :int32))
(define-gl-function gl-scissor "glScissor" :void (x :int32) (y :int32) (width :int32) (height :int32))
(define-gl-function gl-clear-color "glClearColor" :void (red :float) (green :float) (blue :float) (alpha :float))
(define-gl-function gl-clear "glClear" :void (mask :uint32))
(define-gl-function gl-enable "glEnable" :void (capability :uint32))
(define-gl-function gl-disable "glDisable" :void (capability :uint32))
(define-gl-function gl-depth-func "glDepthFunc" :void (function :uint32))
(define-gl-function gl-depth-mask "glDepthMask" :void (flag :uint8))
(define-gl-function gl-blend-func "glBlendFunc" :void (source :uint32) (destination :uint32))
(define-gl-function gl-cull-face "glCullFace" :void (mode :uint32))
(define-gl-function gl-front-face "glFrontFace" :void (mode :uint32))
(define-gl-function gl-pixel-storei "glPixelStorei" :void (pname :uint32) (param :int32))
(define-gl-function gl-get-string "glGetString" :pointer (name :uint32))
(define-gl-function gl-get-integerv "glGetIntegerv" :void (pname :uint32) (data :pointer))
(define-gl-function gl-get-error "glGetError" :uint32)
(define-gl-function gl-finish "glFinish" :void)
;; Shaders and programs
(define-gl-function gl-create-shader "glCreateShader" :uint32 (type :uint32))
(define-gl-function gl-shader-source "glShaderSource" :void
  (shader :uint32) (count :int32) (strings :pointer) (lengths :pointer))
(define-gl-function gl-compile-shader "glCompileShader" :void (shader :uint32))
(define-gl-function gl-get-shaderiv "glGetShaderiv" :void (shader :uint32) (pname :uint32) (params :pointer))
(define-gl-function gl-get-shader-info-log "glGetShaderInfoLog" :void
  (shader :uint32) (size :int32) (length :pointer) (log :pointer))
(define-gl-function gl-create-program "glCreateProgram" :uint32)
(define-gl-function gl-attach-shader "glAttachShader" :void (program :uint32) (shader :uint32))
(define-gl-function gl-link-program "glLinkProgram" :void (program :uint32))
(define-gl-function gl-get-programiv "glGetProgramiv" :void (program :uint32) (pname :uint32) (params :pointer))
(define-gl-function gl-get-program-info-log "glGetProgramInfoLog" :void
  (program :uint32) (size :int32) (length :pointer) (log :pointer))
(define-gl-function gl-use-program "glUseProgram" :void (program :uint32))
(define-gl-function gl-delete-shader "glDeleteShader" :void (shader :uint32))
(define-gl-function gl-delete-program "glDeleteProgram" :void (program :uint32))
(define-gl-function gl-get-uniform-location "glGetUniformLocation" :int32 (program :uint32) (name :string))
(define-gl-function gl-get-attrib-location "glGetAttribLocation" :int32 (program :uint32) (name :string))
(define-gl-function gl-uniform1i "glUniform1i" :void (location :int32) (x :int32))
(define-gl-function gl-uniform1f "glUniform1f" :void (location :int32) (x :float))
(define-gl-function gl-uniform3f "glUniform3f" :void (location :int32) (x :float) (y :float) (z :float))
(define-gl-function gl-uniform4f "glUniform4f" :void
  (location :int32) (x :float) (y :float) (z :float) (w :float))
(define-gl-function gl-uniform-matrix4fv "glUniformMatrix4fv" :void
  (location :int32) (count :int32) (transpose :uint8) (value :pointer))
;; Vertex arrays and buffers
(define-gl-function gl-gen-vertex-arrays "glGenVertexArrays" :void (n :int32) (arrays :pointer))
(define-gl-function gl-bind-vertex-array "glBindVertexArray" :void (array :uint32))
(define-gl-function gl-delete-vertex-arrays "glDeleteVertexArrays" :void (n :int32) (arrays :pointer))
(define-gl-function gl-gen-buffers "glGenBuffers" :void (n :int32) (buffers :pointer))
(define-gl-function gl-bind-buffer "glBindBuffer" :void (target :uint32) (buffer :uint32))
(define-gl-function gl-buffer-data "glBufferData" :void
  (target :uint32) (size :intptr) (data :pointer) (usage :uint32))
(define-gl-function gl-buffer-sub-data "glBufferSubData" :void
  (target :uint32) (offset :intptr) (size :intptr) (data :pointer))
(define-gl-function gl-delete-buffers "glDeleteBuffers" :void (n :int32) (buffers :pointer))
(define-gl-function gl-vertex-attrib-pointer "glVertexAttribPointer" :void
  (index :uint32) (size :int32) (type :uint32) (normalized :uint8) (stride :int32) (offset :pointer))
(define-gl-function gl-enable-vertex-attrib-array "glEnableVertexAttribArray" :void (index :uint32))
(define-gl-function gl-draw-arrays "glDrawArrays" :void (mode :uint32) (first :int32) (count :int32))
(define-gl-function gl-draw-elements "glDrawElements" :void
  (mode :uint32) (count :int32) (type :uint32) (offset :pointer))
(define-gl-function gl-read-pixels "glReadPixels" :void
  (x :int32) (y :int32) (width :int32) (height :int32) (format :uint32) (type :uint32) (pixels :pointer))
;; Framebuffers
(define-gl-function gl-gen-framebuffers "glGenFramebuffers" :void (n :int32) (framebuffers :pointer))
(define-gl-function gl-bind-framebuffer "glBindFramebuffer" :void (target :uint32) (framebuffer :uint32))
(define-gl-function gl-delete-framebuffers "glDeleteFramebuffers" :void (n :int32) (framebuffers :pointer))
(define-gl-function gl-framebuffer-renderbuffer "glFramebufferRenderbuffer" :void
  (target :uint32) (attachment :uint32) (renderbuffer-target :uint32) (renderbuffer :uint32))
(define-gl-function gl-check-framebuffer-status "glCheckFramebufferStatus" :uint32 (target :uint32))
(define-gl-function gl-gen-renderbuffers "glGenRenderbuffers" :void (n :int32) (renderbuffers :pointer))
(define-gl-function gl-bind-renderbuffer "glBindRenderbuffer" :void (target :uint32) (renderbuffer :uint32))
(define-gl-function gl-delete-renderbuffers "glDeleteRenderbuffers" :void (n :int32) (renderbuffers :pointer))
(define-gl-function gl-renderbuffer-storage-multisample "glRenderbufferStorageMultisample" :void
  (target :uint32) (samples :int32) (internal-format :uint32) (width :int32) (height :int32))
(define-gl-function gl-blit-framebuffer "glBlitFramebuffer" :void
  (src-x0 :int32) (src-y0 :int32) (src-x1 :int32) (src-y1 :int32)
  (dst-x0 :int32) (dst-y0 :int32) (dst-x1 :int32) (dst-y1 :int32) (mask :uint32) (filter :uint32))

;;; ---------------------------------------------------------------------------
;;; A Lisp layer over the pointer-passing calls

(defun gl-gen-object (generator)
  "One fresh object name from GENERATOR, a glGen* binding such as #'GL-GEN-BUFFERS."
  (cffi:with-foreign-object (name :uint32)
    (funcall generator 1 name)
    (cffi:mem-ref name :uint32)))

(defun gl-delete-object (deleter name)
  "Delete object NAME with DELETER, a glDelete* binding such as #'GL-DELETE-BUFFERS."
  (cffi:with-foreign-object (pointer :uint32)
    (setf (cffi:mem-ref pointer :uint32) name)
    (funcall deleter 1 pointer)))

(defun gl-get-integer (pname)
  "The single integer glGetIntegerv returns for PNAME."
  (cffi:with-foreign-object (value :int32)
    (gl-get-integerv pname value)
    (cffi:mem-ref value :int32)))

(defun gl-string (name)
  "The glGetString text for NAME (+GL-VERSION+, +GL-RENDERER+...), or NIL."
  (let ((pointer (gl-get-string name)))
    (unless (cffi:null-pointer-p pointer)
      (cffi:foreign-string-to-lisp pointer))))

(defun gl-version-string ()
  "The current context's GL_VERSION, e.g. \"4.5 (Core Profile) Mesa 22.3.6\"."
  (gl-string +gl-version+))

(defun gl-version ()
  "The current context's GL version as two values, MAJOR and MINOR."
  (let* ((text (or (gl-version-string) "0.0"))
         (dot (position #\. text)))
    (values (parse-integer text :end dot :junk-allowed t)
            (parse-integer text :start (1+ dot) :junk-allowed t))))

(defun check-gl-error (&optional doing)
  "Signal a RENDER-ERROR if GL has recorded an error; DOING names the step for the message."
  (let ((code (gl-get-error)))
    (unless (= code +gl-no-error+)
      (render-fail "GL error #x~4,'0X~@[ while ~A~]" code doing))))

;;; ---------------------------------------------------------------------------
;;; Shader programs

(defun gl-info-log (object get-iv get-log)
  "The info log of shader or program OBJECT, read with bindings GET-IV and GET-LOG."
  (let ((size (cffi:with-foreign-object (value :int32)
                (funcall get-iv object +gl-info-log-length+ value)
                (cffi:mem-ref value :int32))))
    (if (<= size 1)
        ""
        (cffi:with-foreign-pointer-as-string (log size)
          (funcall get-log object size (cffi:null-pointer) log)))))

(defun gl-status-p (object pname get-iv)
  "True when GET-IV reports PNAME (compile or link status) of OBJECT as GL_TRUE."
  (cffi:with-foreign-object (value :int32)
    (funcall get-iv object pname value)
    (= (cffi:mem-ref value :int32) +gl-true+)))

(defun compile-shader (type source)
  "A compiled shader of TYPE (+GL-VERTEX-SHADER+ or +GL-FRAGMENT-SHADER+) from SOURCE.
Signals a RENDER-ERROR carrying the compiler's info log when it fails."
  (let ((shader (gl-create-shader type)))
    (cffi:with-foreign-string (text source)
      (cffi:with-foreign-object (strings :pointer)
        (setf (cffi:mem-ref strings :pointer) text)
        (gl-shader-source shader 1 strings (cffi:null-pointer))))
    (gl-compile-shader shader)
    (unless (gl-status-p shader +gl-compile-status+ #'gl-get-shaderiv)
      (let ((log (gl-info-log shader #'gl-get-shaderiv #'gl-get-shader-info-log)))
        (gl-delete-shader shader)
        (render-fail "the ~:[fragment~;vertex~] shader did not compile: ~A"
                     (= type +gl-vertex-shader+) (string-trim '(#\Newline #\Space #\Nul) log))))
    shader))

(defun compile-shader-program (vertex-source fragment-source)
  "The id of a GL program linked from VERTEX-SOURCE and FRAGMENT-SOURCE (GLSL strings).
Signals a RENDER-ERROR with the info log when either shader or the link fails."
  (check-argument 'compile-shader-program 'vertex-source vertex-source #'stringp "GLSL source text (a string)")
  (check-argument 'compile-shader-program 'fragment-source fragment-source #'stringp "GLSL source text (a string)")
  (let* ((vertex (compile-shader +gl-vertex-shader+ vertex-source))
         (fragment (handler-bind ((render-error (lambda (e) (declare (ignore e))
                                                  (gl-delete-shader vertex))))
                     (compile-shader +gl-fragment-shader+ fragment-source)))
         (program (gl-create-program)))
    (gl-attach-shader program vertex)
    (gl-attach-shader program fragment)
    (gl-link-program program)
    ;; Once linked (or not) the program keeps what it needs; the shaders can go.
    (gl-delete-shader vertex)
    (gl-delete-shader fragment)
    (unless (gl-status-p program +gl-link-status+ #'gl-get-programiv)
      (let ((log (gl-info-log program #'gl-get-programiv #'gl-get-program-info-log)))
        (gl-delete-program program)
        (render-fail "the shader program did not link: ~A"
                     (string-trim '(#\Newline #\Space #\Nul) log))))
    program))
