;;;; gltf-buffer.lisp -- a glTF file's one binary buffer as it is filled: typed
;;;; octets that grow by doubling, numbers stored little-endian in place (a
;;;; float by its IEEE bits), and the bufferViews and accessors that describe
;;;; its parts as JSON objects.  One part is one bufferView starting on a
;;;; 4-byte boundary, read by one accessor; nothing is interleaved, so no
;;;; view needs a byteStride.  gltf-write.lisp fills it.

(in-package #:player.model)

(deftype octets () "A vector of bytes." '(simple-array (unsigned-byte 8) (*)))

(defconstant +gltf-float+ 5126 "glTF's componentType FLOAT.")
(defconstant +gltf-unsigned-short+ 5123 "glTF's componentType UNSIGNED_SHORT.")
(defconstant +gltf-unsigned-int+ 5125 "glTF's componentType UNSIGNED_INT.")
(defconstant +gltf-array-buffer+ 34962 "A bufferView's target for vertex attributes.")
(defconstant +gltf-element-array-buffer+ 34963 "A bufferView's target for vertex indices.")

(defstruct (gltf-buffer (:constructor make-gltf-buffer ()) (:conc-name buffer-))
  "The binary buffer being filled: OCTETS, of which the first FILL are
written; VIEWS and ACCESSORS, the JSON objects describing its parts, newest
first, with their counts (the index the next one gets)."
  (octets (make-array 65536 :element-type '(unsigned-byte 8)) :type octets)
  (fill 0 :type (integer 0 #.array-dimension-limit))
  (views '() :type list)
  (view-count 0 :type (integer 0))
  (accessors '() :type list)
  (accessor-count 0 :type (integer 0)))

(defun reserve-octets (buffer count)
  "BUFFER's octets, grown (by doubling) so that COUNT more fit after its fill."
  (let ((needed (+ (buffer-fill buffer) count))
        (octets (buffer-octets buffer)))
    (when (> needed (length octets))
      (let ((grown (make-array (max needed (* 2 (length octets))) :element-type '(unsigned-byte 8))))
        (replace grown octets :end2 (buffer-fill buffer))
        (setf (buffer-octets buffer) grown)))
    (buffer-octets buffer)))

(defun align-buffer (buffer)
  "Pad BUFFER with zeros to a multiple of 4 octets: glTF wants each view, and
the BIN chunk, to start on a 4-byte boundary."
  (let ((padding (mod (- (buffer-fill buffer)) 4)))
    (fill (reserve-octets buffer padding) 0 :start (buffer-fill buffer) :end (+ (buffer-fill buffer) padding))
    (incf (buffer-fill buffer) padding)))

(defun buffer-contents (buffer)
  "BUFFER's written octets, padded to a multiple of 4, as a fresh vector."
  (align-buffer buffer)
  (subseq (buffer-octets buffer) 0 (buffer-fill buffer)))

;;;# Numbers, little-endian

(declaim (inline store-u16 store-u32 store-f32))
(defun store-u16 (octets position value)
  "Store VALUE, an (unsigned-byte 16), at POSITION of OCTETS, low byte first."
  (declare (type octets octets) (type (unsigned-byte 16) value) (type fixnum position))
  (setf (aref octets position) (ldb (byte 8 0) value)
        (aref octets (+ position 1)) (ldb (byte 8 8) value)))

(defun store-u32 (octets position value)
  "Store VALUE, an (unsigned-byte 32), at POSITION of OCTETS, low byte first."
  (declare (type octets octets) (type (unsigned-byte 32) value) (type fixnum position))
  (setf (aref octets position) (ldb (byte 8 0) value)
        (aref octets (+ position 1)) (ldb (byte 8 8) value)
        (aref octets (+ position 2)) (ldb (byte 8 16) value)
        (aref octets (+ position 3)) (ldb (byte 8 24) value)))

(defun store-f32 (octets position x)
  "Store the single-float X at POSITION of OCTETS as its IEEE 754 bits, low byte first."
  (declare (type single-float x))
  (store-u32 octets position (ldb (byte 32 0) (sb-kernel:single-float-bits x))))

;;;# Views and accessors

(defun add-view (buffer start &optional target)
  "Record the octets of BUFFER from START to its fill as a bufferView (for
TARGET, a vertex or index buffer, when given); its index."
  (push (json-object "buffer" 0 "byteOffset" start "byteLength" (- (buffer-fill buffer) start)
                     "target" target)
        (buffer-views buffer))
  (prog1 (buffer-view-count buffer) (incf (buffer-view-count buffer))))

(defun add-accessor (buffer view component-type count type &key min max)
  "Record an accessor of COUNT elements of TYPE (\"SCALAR\", \"VEC3\"...) of
COMPONENT-TYPE reading all of the bufferView VIEW, with its MIN and MAX when
given; its index."
  (push (json-object "bufferView" view "componentType" component-type "count" count "type" type
                     "min" min "max" max)
        (buffer-accessors buffer))
  (prog1 (buffer-accessor-count buffer) (incf (buffer-accessor-count buffer))))

(defun element-type-name (width)
  "The glTF accessor type of elements of WIDTH components."
  (ecase width (1 "SCALAR") (2 "VEC2") (3 "VEC3") (4 "VEC4") (16 "MAT4")))

(defun add-floats (buffer floats width what &key target bounds)
  "Append FLOATS (a FLOAT-VECTOR, WIDTH components an element) to BUFFER as
a view (for TARGET when given) and an accessor of floats, whose index is
returned; with BOUNDS, the accessor carries each component's min and max.
A MODEL-WRITE-ERROR naming WHAT when a float is NaN or infinite."
  (declare (type float-vector floats) (type (integer 1 16) width))
  (align-buffer buffer)
  (let* ((start (buffer-fill buffer))
         (count (floor (length floats) width))
         (octets (reserve-octets buffer (* 4 (length floats))))
         (min (make-array width :element-type 'single-float :initial-element most-positive-single-float))
         (max (make-array width :element-type 'single-float :initial-element most-negative-single-float)))
    (declare (type octets octets) (type fixnum start))
    (dotimes (i (length floats))
      (let ((x (aref floats i)))
        (unless (finite-single-p x)
          (write-fail "~A hold a value that is not finite (NaN or infinite)" what))
        (store-f32 octets (+ start (* 4 i)) x)
        (when bounds
          (let ((k (mod i width)))
            (setf (aref min k) (min x (aref min k))
                  (aref max k) (max x (aref max k)))))))
    (setf (buffer-fill buffer) (+ start (* 4 (length floats))))
    (add-accessor buffer (add-view buffer start target) +gltf-float+ count (element-type-name width)
                  :min (and bounds min) :max (and bounds max))))

(defun add-indices (buffer indices)
  "Append INDICES (an INDEX-VECTOR of vertex indices) to BUFFER as an index
view and an UNSIGNED_INT accessor; the accessor's index."
  (declare (type index-vector indices))
  (align-buffer buffer)
  (let ((start (buffer-fill buffer))
        (octets (reserve-octets buffer (* 4 (length indices)))))
    (dotimes (i (length indices))
      (store-u32 octets (+ start (* 4 i)) (aref indices i)))
    (setf (buffer-fill buffer) (+ start (* 4 (length indices))))
    (add-accessor buffer (add-view buffer start +gltf-element-array-buffer+)
                  +gltf-unsigned-int+ (length indices) "SCALAR")))

(defun add-joint-indices (buffer joints)
  "Append JOINTS (a vector of (unsigned-byte 16), 4 a vertex) to BUFFER as a
vertex view and an UNSIGNED_SHORT VEC4 accessor; the accessor's index."
  (declare (type (simple-array (unsigned-byte 16) (*)) joints))
  (align-buffer buffer)
  (let ((start (buffer-fill buffer))
        (octets (reserve-octets buffer (* 2 (length joints)))))
    (dotimes (i (length joints))
      (store-u16 octets (+ start (* 2 i)) (aref joints i)))
    (setf (buffer-fill buffer) (+ start (* 2 (length joints))))
    (add-accessor buffer (add-view buffer start +gltf-array-buffer+)
                  +gltf-unsigned-short+ (floor (length joints) 4) "VEC4")))

(defun add-octets (buffer octets)
  "Append OCTETS (an image file's bytes) to BUFFER as a view; the view's index."
  (align-buffer buffer)
  (let ((start (buffer-fill buffer)))
    (replace (reserve-octets buffer (length octets)) octets :start1 start)
    (setf (buffer-fill buffer) (+ start (length octets)))
    (add-view buffer start)))
