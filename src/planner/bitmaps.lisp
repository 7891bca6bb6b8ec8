;;;; bitmaps.lisp -- sets of dense state numbers as vectors of 64-bit words.
;;;; SolvedStates, the goals' solved states and the reachable index's state
;;;; sets are read and written a word at a time (a cube's states in one word
;;;; are one 64-bit pattern), so they are (UNSIGNED-BYTE 64) vectors: bit I is
;;;; bit (MOD I 64) of word (FLOOR I 64), and the bits past the last state are
;;;; always clear.  Portable Lisp, no access to SBCL's vector internals.

(in-package #:player.planner)

(deftype bitmap ()
  "A set of small integers: bit I of the set is bit (MOD I 64) of word (FLOOR I 64)."
  '(simple-array (unsigned-byte 64) (*)))

(defconstant +full-word+ (1- (ash 1 64)) "A word with every bit set.")

(defun make-bitmap (bit-count &key (initial-bit 0))
  "A BITMAP for bits [0, BIT-COUNT), every one INITIAL-BIT (0 or 1)."
  (multiple-value-bind (words rest) (ceiling bit-count 64)
    (let ((bitmap (make-array words :element-type '(unsigned-byte 64)
                                    :initial-element (if (= initial-bit 1) +full-word+ 0))))
      ;; REST is minus the unused bits of the last word, which stay clear.
      (when (and (= initial-bit 1) (minusp rest))
        (setf (aref bitmap (1- words)) (1- (ash 1 (+ 64 rest)))))
      bitmap)))

(defmacro bitmap-word (bitmap index)
  "Word INDEX of BITMAP, an (UNSIGNED-BYTE 64); SETF-able."
  `(aref (the bitmap ,bitmap) ,index))

(declaim (inline bitmap-bit (setf bitmap-bit)))
(defun bitmap-bit (bitmap index)
  "Bit INDEX of BITMAP, 0 or 1."
  (declare (type bitmap bitmap) (type (integer 0 #.most-positive-fixnum) index))
  (logand 1 (ash (aref bitmap (ash index -6)) (- (logand index 63)))))

(defun (setf bitmap-bit) (bit bitmap index)
  "Set bit INDEX of BITMAP to BIT (0 or 1); return BIT."
  (declare (type bit bit) (type bitmap bitmap) (type (integer 0 #.most-positive-fixnum) index))
  (let ((word (ash index -6))
        (mask (ash 1 (logand index 63))))
    (declare (type (unsigned-byte 64) mask))
    (setf (aref bitmap word) (if (= bit 1)
                                 (logior (aref bitmap word) mask)
                                 (logandc2 (aref bitmap word) mask)))
    bit))

(defun count-marked (bitmap)
  "How many bits of BITMAP are set, a word at a time."
  (declare (type bitmap bitmap) (optimize speed))
  (loop for word across bitmap sum (logcount word) of-type fixnum))

(defun bitmap-first-clear (bitmap bit-count)
  "The smallest I below BIT-COUNT whose bit in BITMAP is clear, or NIL."
  (declare (type bitmap bitmap) (type fixnum bit-count))
  (loop for index of-type fixnum from 0
        for word across bitmap
        unless (= word +full-word+)
          do (let ((bit (+ (* index 64) (1- (integer-length (logand (lognot word) (1+ word)))))))
               (return (and (< bit bit-count) bit)))))

(defun bitmap-ior-into (target source)
  "Set in TARGET every bit set in SOURCE (a BITMAP of the same length); return TARGET."
  (declare (type bitmap target source))
  (dotimes (index (length target) target)
    (setf (aref target index) (logior (aref target index) (aref source index)))))

(defun bitmap-bits (bitmap bit-count)
  "BITMAP's first BIT-COUNT bits as a fresh SIMPLE-BIT-VECTOR (for tests and printing)."
  (let ((bits (make-array bit-count :element-type 'bit)))
    (dotimes (index bit-count bits)
      (setf (sbit bits index) (bitmap-bit bitmap index)))))
