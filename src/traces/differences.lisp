;;;; differences.lisp -- the first place a replay departs from a recording,
;;;; said in plain words: a trace line (compared as text), the number of
;;;; lines, the number of frames, or one number of a frame (compared within a
;;;; tolerance), named by frame, body, joint and component.

(in-package #:player.traces)

(defstruct (recording-difference (:constructor make-recording-difference (kind index message)))
  "Where a replay first differs from a recording: KIND is :LINE, :LINE-COUNT,
:FRAME or :FRAME-COUNT; INDEX the 1-based trace line or 0-based frame at
fault (NIL for a count); MESSAGE says it in plain words."
  kind index message)

(defun file-line-note (numbers index)
  "\" (file line N)\" for the INDEXth form of a recording whose file lines are NUMBERS, or \"\"."
  (let ((line (nth index numbers)))
    (if line (format nil " (file line ~D)" line) "")))

;;;# Trace lines

(defun trace-difference (recording replayed)
  "The first RECORDING-DIFFERENCE between RECORDING's trace lines and the
REPLAYED ones (texts), or NIL when they are the same."
  (let* ((expected (recording-lines recording))
         (at (mismatch expected replayed :test #'string=)))
    (cond ((null at) nil)
          ((and (< at (length expected)) (< at (length replayed)))
           (make-recording-difference
            :line (1+ at)
            (format nil "trace line ~D~A: expected ~A, got ~A" (1+ at)
                    (file-line-note (recording-line-numbers recording) at)
                    (nth at expected) (nth at replayed))))
          (t (make-recording-difference
              :line-count nil
              (format nil "the recording has ~D trace line~:P, the replay ~D; the first ~:[missing~;extra~] is line ~D: ~A"
                      (length expected) (length replayed) (> (length replayed) (length expected))
                      (1+ at) (or (nth at replayed) (nth at expected))))))))

;;;# Frames

(defparameter *default-frame-tolerance* 1d-4
  "How far a number of a replayed frame may be from the recorded one.")

(defparameter *frame-entry-kinds* '((:bodies . "body") (:joints . "joint") (:objects . "object"))
  "The frame keys whose values are lists of named entries, and what an entry is called.")

(defparameter *component-names* '((:position "x" "y" "z") (:rotation "w" "x" "y" "z"))
  "The frame keys whose values are number lists, and their components' names.")

(defun plist-form-p (form)
  "Is FORM a proper list of keys and values, every key a symbol?"
  (and (proper-list-p form) (evenp (length form))
       (loop for (key) on form by #'cddr always (symbolp key))))

(defun frame-number-difference (expected got tolerance)
  "Do the reals EXPECTED and GOT differ by more than TOLERANCE?"
  (> (abs (- expected got)) tolerance))

(defun frame-path-text (path)
  "PATH, a list of names from the frame inwards, as words: \"body peedy, joint neck, rotation w\"."
  (format nil "~{~A~^, ~}" (reverse path)))

(defun frame-name= (a b)
  "Do the frame atoms A and B match: EQUAL, or two uninterned symbols of one
name (an imported model's joints are named by uninterned symbols, which a
recording reads back as fresh ones)?"
  (or (equal a b)
      (and (symbolp a) (symbolp b) a b
           (null (symbol-package a)) (null (symbol-package b))
           (string= (symbol-name a) (symbol-name b)))))

(defun compare-frame-parts (expected got path tolerance)
  "The first place where the frame parts EXPECTED and GOT differ beyond
TOLERANCE, as (PATH EXPECTED-PART GOT-PART), or NIL.  PATH names the parts
around them, innermost first."
  (cond ((and (realp expected) (realp got))
         (and (frame-number-difference expected got tolerance) (list path expected got)))
        ((or (atom expected) (atom got))
         (and (not (frame-name= expected got)) (list path expected got)))
        ((/= (length expected) (length got))
         (list path expected got))
        ((plist-form-p expected)
         (loop for (key value) on expected by #'cddr
               for (other-key other-value) on got by #'cddr
               thereis (if (eq key other-key)
                           (compare-frame-children key value other-value path tolerance)
                           (list path expected got))))
        (t (loop for a in expected for b in got for i from 0
                 thereis (compare-frame-parts a b (cons (format nil "[~D]" i) path) tolerance)))))

(defun compare-frame-children (key expected got path tolerance)
  "Compare the values EXPECTED and GOT of frame KEY (see COMPARE-FRAME-PARTS),
naming named entries (bodies, joints, objects) and components (x, w) by name."
  (let ((kind (cdr (assoc key *frame-entry-kinds*)))
        (components (rest (assoc key *component-names*)))
        (path (cons (string-downcase (symbol-name key)) path)))
    (cond ((and kind (proper-list-p expected) (proper-list-p got) (= (length expected) (length got)))
           (loop for a in expected for b in got
                 thereis (if (and (consp a) (consp b) (frame-name= (first a) (first b)))
                             (compare-frame-parts (rest a) (rest b)
                                                  (list* (format nil "~A ~(~A~)" kind (first a)) (rest path))
                                                  tolerance)
                             (list path a b))))
          ((and components (proper-list-p expected) (proper-list-p got)
                (= (length expected) (length got) (length components)))
           (loop for a in expected for b in got for name in components
                 thereis (compare-frame-parts a b (list* (format nil "~(~A~) ~A" key name) (rest path))
                                              tolerance)))
          ((and (eq key :dofs) (plist-form-p expected) (plist-form-p got)
                (equal (loop for (k) on expected by #'cddr collect k)
                       (loop for (k) on got by #'cddr collect k)))
           (loop for (name a) on expected by #'cddr
                 for b in (rest got) by #'cddr
                 thereis (compare-frame-parts a b (list* (format nil "dof ~(~A~)" name) (rest path))
                                              tolerance)))
          (t (compare-frame-parts expected got path tolerance)))))

(defun frame-part-text (part)
  "A frame PART as short text for a message."
  (with-recording-syntax () (truncate-text (prin1-to-string part) 120)))

(defun frames-difference (recording replayed tolerance)
  "The first RECORDING-DIFFERENCE between RECORDING's frames and the REPLAYED
ones (forms, as REPLAY-FRAMES returns them), numbers compared within TOLERANCE; or NIL."
  (let ((expected (recording-frames recording)))
    (if (/= (length expected) (length replayed))
        (make-recording-difference
         :frame-count nil
         (format nil "the recording has ~D frame~:P, the replay ~D" (length expected) (length replayed)))
        (loop for a in expected for b in replayed for index from 0
              for found = (compare-frame-parts a b '() tolerance)
              when found
                return (destructuring-bind (path expected-part got-part) found
                         (make-recording-difference
                          :frame index
                          (format nil "frame ~D at ~A s~A: ~@[~A: ~]expected ~A, got ~A~@[ (tolerance ~A)~]"
                                  index (format-number (fourth a))
                                  (file-line-note (recording-frame-line-numbers recording) index)
                                  (and path (frame-path-text path))
                                  (frame-part-text expected-part) (frame-part-text got-part)
                                  (and (realp expected-part) (realp got-part) (tolerance-text tolerance)))))))))

(defun tolerance-text (tolerance)
  "TOLERANCE as text: decimals down to a millionth, else exponent notation."
  (if (or (zerop tolerance) (>= tolerance 1d-6))
      (format-number tolerance)
      (format nil "~,1,,,,,'eE" tolerance)))
