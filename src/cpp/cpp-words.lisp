;;;; cpp-words.lisp -- the one-hot state in the generated C++: 64-bit words.
;;;;
;;;; The rule: bit I of the Lisp one-hot integer is bit I % 64 of word I / 64
;;;; of the C++ StateBits. A spec whose plannable variables need at most 64
;;;; bits (Peedy needs 14) keeps the fast path it always had: StateBits is one
;;;; std::uint64_t and a cube test is one mask test. A wider spec gets
;;;; std::array<std::uint64_t, kStateWords>, kStateWords a constant of the
;;;; generated code; every test of the state is written word by word, naming
;;;; only the words its constant mask constrains, so "does this plan apply"
;;;; stays a few mask tests however wide the state is, and an op's change
;;;; stores only the words it touches (other changes go through with_delta,
;;;; a loop over the words). The functions here turn Lisp masks into that
;;;; C++; the rest of the backend never looks at a word itself.

(in-package #:player.cpp)

(defvar *state-words* 1
  "How many 64-bit words hold the one-hot state of the machine being generated.")

(defvar *state-bit-count* 0
  "How many one-hot bits the state of the machine being generated has.")

(defun state-word-count (spec)
  "How many 64-bit words SPEC's one-hot state needs (at least one)."
  (max 1 (ceiling (spec-bit-count spec) 64)))

(defun wide-state-p ()
  "True when the state being generated takes more than one word."
  (> *state-words* 1))

(defun state-word (integer index)
  "Word INDEX of the one-hot INTEGER: its bits 64*INDEX ... 64*INDEX+63."
  (ldb (byte 64 (* 64 index)) integer))

(defun nonzero-words (integer)
  "The indices of INTEGER's words that are not zero, ascending."
  (loop for index below *state-words*
        unless (zerop (state-word integer index)) collect index))

(defun c++-word (bits index)
  "C++ for word INDEX of the StateBits expression BITS (BITS itself in one word)."
  (if (wide-state-p) (format nil "~A[~D]" bits index) bits))

(defun c++-bits (integer)
  "INTEGER, a set of one-hot bits, as a C++ StateBits value."
  (if (wide-state-p)
      (format nil "StateBits{{~{~A~^, ~}}}"
              (loop for index below *state-words* collect (c++-hex (state-word integer index))))
      (c++-hex integer)))

(defun c++-bits-parameter (name)
  "The declaration of a StateBits parameter NAME: by value in one word, else by reference."
  (if (wide-state-p) (format nil "const StateBits& ~A" name) (format nil "StateBits ~A" name)))

(defun c++-conjunction (tests)
  "C++ true when all of TESTS (C++ boolean texts) hold; true for none."
  (cond ((null tests) "true")
        ((null (rest tests)) (first tests))
        (t (format nil "(~{~A~^ && ~})" tests))))

(defun c++-disjunction (tests)
  "C++ true when one of TESTS (C++ boolean texts) holds; false for none."
  (cond ((null tests) "false")
        ((null (rest tests)) (first tests))
        (t (format nil "(~{~A~^ || ~})" tests))))

(defun c++-cube-holds (cube bits)
  "C++ true when the state BITS (a StateBits expression) lies in CUBE. In one
word, the mask test it always was; wider, one test per word where the cube
forbids something (true when it forbids nothing)."
  (if (wide-state-p)
      ;; Bits past the last field are never set: no test for them.
      (let ((forbidden (logandc2 (1- (ash 1 *state-bit-count*)) cube)))
        (c++-conjunction
         (loop for index in (nonzero-words forbidden)
               collect (format nil "(~A & ~A) == 0" (c++-word bits index)
                               (c++-hex (state-word forbidden index))))))
      (format nil "(~A & ~~~A) == 0" bits (c++-hex cube))))

(defun c++-bit-set-p (bit bits)
  "C++ true when the single one-hot BIT is set in the StateBits expression BITS."
  (let ((index (floor (1- (integer-length bit)) 64)))
    (format nil "(~A & ~A) != 0" (c++-word bits index) (c++-hex (state-word bit index)))))

(defun c++-bits-differ (before after mask)
  "C++ true when the StateBits expressions BEFORE and AFTER differ within MASK."
  (c++-disjunction
   (loop for index in (nonzero-words mask)
         collect (format nil "((~A ^ ~A) & ~A) != 0" (c++-word before index)
                         (c++-word after index) (c++-hex (state-word mask index))))))

(defun c++-delta-statements (bits mask values)
  "C++ statements setting the fields MASK of the StateBits lvalue BITS to
VALUES: in a wide state, only the words MASK touches."
  (if (wide-state-p)
      (loop for index in (nonzero-words mask)
            collect (let ((word (c++-word bits index)))
                      (format nil "~A = (~A & ~~~A) | ~A;" word word (c++-hex (state-word mask index))
                              (c++-hex (state-word values index)))))
      (list (format nil "~A = ~A;" bits (c++-with-delta bits mask values)))))

(defun c++-with-delta (bits mask values)
  "C++ for the StateBits expression BITS with the fields MASK set to VALUES."
  (if (wide-state-p)
      (format nil "with_delta(~A, ~A, ~A)" bits (c++-bits mask) (c++-bits values))
      (format nil "(~A & ~~~A) | ~A" bits (c++-hex mask) (c++-hex values))))

;;; The declarations in the header, and the helpers the .cpp's code and the
;;; timed layer call on StateBits whatever its width.

(defun emit-state-bits-type ()
  "The header's kStateWords and StateBits."
  (emit "/// The plannable state, one-hot: bit I of the state is bit I % 64 of word I / 64.")
  (emit "constexpr int kStateWords = ~D;" *state-words*)
  (if (wide-state-p)
      (emit "using StateBits = std::array<std::uint64_t, kStateWords>;~%")
      (emit "using StateBits = std::uint64_t;~%")))

(defun emit-state-bits-helpers ()
  "The .cpp's StateBits helpers (in its anonymous namespace)."
  (emit-resource (if (wide-state-p) "word-helpers.cpp" "one-word-helpers.cpp")))
