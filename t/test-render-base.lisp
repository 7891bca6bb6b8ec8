;;;; test-render-base.lisp -- the renderer's base: PNG files, OSMesa contexts,
;;;; GL bindings, shaders and multisampled targets.
;;;; PNGs are checked by an independent decoder (python3's zlib, as on CI);
;;;; GL is checked by drawing into llvmpipe and counting the pixels read back.

(in-package #:player-tests)

(def-suite* render-base :in player-tests)

;;; ---------------------------------------------------------------------------
;;; PNG

(defparameter *png-decoder*
  "import sys, struct, zlib
def decode(path):
  data = open(path, 'rb').read()
  assert data[:8] == bytes([137, 80, 78, 71, 13, 10, 26, 10]), 'bad signature'
  pos, chunks = 8, []
  while pos < len(data):
      n, = struct.unpack('>I', data[pos:pos + 4])
      kind, body = data[pos + 4:pos + 8], data[pos + 8:pos + 8 + n]
      crc, = struct.unpack('>I', data[pos + 8 + n:pos + 12 + n])
      assert crc == zlib.crc32(kind + body) & 0xffffffff, 'bad CRC in ' + kind.decode()
      chunks.append((kind, body))
      pos += 12 + n
  assert chunks[0][0] == b'IHDR' and chunks[-1][0] == b'IEND', 'bad chunk order'
  w, h, depth, ct, comp, filt, lace = struct.unpack('>IIBBBBB', chunks[0][1])
  c = {2: 3, 6: 4}[ct]
  raw = zlib.decompress(b''.join(b for k, b in chunks if k == b'IDAT'))
  assert len(raw) == h * (w * c + 1), 'bad scanline count'
  stride, out, prev = w * c, bytearray(), bytearray(w * c)
  for y in range(h):
      f, row = raw[y * (stride + 1)], bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
      for i in range(stride):
          a, b = (row[i - c] if i >= c else 0), prev[i]
          if f == 1: row[i] = (row[i] + a) & 255
          elif f == 2: row[i] = (row[i] + b) & 255
          else: assert f == 0, 'unexpected filter'
      out += row
      prev = row
  return ' '.join(map(str, (w, h, depth, ct, comp, filt, lace, out.hex())))
for path in sys.argv[1:]:
  try: print(decode(path))
  except Exception as e: print('error', repr(str(e)))"
  "A PNG reader independent of Player: checks signature, chunk CRCs and order,
inflates IDAT with zlib, undoes filters 0-2, prints the header and pixels in hex.")

(defun parse-decoded-png (line)
  "LINE of the decoder's output as (width height bit-depth colour-type
compression filter interlace pixels), or LINE itself when it reports an error."
  (if (eql 0 (search "error" line))
      line
      (with-input-from-string (in line)
        (let ((header (loop repeat 7 collect (read in)))
              (hex (string-trim " " (read-line in))))
          (append header
                  (list (coerce (loop for i from 0 below (length hex) by 2
                                      collect (parse-integer hex :start i :end (+ i 2) :radix 16))
                                '(vector (unsigned-byte 8)))))))))

(defun decode-pngs (paths)
  "What python3 reads from each PNG file in PATHS (see PARSE-DECODED-PNG).
One process for all of them: starting python3 can cost half a second."
  (let ((output (with-output-to-string (out)
                  (sb-ext:run-program "python3" (list* "-c" *png-decoder* (mapcar #'namestring paths))
                                      :search t :output out :error *error-output*))))
    (with-input-from-string (in output)
      (loop for line = (read-line in nil) while line collect (parse-decoded-png line)))))

(defun random-pixels (width height channels seed)
  "WIDTH*HEIGHT*CHANNELS random bytes, the same for the same SEED."
  (let ((state (sb-ext:seed-random-state seed))
        (pixels (make-array (* width height channels) :element-type '(unsigned-byte 8))))
    (dotimes (i (length pixels) pixels)
      (setf (aref pixels i) (random 256 state)))))

(defun temporary-png (name)
  "A pathname for a scratch PNG called NAME."
  (merge-pathnames (format nil "player-test-~36R-~A.png" (random (expt 36 6) (make-random-state t)) name) "/tmp/"))

(test crc32-known-vectors
  (flet ((crc (text) (player.render::crc32-octets (map 'player.render::octets #'char-code text))))
    (is (= 0 (crc "")))
    (is (= #xCBF43926 (crc "123456789")))
    (is (= #x414FA339 (crc "The quick brown fox jumps over the lazy dog"))))
  ;; Every PNG ends with the same IEND chunk, CRC AE 42 60 82.
  (is (equalp #(0 0 0 0 73 69 78 68 #xAE #x42 #x60 #x82)
              (player.render::png-chunk "IEND" (make-array 0 :element-type '(unsigned-byte 8))))))

(test png-round-trip
  ;; Odd sizes, both colour types, every filter; each file checked by the decoder.
  (let ((cases (loop for (width height) in '((1 1) (3 5) (17 9) (64 2))
                     append (loop for channels in '(3 4)
                                  append (loop for filter in '(:none :sub :up)
                                               collect (list width height channels filter)))))
        (paths '()))
    (unwind-protect
         (let ((expected
                 (loop for (width height channels filter) in cases
                       for seed from 1
                       for pixels = (random-pixels width height channels seed)
                       for path = (temporary-png (format nil "~D" seed))
                       do (push path paths)
                          (player::write-png path width height pixels :channels channels
                                                                      :filter filter)
                       collect (list width height 8 (if (= channels 3) 2 6) 0 0 0 pixels))))
           (is (= (length cases) (length expected)))
           (loop for case in cases
                 for wanted in expected
                 for got in (decode-pngs (reverse paths))
                 do (is (equalp wanted got) "~{~Dx~D, ~D channels, filter ~A~}: ~S" case got)))
      (mapc (lambda (path) (ignore-errors (delete-file path))) paths))))

(test png-decoder-notices-corruption
  ;; The round trip is only as good as its decoder: a flipped byte must show.
  (let ((octets (player::png-octets 3 5 (random-pixels 3 5 3 7) :channels 3))
        (path (temporary-png "corrupt")))
    (incf (aref octets 40))
    (unwind-protect
         (progn (with-open-file (out path :direction :output :element-type '(unsigned-byte 8))
                  (write-sequence octets out))
                (is (search "bad CRC in IDA" (first (decode-pngs (list path))))))
      (ignore-errors (delete-file path)))))

(test png-up-filter-shrinks-shaded-frames
  ;; Lit surfaces are smooth gradients; filter Up (the default) turns them into
  ;; near-constant rows that deflate far better than the raw bytes.
  (let ((frame (make-array (* 64 64 4) :element-type '(unsigned-byte 8))))
    (dotimes (i (* 64 64))
      (multiple-value-bind (y x) (floor i 64)
        (replace frame (list (* 4 x) (* 3 y) 128 255) :start1 (* 4 i))))
    (is (< (* 4 (length (player::png-octets 64 64 frame)))
           (length (player::png-octets 64 64 frame :filter :none))))))

(test png-errors
  (let ((pixels (random-pixels 2 2 4 1)))
    (signals player::render-error
      (player::write-png "/nonexistent-directory/frame.png" 2 2 pixels))
    (handler-case (player::write-png "/nonexistent-directory/frame.png" 2 2 pixels)
      (player::render-error (e)
        (is (search "cannot write the PNG file /nonexistent-directory/frame.png"
                    (princ-to-string e)))))
    (signals player::render-error (player::png-octets 3 2 pixels))
    (signals player::render-error (player::png-octets 2 2 pixels :channels 2))
    (signals player::render-error (player::png-octets 0 2 pixels))
    (signals player::render-error (player::png-octets 2 2 (coerce pixels 'list)))))

;;; ---------------------------------------------------------------------------
;;; Libraries

(test missing-libraries-name-their-packages
  (let ((player.render::*osmesa-library-names* '("libPlayerNoSuchOSMesa.so.99")))
    (handler-case (progn (player.render::load-osmesa-library) (fail "no error"))
      (player::render-error (e)
        (is (search "libOSMesa not found: install the Debian package libosmesa6"
                    (princ-to-string e))))))
  (let ((player.render::*glfw-library-names* '("libPlayerNoSuchGlfw.so.99")))
    (signals player::render-error (player.render::load-glfw-library)))
  (is-true (player.render::load-osmesa-library))
  (is-true (player.render::load-glfw-library)))

(test gl-calls-need-a-context
  (let ((player.render::*gl-entry-points* #()))
    (handler-case (progn (player.render::gl-finish) (fail "no error"))
      (player::render-error (e)
        (is (search "glFinish is not available" (princ-to-string e)))))))

;;; ---------------------------------------------------------------------------
;;; Offscreen contexts

(test offscreen-context-version-and-clear
  (player::with-offscreen-context ((context) 17 9)
    (multiple-value-bind (major minor) (player.render::gl-version)
      (is (or (> major 3) (and (= major 3) (>= minor 3))) "GL ~D.~D" major minor))
    (is (member (player.render::offscreen-context-profile context) '(:core :compat)))
    ;; Colours of the form k/255 convert to bytes exactly.
    (player.render::gl-clear-color (/ 51 255) (/ 102 255) (/ 153 255) 1)
    (player.render::gl-clear player.render::+gl-color-buffer-bit+)
    (let ((rgba (player::read-frame-pixels 17 9))
          (rgb (player::read-frame-pixels 17 9 :channels 3)))
      (is (= (* 17 9 4) (length rgba)))
      (is (equalp rgba (player.render::offscreen-context-pixels context)))
      (is (loop for i from 0 below (length rgba) by 4
                always (equalp #(51 102 153 255) (subseq rgba i (+ i 4)))))
      ;; 17*3 bytes per row is not a multiple of 4: checks the pack alignment.
      (is (= (* 17 9 3) (length rgb)))
      (is (loop for i from 0 below (length rgb) by 3
                always (equalp #(51 102 153) (subseq rgb i (+ i 3))))))
    (player.render::check-gl-error "clearing"))
  ;; Leaving the context unloads its functions.
  (signals player::render-error (player.render::gl-finish)))

(test offscreen-context-options-and-fallback
  (player::with-offscreen-context ((context) 8 8 :profile :compat)
    (is (eq :compat (player.render::offscreen-context-profile context)))
    (is (search "Compatibility" (player::gl-version-string))))
  ;; The fallback for Mesa before 11.2, which lacks OSMesaCreateContextAttribs.
  (let ((handle (player.render::osmesa-context-legacy 24 8)))
    (is-false (cffi:null-pointer-p handle))
    (player::with-gl-traps-masked
      (cffi:foreign-funcall "OSMesaDestroyContext" :pointer handle :void)))
  (signals player::render-error (player.render::make-offscreen-context 0 10)))

(test offscreen-contexts-nest
  (player::with-offscreen-context ((outer) 8 8)
    (player.render::gl-clear-color 0 1 0 1)
    (player.render::gl-clear player.render::+gl-color-buffer-bit+)
    (player::with-offscreen-context ((inner) 4 4)
      (player.render::gl-clear-color 1 0 0 1)
      (player.render::gl-clear player.render::+gl-color-buffer-bit+)
      (is (equalp #(255 0 0 255) (subseq (player::read-frame-pixels 4 4) 0 4))))
    ;; Back in the outer context, its frame is intact and GL calls still work.
    (is (equalp #(0 255 0 255) (subseq (player::read-frame-pixels 8 8) 60 64)))
    (player.render::check-gl-error "after a nested context")))

(defparameter *flat-vertex-shader*
  "#version 330 core
layout(location = 0) in vec2 position;
void main() { gl_Position = vec4(position, 0.0, 1.0); }")

(defparameter *flat-fragment-shader*
  "#version 330 core
uniform vec4 color;
out vec4 fragment;
void main() { fragment = color; }")

(defun draw-red-triangle (vertices)
  "Draw the triangle VERTICES (six NDC coordinates) in pure red over black."
  (let ((program (player::compile-shader-program *flat-vertex-shader* *flat-fragment-shader*))
        (array (player.render::gl-gen-object #'player.render::gl-gen-vertex-arrays))
        (buffer (player.render::gl-gen-object #'player.render::gl-gen-buffers)))
    (player.render::gl-clear-color 0 0 0 1)
    (player.render::gl-clear player.render::+gl-color-buffer-bit+)
    (player.render::gl-use-program program)
    (player.render::gl-uniform4f (player.render::gl-get-uniform-location program "color") 1 0 0 1)
    (player.render::gl-bind-vertex-array array)
    (player.render::gl-bind-buffer player.render::+gl-array-buffer+ buffer)
    (cffi:with-foreign-object (data :float 6)
      (loop for v in vertices for i from 0 do (setf (cffi:mem-aref data :float i) (float v 1f0)))
      (player.render::gl-buffer-data player.render::+gl-array-buffer+ 24 data player.render::+gl-static-draw+))
    (player.render::gl-vertex-attrib-pointer 0 2 player.render::+gl-float+ player.render::+gl-false+ 0
                                      (cffi:null-pointer))
    (player.render::gl-enable-vertex-attrib-array 0)
    (player.render::gl-draw-arrays player.render::+gl-triangles+ 0 3)
    (player.render::check-gl-error "drawing the test triangle")
    (player.render::gl-delete-object #'player.render::gl-delete-buffers buffer)
    (player.render::gl-delete-object #'player.render::gl-delete-vertex-arrays array)
    (player.render::gl-delete-program program)))

(defun red-levels (pixels)
  "The red byte of each RGBA pixel in PIXELS, as a list."
  (loop for i from 0 below (length pixels) by 4 collect (aref pixels i)))

(test triangle-drawn-with-a-vbo-shows-up-top-down
  ;; A triangle in the upper half of clip space: x -0.5..0.5, y 0.1..0.9,
  ;; i.e. on a 64x64 frame columns 16..48 and (top-down) rows 3..29, ~410 pixels.
  (player::with-offscreen-context ((context) 64 64)
    (draw-red-triangle '(-0.5 0.1  0.5 0.1  0.0 0.9))
    (let* ((pixels (player::read-frame-pixels 64 64))
           (red (loop for i from 0 below (* 64 64)
                      when (= 255 (aref pixels (* 4 i))) collect (multiple-value-list (floor i 64)))))
      (is (< 380 (length red) 440) "~D red pixels" (length red))
      (is (every (lambda (row-column) (<= 3 (first row-column) 29)) red))
      (is (every (lambda (row-column) (<= 15 (second row-column) 48)) red))
      (is (every (lambda (level) (member level '(0 255))) (red-levels pixels))
          "without multisampling every pixel is in or out")
      (is (equalp pixels (player.render::offscreen-context-pixels context))))))

(test shader-errors-carry-the-log
  (player::with-offscreen-context ((context) 4 4)
    (handler-case (progn (player::compile-shader-program *flat-vertex-shader* "#version 330 core
void main() { undefined_thing = 1; }")
                         (fail "no error"))
      (player::render-error (e)
        (is (search "fragment shader did not compile" (princ-to-string e)))
        (is (search "undefined_thing" (princ-to-string e)))))
    (is (plusp (player::compile-shader-program *flat-vertex-shader* *flat-fragment-shader*)))))

(test msaa-target-smooths-edges
  (player::with-offscreen-context ((context) 64 64)
    (let ((target (player::make-msaa-target 64 64 4)))
      (is (= 4 (player.render::msaa-target-samples target)))
      (draw-red-triangle '(-0.8 -0.7  0.9 -0.2  -0.1 0.85))
      (player::resolve-msaa-target target)
      (let* ((levels (red-levels (player::read-frame-pixels 64 64)))
             (between (count-if (lambda (level) (< 0 level 255)) levels)))
        (is (< 40 between) "~D edge pixels with intermediate red" between)
        (is (< 600 (count 255 levels)) "the interior is still solid"))
      ;; Drawing again after BIND-MSAA-TARGET works, and deleting leaves GL clean.
      (player::bind-msaa-target target)
      (draw-red-triangle '(-1 -1  1 -1  0 1))
      (player::resolve-msaa-target target)
      (player::delete-msaa-target target)
      (player.render::check-gl-error "with an MSAA target"))))
