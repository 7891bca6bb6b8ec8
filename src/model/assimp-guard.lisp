;;;; assimp-guard.lisp -- importing with Assimp guarded: its assertions and
;;;; memory faults become one MODEL-ERROR, its stderr is captured, one import
;;;; at a time (IMPORT-MODEL, in import.lisp, calls CALL-GUARDING-ASSIMP).

(in-package #:player.model)

;;;# Crashes inside Assimp
;;; Assimp (Debian's 5.2.5, built with its assertions on) trusts some of what a
;;; file says: fuzzed glTF 1.0 and .x files make it read past its buffers (a
;;; memory fault) or fail an ai_assert, whose handler prints to stderr and
;;; calls abort().  No check of ours before the call catches them all (`make
;;; fuzz` measures how often), so the call itself is guarded:
;;;  - a memory fault inside it (SBCL signals MEMORY-FAULT-ERROR) becomes one
;;;    MODEL-ERROR, SBCL's corruption warning captured with the rest of what
;;;    C printed to stderr meanwhile;
;;;  - a failed ai_assert calls our callback instead of abort(), which unwinds
;;;    out of Assimp as one MODEL-ERROR naming the assertion.  Assimp 5.2 keeps
;;;    its handler in a static pointer that Assimp::aiAssertViolation jumps
;;;    through (`jmp *handler(%rip)`), and Debian does not export
;;;    setAiAssertHandler, so the pointer is found from that one instruction
;;;    and set only when the instruction is exactly that (else asserts abort as
;;;    before).  SIGABRT itself cannot be caught from Lisp: SBCL's runtime owns
;;;    it and calls lose().
;;; Unwinding skips Assimp's destructors (its import leaks) and a memory fault
;;; may leave its heap broken, so the error says to treat the process as
;;; suspect; the CLI exits right after it.

(define-condition assimp-assertion (error)
  ((expression :initarg :expression :reader assimp-assertion-expression))
  (:documentation "Internal: an ai_assert failed inside a guarded call into Assimp."))

(cffi:defcallback assimp-assert-handler :void ((expression :pointer) (file :pointer) (line :int))
  (error 'assimp-assertion
         :expression (format nil "~A (~A:~D)" (c-message expression)
                             (let ((name (or (c-message file) "?"))) (subseq name (1+ (or (position #\/ name :from-end t) -1))))
                             line)))

(defvar *assert-handler-installed* nil "Whether Assimp's assertions call ASSIMP-ASSERT-HANDLER.")

(defun install-assert-handler ()
  "Point Assimp's assertion handler at ASSIMP-ASSERT-HANDLER, when
aiAssertViolation is the one indirect jump through it; true when it now is."
  (or *assert-handler-installed*
      (let ((violation (cffi:foreign-symbol-pointer "_ZN6Assimp17aiAssertViolationEPKcS1_i")))
        (when (and violation
                   (= #xFF (cffi:mem-aref violation :uint8 0))
                   (= #x25 (cffi:mem-aref violation :uint8 1)))
          ;; jmp *disp32(%rip): the slot is at the next instruction (6 bytes on) plus disp32.
          (let ((slot (cffi:inc-pointer violation (+ 6 (cffi:mem-ref violation :int32 2)))))
            (setf (cffi:mem-ref slot :pointer) (cffi:callback assimp-assert-handler)
                  *assert-handler-installed* t))))))

(defvar *assimp-lock* (bt:make-lock "player assimp")
  "Held around each import: Assimp's error string is one global, and a guarded
call redirects the process's file descriptor 2.")

(defun captured-text (fd)
  "The first line of what was written to the file descriptor FD (a temporary
file), at most 300 bytes, as one line; NIL when nothing was."
  (sb-posix:lseek fd 0 sb-posix:seek-set)
  (let* ((octets (make-array 300 :element-type '(unsigned-byte 8)))
         (count (sb-sys:with-pinned-objects (octets)
                  (sb-unix:unix-read fd (sb-sys:vector-sap octets) (length octets)))))
    (when (and count (plusp count))
      (let ((text (sb-ext:octets-to-string octets :end count :external-format '(:utf-8 :replacement #\?))))
        (string-trim " " (substitute-if #\Space (lambda (c) (< (char-code c) 32))
                                        (subseq text 0 (or (position #\Newline text) (length text)))))))))

(defun echo-captured (fd)
  "Copy what was written to the temporary file FD to the real stderr (an
import that went well keeps whatever Assimp printed)."
  (sb-posix:lseek fd 0 sb-posix:seek-set)
  (let ((octets (make-array 4096 :element-type '(unsigned-byte 8))))
    (loop for count = (sb-sys:with-pinned-objects (octets)
                        (sb-unix:unix-read fd (sb-sys:vector-sap octets) (length octets)))
          while (and count (plusp count))
          do (sb-unix:unix-write 2 octets 0 count))))

(defun call-guarding-assimp (thunk)
  "THUNK's value, THUNK being a call into Assimp made with stderr captured, a
memory fault or a failed assertion inside it made one MODEL-ERROR naming *MODEL-FILE*."
  (install-assert-handler)
  (finish-output *error-output*)
  (multiple-value-bind (capture name) (sb-posix:mkstemp "/tmp/player-assimp-XXXXXX")
    (sb-posix:unlink name)
    (let ((saved (sb-posix:dup 2)) (crash nil) (value nil))
      (sb-posix:dup2 capture 2)
      (unwind-protect
           (handler-case (setf value (funcall thunk))
             (sb-sys:memory-fault-error ()
               (setf crash "Assimp crashed reading it (a memory fault); the file is broken, and this process's memory is suspect"))
             (assimp-assertion (e)
               (setf crash (format nil "Assimp's own check failed reading it: ~A" (assimp-assertion-expression e)))))
        (sb-posix:dup2 saved 2)
        (sb-posix:close saved)
        (unless crash (echo-captured capture))
        (sb-posix:close capture))
      (when crash (fail "~A" crash))
      value)))
