;;;; fuzz-models.lisp -- the fuzzer's model files: .gltf, .glb and .x files
;;;; seeded from Assimp's test models (Debian assimp-testmodels), mutated
;;;; (bytes flipped, files cut, JSON edited where it counts: accessor counts
;;;; and offsets, indices, NaN, missing buffers, out-of-range joints; counts
;;;; and numbers of .x text) and fed to bin/player as child processes.  Each
;;;; run of a case must end with exit 0, or exit 1 and one line
;;;; "player: error: ..." naming the file; a signal, a memory fault, SBCL's
;;;; "fatal error", a backtrace, the debugger, a Lisp object printed (#<) or a
;;;; hang past the timeout is a finding.
;;;;
;;;; What runs on a case is a list of targets (*FZM-TARGETS*), each a command
;;;; builder: `model` on the file, then `check` and `render` (one tiny frame)
;;;; of a spec whose script library's (model ...) names it.  `make fuzz` runs FUZZ_MODEL_CASES (300) cases
;;;; (fuzz-main.lisp); t/test-model-fuzz.lisp runs a sample.

(in-package #:player-tests)

;;; ---------------------------------------------------------------------------
;;; The seeds: Assimp's test models

(defparameter *fzm-models-directory* #p"/usr/share/assimp/models/"
  "Where Debian's assimp-testmodels puts Assimp's test models.")

(defparameter *fzm-seed-size-limit* 65536
  "Seeds larger than this many bytes are left out (but see *FZM-LARGE-SEEDS*),
so a case costs milliseconds to write and import.")

(defparameter *fzm-large-seeds* '("X/Testwuson.X" "X/BCN_Epileptic.X")
  "Seeds kept whatever their size: skinned, animated .x files, the ones whose
joints, weights and keys Player reads most of.")

(defun fzm-seed-files ()
  "The seed files, relative names under *FZM-MODELS-DIRECTORY* in a fixed
order: every .gltf and .glb under glTF/ and glTF2/ and every .x under X/ no
larger than *FZM-SEED-SIZE-LIMIT*, and *FZM-LARGE-SEEDS*."
  (let ((root (namestring *fzm-models-directory*)))
    (flet ((small-p (path)
             (with-open-file (in path :element-type '(unsigned-byte 8))
               (<= (file-length in) *fzm-seed-size-limit*)))
           (relative (path) (subseq (namestring path) (length root))))
      (sort (remove-duplicates
             (append (loop for pattern in '("glTF2/**/*.gltf" "glTF2/**/*.glb" "glTF/**/*.gltf" "glTF/**/*.glb"
                                            "X/*.x" "X/*.X")
                           nconc (loop for path in (directory (merge-pathnames pattern *fzm-models-directory*))
                                       when (small-p path) collect (relative path)))
                     (remove-if-not (lambda (name) (probe-file (merge-pathnames name *fzm-models-directory*)))
                                    *fzm-large-seeds*))
             :test #'string=)
            #'string<))))

(defvar *fzm-seeds* nil "The seed names, found once (FZM-SEEDS).")

(defun fzm-seeds ()
  "The seed names (see FZM-SEED-FILES), found on first use."
  (or *fzm-seeds* (setf *fzm-seeds* (fzm-seed-files))))

(defun fzm-format (name)
  "The kind of the model NAME: :GLTF, :GLB, :X-TEXT or :X-BINARY (from its header)."
  (let ((type (string-downcase (pathname-type name))))
    (cond ((string= type "gltf") :gltf)
          ((string= type "glb") :glb)
          (t (let ((header (make-array 12 :element-type '(unsigned-byte 8) :initial-element 0)))
               (with-open-file (in (merge-pathnames name *fzm-models-directory*) :element-type '(unsigned-byte 8))
                 (read-sequence header in))
               (if (equalp (subseq header 8 12) (map 'vector #'char-code "txt "))
                   :x-text
                   :x-binary))))))

(defun fzm-seed-octets (name)
  "The bytes of the seed NAME."
  (alexandria:read-file-into-byte-vector (merge-pathnames name *fzm-models-directory*)))

;;; ---------------------------------------------------------------------------
;;; Octets and text

(defun fzm-octets-text (octets)
  "OCTETS as a string of Latin-1 characters, one a byte, so text edits keep
every other byte as it was."
  (map 'string #'code-char octets))

(defun fzm-text-octets (text)
  "TEXT (characters below 256, see FZM-OCTETS-TEXT) as octets."
  (map '(vector (unsigned-byte 8)) (lambda (c) (logand #xFF (char-code c))) text))

(defun fzm-utf8 (string)
  "STRING as UTF-8 octets."
  (sb-ext:string-to-octets string :external-format :utf-8))

;;; ---------------------------------------------------------------------------
;;; Byte mutations, for every format

(defparameter *fzm-interesting-bytes* '(#x00 #xFF #x7F #x80 #x01 #x20 #x22 #x7B #x5B #x3B)
  "Bytes worth writing: the ends of each range, and JSON's and .x's punctuation.")

(defparameter *fzm-interesting-u32*
  '(#xFFFFFFFF #x7FFFFFFF #x80000000 #x0000FFFF #x00010000 #x7FC00000 #x7F800000 #xFF800000 0 1)
  "32-bit words worth writing: the ends of the integer ranges, float NaN and the infinities.")

(defun fzm-flip (prng octets)
  "OCTETS with 1 to 16 bits flipped at random places."
  (let ((copy (copy-seq octets)) (count (fz-between prng 1 16)))
    (dotimes (i count) (let ((at (fz-below prng (length copy))))
                         (setf (aref copy at) (logxor (aref copy at) (ash 1 (fz-below prng 8))))))
    (values copy (format nil "~D bits flipped" count))))

(defun fzm-bytes (prng octets)
  "OCTETS with 1 to 8 bytes overwritten by interesting ones."
  (let ((copy (copy-seq octets)) (count (fz-between prng 1 8)))
    (dotimes (i count) (setf (aref copy (fz-below prng (length copy))) (fz-pick prng *fzm-interesting-bytes*)))
    (values copy (format nil "~D bytes overwritten" count))))

(defun fzm-put-u32 (octets at value)
  "Write VALUE as a little-endian 32-bit word at AT of OCTETS (cut at the end)."
  (loop for k below 4
        when (< (+ at k) (length octets))
          do (setf (aref octets (+ at k)) (ldb (byte 8 (* 8 k)) value))))

(defun fzm-words (prng octets &key (start 0) (end (length octets)) (aligned t))
  "OCTETS with 1 to 6 interesting 32-bit words written between START and END."
  (let ((copy (copy-seq octets)) (count (fz-between prng 1 6)))
    (when (> end (+ start 4))
      (dotimes (i count)
        (let ((at (+ start (fz-below prng (- end start 3)))))
          (fzm-put-u32 copy (if aligned (- at (mod (- at start) 4)) at) (fz-pick prng *fzm-interesting-u32*)))))
    (values copy (format nil "~D 32-bit words overwritten" count))))

(defun fzm-truncate (prng octets)
  "OCTETS cut at a random place (sometimes a byte short of the end)."
  (let ((end (if (fz-chance prng 0.2) (1- (length octets)) (fz-below prng (length octets)))))
    (values (subseq octets 0 (max 1 end)) (format nil "cut to ~D of ~D bytes" (max 1 end) (length octets)))))

(defun fzm-chunk (prng octets)
  "OCTETS with a random chunk of up to 64 bytes deleted or repeated."
  (let* ((start (fz-below prng (length octets)))
         (end (min (length octets) (+ start 1 (fz-below prng 64))))
         (chunk (subseq octets start end)))
    (if (fz-chance prng 0.5)
        (values (concatenate '(vector (unsigned-byte 8)) (subseq octets 0 start) (subseq octets end))
                (format nil "bytes ~D to ~D deleted" start end))
        (values (concatenate '(vector (unsigned-byte 8)) (subseq octets 0 end) chunk (subseq octets end))
                (format nil "bytes ~D to ~D repeated" start end)))))

(defparameter *fzm-byte-kinds*
  '((3 . :flip) (2 . :bytes) (2 . :words) (2 . :truncate) (1 . :chunk))
  "The byte mutations, weighted.")

(defun fzm-mutate-bytes (prng kind octets)
  "OCTETS mutated by the byte mutation KIND; the bytes and a note."
  (ecase kind
    (:flip (fzm-flip prng octets))
    (:bytes (fzm-bytes prng octets))
    (:words (fzm-words prng octets :aligned nil))
    (:truncate (fzm-truncate prng octets))
    (:chunk (fzm-chunk prng octets))))

;;; ---------------------------------------------------------------------------
;;; JSON, read and written back as it was (for glTF)
;;; A value is a string (its raw text between the quotes, escapes kept),
;;; (:NUMBER . TEXT), (:RAW . TEXT) (a mutation's token, written verbatim),
;;; :TRUE, :FALSE, :NULL, (:ARRAY . VALUES) or (:OBJECT . ((KEY . VALUE) ...)).

(defun fzm-json-parse (text)
  "The JSON value of TEXT; an ERROR when TEXT is not JSON."
  (let ((i 0) (n (length text)))
    (labels ((peek () (and (< i n) (char text i)))
             (blanks () (loop while (and (< i n) (member (char text i) '(#\Space #\Tab #\Newline #\Return)))
                            do (incf i)))
             (expect (char)
               (blanks)
               (unless (eql (peek) char) (error "JSON: ~S expected at ~D" char i))
               (incf i))
             (word (word)
               (when (and (<= (+ i (length word)) n) (string= word text :start2 i :end2 (+ i (length word))))
                 (incf i (length word))))
             (raw-string ()
               (let ((start i))
                 (loop (let ((c (peek)))
                         (cond ((null c) (error "JSON: unterminated string"))
                               ((char= c #\\) (incf i 2))
                               ((char= c #\") (incf i) (return (subseq text start (1- i))))
                               (t (incf i)))))))
             (value ()
               (blanks)
               (let ((c (peek)))
                 (cond ((null c) (error "JSON: value expected at the end"))
                       ((char= c #\{) (incf i) (object))
                       ((char= c #\[) (incf i) (array))
                       ((char= c #\") (incf i) (raw-string))
                       ((or (digit-char-p c) (char= c #\-))
                        (let ((start i))
                          (loop while (and (< i n) (find (char text i) "+-0123456789.eE")) do (incf i))
                          (cons :number (subseq text start i))))
                       ((word "true") :true)
                       ((word "false") :false)
                       ((word "null") :null)
                       (t (error "JSON: unexpected ~S at ~D" c i)))))
             (object ()
               (blanks)
               (if (eql (peek) #\})
                   (progn (incf i) (list :object))
                   (cons :object
                         (loop collect (progn (expect #\") (let ((key (raw-string)))
                                                             (expect #\:)
                                                             (cons key (value))))
                               do (blanks)
                               while (eql (peek) #\,)
                               do (incf i)
                               finally (expect #\})))))
             (array ()
               (blanks)
               (if (eql (peek) #\])
                   (progn (incf i) (list :array))
                   (cons :array (loop collect (value)
                                      do (blanks)
                                      while (eql (peek) #\,)
                                      do (incf i)
                                      finally (expect #\]))))))
      (prog1 (value) (blanks)))))

(defun fzm-json-text (value)
  "VALUE written as JSON text."
  (with-output-to-string (out)
    (labels ((write-value (value)
               (cond ((stringp value) (format out "\"~A\"" value))
                     ((eq value :true) (write-string "true" out))
                     ((eq value :false) (write-string "false" out))
                     ((eq value :null) (write-string "null" out))
                     ((member (car value) '(:number :raw)) (write-string (cdr value) out))
                     ((eq (car value) :array)
                      (write-char #\[ out)
                      (loop for (element . more) on (rest value)
                            do (write-value element) (when more (write-char #\, out)))
                      (write-char #\] out))
                     (t (write-char #\{ out)
                        (loop for ((key . element) . more) on (rest value)
                              do (format out "\"~A\":" key) (write-value element) (when more (write-char #\, out)))
                        (write-char #\} out)))))
      (write-value value))))

(defun fzm-json-sites (value &optional (path '()))
  "Every place in VALUE, as (PATH . VALUE), PATH the keys and indices from the root."
  (cons (cons (reverse path) value)
        (when (consp value)
          (case (car value)
            (:array (loop for element in (rest value) for i from 0
                          nconc (fzm-json-sites element (cons i path))))
            (:object (loop for (key . element) in (rest value)
                           nconc (fzm-json-sites element (cons key path))))))))

(defun fzm-json-get (value path)
  "The value at PATH in VALUE, or NIL."
  (loop for step in path
        do (setf value (cond ((and (integerp step) (consp value) (eq (car value) :array)) (nth step (rest value)))
                             ((and (stringp step) (consp value) (eq (car value) :object))
                              (cdr (assoc step (rest value) :test #'string=)))
                             (t (return nil))))
        finally (return value)))

(defun fzm-json-update (value path function)
  "VALUE with the value at PATH replaced by FUNCTION of it (a fresh copy along
PATH); when FUNCTION returns :DELETE, that member or element is removed."
  (if (null path)
      (funcall function value)
      (let ((step (first path)))
        (flet ((update (old) (fzm-json-update old (rest path) function)))
          (ecase (car value)
            (:array (cons :array (loop for element in (rest value) for i from 0
                                       for new = (if (eql i step) (update element) element)
                                       unless (eq new :delete) collect new)))
            (:object (cons :object (loop for (key . element) in (rest value)
                                         for new = (if (equal key step) (update element) element)
                                         unless (eq new :delete) collect (cons key new)))))))))

(defun fzm-json-length (value key)
  "How many elements the top-level array KEY of the glTF VALUE has (0 when none)."
  (let ((array (fzm-json-get value (list key))))
    (if (and (consp array) (eq (car array) :array)) (length (rest array)) 0)))

;;; ---------------------------------------------------------------------------
;;; glTF mutations, on the JSON

(defparameter *fzm-special-numbers*
  '("NaN" "Infinity" "-Infinity" "1e39" "-1e39" "1e308" "-1" "0" "4294967295" "4294967296" "2147483647"
    "-2147483648" "18446744073709551615" "0.5" "-0.0" "1e-45")
  "Numbers worth writing: not finite, past a float, past each integer range, negative, fractional.")

(defparameter *fzm-reference-keys*
  '(("bufferView" . "bufferViews") ("buffer" . "buffers") ("indices" . "accessors")
    ("POSITION" . "accessors") ("NORMAL" . "accessors") ("TEXCOORD_0" . "accessors") ("TEXCOORD_1" . "accessors")
    ("COLOR_0" . "accessors") ("JOINTS_0" . "accessors") ("WEIGHTS_0" . "accessors") ("TANGENT" . "accessors")
    ("input" . "accessors") ("output" . "accessors") ("inverseBindMatrices" . "accessors")
    ("node" . "nodes") ("children" . "nodes") ("joints" . "nodes") ("skeleton" . "nodes") ("nodes" . "nodes")
    ("mesh" . "meshes") ("skin" . "skins") ("camera" . "cameras") ("material" . "materials")
    ("source" . "images") ("index" . "textures") ("sampler" . "samplers") ("scene" . "scenes"))
  "glTF keys whose numbers (or arrays of numbers) index a top-level array, with that array.")

(defparameter *fzm-size-keys* '("count" "byteOffset" "byteLength" "byteStride" "componentType" "mode")
  "glTF keys whose numbers are sizes, offsets or codes.")

(defun fzm-number-value (value)
  "The integer a (:NUMBER . TEXT) VALUE holds, or NIL."
  (and (consp value) (eq (car value) :number) (ignore-errors (parse-integer (cdr value)))))

(defun fzm-sites-if (predicate json)
  "The sites (PATH . VALUE) of JSON for which PREDICATE of the path and the value is true."
  (remove-if-not (lambda (site) (funcall predicate (car site) (cdr site))) (rest (fzm-json-sites json))))

(defun fzm-site-key (path)
  "The last key (a string) on PATH: the member's own, or, for an array element, its array's."
  (find-if #'stringp path :from-end t))

(defun fzm-set-site (json site value note-control &rest arguments)
  "JSON with SITE's value set to VALUE, and a note."
  (values (fzm-json-update json (car site) (constantly value))
          (format nil "~{~A~^.~} := ~A~@[ (~?)~]" (car site) (fzm-json-text value) note-control arguments)))

(defun fzm-gltf-number (prng json)
  "A number of JSON replaced by a special one (NaN, huge, negative...)."
  (let ((sites (fzm-sites-if (lambda (path value) (declare (ignore path)) (and (consp value) (eq (car value) :number))) json)))
    (when sites
      (fzm-set-site json (fz-pick prng sites) (cons :raw (fz-pick prng *fzm-special-numbers*)) nil))))

(defun fzm-gltf-reference (prng json)
  "An index of JSON (an accessor, node, joint, buffer view...) sent out of
range, negative, huge, or to another element (the node itself, for children)."
  (let ((sites (fzm-sites-if (lambda (path value)
                               (and (fzm-number-value value)
                                    (assoc (fzm-site-key path) *fzm-reference-keys* :test #'string=)))
                             json)))
    (when sites
      (let* ((site (fz-pick prng sites))
             (length (fzm-json-length json (cdr (assoc (fzm-site-key (car site)) *fzm-reference-keys* :test #'string=))))
             (self (and (string= (fzm-site-key (car site)) "children") (third (reverse (car site)))))
             (value (fz-pick prng (list length (1+ length) -1 255 65535 4294967295 2147483648
                                        (fz-below prng (max 1 length)) (or self 0)))))
        (fzm-set-site json site (cons :raw (princ-to-string value)) "of ~D" length)))))

(defun fzm-gltf-size (prng json)
  "A count, offset, length, stride or code of JSON made wrong: zero, negative,
one more or less, doubled, misaligned or huge."
  (let ((sites (fzm-sites-if (lambda (path value)
                               (and (fzm-number-value value) (member (fzm-site-key path) *fzm-size-keys* :test #'string=)))
                             json)))
    (when sites
      (let* ((site (fz-pick prng sites))
             (n (fzm-number-value (cdr site)))
             (value (fz-pick prng (list 0 -1 -4 (1+ n) (1- n) (* 2 n) (+ n 4) 1 3 4294967295 2147483647
                                        268435456 1000000000 5120 5126 9999))))
        (fzm-set-site json site (cons :raw (princ-to-string value)) "was ~D" n)))))

(defun fzm-gltf-delete (prng json)
  "A member or element of JSON removed (a buffer, an accessor, a key, an index)."
  (let ((sites (rest (fzm-json-sites json))))
    (when sites
      (let ((site (fz-pick prng sites)))
        (values (fzm-json-update json (car site) (constantly :delete))
                (format nil "~{~A~^.~} deleted" (car site)))))))

(defun fzm-gltf-duplicate (prng json)
  "An element of an array of JSON repeated (a node with two parents, a joint twice...)."
  (let ((sites (fzm-sites-if (lambda (path value) (declare (ignore path))
                               (and (consp value) (eq (car value) :array) (rest value)))
                             json)))
    (when sites
      (let* ((site (fz-pick prng sites))
             (k (fz-below prng (length (rest (cdr site))))))
        (values (fzm-json-update json (car site)
                                 (lambda (array)
                                   (let ((elements (rest array)))
                                     (cons :array (append (subseq elements 0 (1+ k)) (subseq elements k))))))
                (format nil "~{~A~^.~}[~D] repeated" (car site) k))))))

(defun fzm-gltf-type (prng json)
  "A value of JSON replaced by one of another type."
  (let ((sites (rest (fzm-json-sites json))))
    (when sites
      (fzm-set-site json (fz-pick prng sites)
                    (fz-pick prng (list "x" :null :true (list :array) (list :object) (cons :number "1.5")
                                        (cons :array (loop repeat 5 collect (cons :number "1")))))
                    nil))))

(defun fzm-gltf-uri (prng json)
  "A buffer's or image's uri sent to a missing file, a folder, a device, or
data that is too short or not base64."
  (let ((sites (fzm-sites-if (lambda (path value) (declare (ignore value))
                               (equal (fzm-site-key path) "uri"))
                             json)))
    (when sites
      (fzm-set-site json (fz-pick prng sites)
                    (fz-pick prng '("missing.bin" "" "." "/dev/zero" "/dev/null" "../../../../../etc/passwd"
                                    "data:application/octet-stream;base64,AAAA"
                                    "data:application/octet-stream;base64,!!!!" "data:,"))
                    nil))))

(defun fzm-gltf-joints (prng json)
  "A skin's joints made 300 to 400 long, over a chain of new nodes: past
*MODEL-JOINT-LIMIT*, with an inverse-bind accessor of the old count."
  (let ((skins (fzm-json-length json "skins"))
        (first (fzm-json-length json "nodes"))
        (count (fz-between prng 300 400)))
    (when (plusp skins)
      (let* ((skin (fz-below prng skins))
             (chain (loop for i below count
                          collect (cons :object (append (list (cons "name" (format nil "j~D" i)))
                                                        (when (< (1+ i) count)
                                                          (list (cons "children"
                                                                      (list :array (cons :number (princ-to-string (+ first i 1))))))))))))
        (values (fzm-json-update
                 (fzm-json-update json (list "nodes") (lambda (nodes) (append nodes chain)))
                 (list "skins" skin)
                 (lambda (object)
                   (cons :object (cons (cons "joints" (cons :array (loop for i below count
                                                                           collect (cons :number (princ-to-string (+ first i))))))
                                       (remove "joints" (rest object) :key #'car :test #'string=)))))
                (format nil "skins.~D.joints: ~D new chained nodes" skin count))))))

(defparameter *fzm-gltf-kinds*
  '((15 . :gltf-number) (20 . :gltf-reference) (20 . :gltf-size) (8 . :gltf-delete) (5 . :gltf-duplicate)
    (8 . :gltf-type) (6 . :gltf-uri) (4 . :gltf-joints))
  "The JSON mutations of glTF, weighted.")

(defun fzm-mutate-json (prng kind json)
  "JSON mutated by KIND (of *FZM-GLTF-KINDS*): the new JSON and a note, or NIL
when JSON has no place for KIND."
  (funcall (ecase kind
             (:gltf-number #'fzm-gltf-number) (:gltf-reference #'fzm-gltf-reference)
             (:gltf-size #'fzm-gltf-size) (:gltf-delete #'fzm-gltf-delete)
             (:gltf-duplicate #'fzm-gltf-duplicate) (:gltf-type #'fzm-gltf-type)
             (:gltf-uri #'fzm-gltf-uri) (:gltf-joints #'fzm-gltf-joints))
           prng json))

;;; ---------------------------------------------------------------------------
;;; .glb: the JSON chunk and the binary chunk, packed again with their lengths

(defun fzm-u32 (octets at)
  "The little-endian 32-bit word at AT of OCTETS."
  (loop for k below 4 sum (ash (aref octets (+ at k)) (* 8 k))))

(defun fzm-glb-chunks (octets)
  "The JSON text and the binary chunk (octets or NIL) of the .glb OCTETS."
  (let* ((json-length (fzm-u32 octets 12))
         (json-end (+ 20 json-length))
         (json (sb-ext:octets-to-string octets :start 20 :end json-end :external-format '(:utf-8 :replacement #\?))))
    (values json (when (< (+ json-end 8) (length octets))
                   (subseq octets (+ json-end 8) (min (length octets) (+ json-end 8 (fzm-u32 octets json-end))))))))

(defun fzm-glb-pack (json binary)
  "A .glb of the JSON text and the BINARY chunk (or none), lengths and padding right."
  (let* ((text (fzm-utf8 json))
         (text (concatenate '(vector (unsigned-byte 8)) text
                            (make-array (mod (- (length text)) 4) :initial-element 32)))
         (binary (and binary (concatenate '(vector (unsigned-byte 8)) binary
                                          (make-array (mod (- (length binary)) 4) :initial-element 0))))
         (total (+ 12 8 (length text) (if binary (+ 8 (length binary)) 0)))
         (out (make-array total :element-type '(unsigned-byte 8) :initial-element 0)))
    (replace out (map 'vector #'char-code "glTF"))
    (fzm-put-u32 out 4 2)
    (fzm-put-u32 out 8 total)
    (fzm-put-u32 out 12 (length text))
    (replace out (map 'vector #'char-code "JSON") :start1 16)
    (replace out text :start1 20)
    (when binary
      (let ((at (+ 20 (length text))))
        (fzm-put-u32 out at (length binary))
        (replace out (map 'vector #'char-code (format nil "BIN~C" (code-char 0))) :start1 (+ at 4))
        (replace out binary :start1 (+ at 8))))
    out))

;;; ---------------------------------------------------------------------------
;;; .x text: counts and numbers

(defun fzm-number-tokens (text)
  "The numbers of TEXT as (START END INTEGERP COUNTP), COUNTP when an integer
is alone on its line before a semicolon (how .x writes a count)."
  (let ((tokens '()) (i 0) (n (length text)))
    (loop while (< i n)
          do (let ((c (char text i)))
               (if (and (or (digit-char-p c) (and (char= c #\-) (< (1+ i) n) (digit-char-p (char text (1+ i)))))
                        (or (zerop i) (not (alphanumericp (char text (1- i))))))
                   (let ((start i))
                     (incf i)
                     (loop while (and (< i n) (find (char text i) "0123456789.eE+-")) do (incf i))
                     (let* ((integerp (not (find-if (lambda (c) (find c ".eE")) text :start start :end i)))
                            (line-start (1+ (or (position #\Newline text :end start :from-end t) -1)))
                            (countp (and integerp (< i n) (char= (char text i) #\;)
                                         (every (lambda (c) (member c '(#\Space #\Tab)))
                                                (subseq text line-start start)))))
                       (unless (alpha-char-p (if (< i n) (char text i) #\;))
                         (push (list start i integerp countp) tokens))))
                   (incf i))))
    (coerce (nreverse tokens) 'vector)))

(defun fzm-replace-token (text token new)
  "TEXT with TOKEN's characters replaced by NEW."
  (concatenate 'string (subseq text 0 (first token)) new (subseq text (second token))))

(defun fzm-x-count (prng text tokens)
  "An integer of the .x TEXT (a count, more often than not) made wrong."
  (let* ((integers (remove-if-not #'third tokens))
         (counts (remove-if-not #'fourth integers))
         (token (if (and (plusp (length counts)) (fz-chance prng 0.6)) (fz-pick prng counts) (fz-pick prng integers)))
         (n (parse-integer text :start (first token) :end (second token) :junk-allowed t))
         (new (princ-to-string (fz-pick prng (list 0 -1 (1+ n) (1- n) (1+ (* 2 n)) 2147483647 4294967295
                                                   99999999 65536 300)))))
    (values (fzm-replace-token text token new)
            (format nil "the integer ~D at ~D := ~A" n (first token) new))))

(defun fzm-x-number (prng text tokens)
  "A number of the .x TEXT made not finite, past a float, or negative."
  (let* ((floats (remove-if #'third tokens))
         (token (fz-pick prng (if (plusp (length floats)) floats tokens)))
         (new (fz-pick prng '("nan" "-nan" "inf" "-inf" "1e39" "-1e39" "1.#QNAN0" "1.#INF00" "NaN" "1e-45" "-1.0"))))
    (values (fzm-replace-token text token new)
            (format nil "the number ~A at ~D := ~A" (subseq text (first token) (second token)) (first token) new))))

(defun fzm-x-line (prng text)
  "A line of the .x TEXT deleted or repeated."
  (let* ((lines (fz-split-lines text))
         (k (fz-below prng (length lines)))
         (delete (fz-chance prng 0.5)))
    (values (format nil "~{~A~^~%~}" (if delete
                                         (append (subseq lines 0 k) (nthcdr (1+ k) lines))
                                         (append (subseq lines 0 (1+ k)) (nthcdr k lines))))
            (format nil "line ~D ~:[repeated~;deleted~]" (1+ k) delete))))

(defparameter *fzm-x-kinds* '((30 . :x-count) (25 . :x-number) (15 . :x-line))
  "The text mutations of .x, weighted.")

;;; ---------------------------------------------------------------------------
;;; Cases

(defstruct (fzm-case (:conc-name fzmc-))
  "One mutated model: SEED and INDEX made it from the seed model BASE (a name
under *FZM-MODELS-DIRECTORY*) of FORMAT; FILE-NAME is the name it is written
under, beside a copy of BASE's folder, with OCTETS; EXTRAS ((NAME . OCTETS)
...) are further files it uses (a mutated buffer); KINDS and NOTES say what
was done."
  seed index base format file-name octets (extras '()) (kinds '()) (notes '()) texture)

(defun fzm-mutate-gltf-json (prng case json)
  "JSON (of CASE) mutated once or twice by glTF mutations, kinds and notes
recorded in CASE; the new JSON."
  (loop repeat (if (fz-chance prng 0.25) 2 1)
        do (loop repeat 8             ; a kind with no place in this file: try another
                 do (let ((kind (fz-weighted prng *fzm-gltf-kinds*)))
                      (multiple-value-bind (new note) (fzm-mutate-json prng kind json)
                        (when new
                          (setf json new)
                          (push kind (fzmc-kinds case))
                          (push note (fzmc-notes case))
                          (return))))))
  json)

(defun fzm-external-buffer (json)
  "The index and uri of the first buffer of JSON stored in its own file, or NIL."
  (loop for buffer in (rest (fzm-json-get json '("buffers")))
        for i from 0
        for uri = (fzm-json-get buffer '("uri"))
        when (and (stringp uri) (plusp (length uri)) (not (eql 0 (search "data:" uri))))
          return (values i uri)))

(defun fzm-mutate-buffer (prng case octets)
  "OCTETS (a binary buffer) with interesting words written, noted in CASE."
  (multiple-value-bind (new note) (fzm-words prng octets :aligned (fz-chance prng 0.8))
    (push :buffer-words (fzmc-kinds case))
    (push (format nil "buffer: ~A" note) (fzmc-notes case))
    new))

(defun fzm-make-gltf (prng case octets)
  "The bytes of CASE, a mutated .gltf made from OCTETS."
  (let* ((json (fzm-json-parse (sb-ext:octets-to-string octets :external-format '(:utf-8 :replacement #\?))))
         (buffer (nth-value 1 (fzm-external-buffer json))))
    (if (and buffer (fz-chance prng 0.15)
             (probe-file (merge-pathnames buffer (merge-pathnames (fzmc-base case) *fzm-models-directory*))))
        ;; The buffer's bytes mutated, in a file of the case's own.
        (let ((index (fzm-external-buffer json))
              (bytes (alexandria:read-file-into-byte-vector
                      (merge-pathnames buffer (merge-pathnames (fzmc-base case) *fzm-models-directory*)))))
          (push (cons "fuzz-case.bin" (fzm-mutate-buffer prng case bytes)) (fzmc-extras case))
          (setf json (fzm-json-update json (list "buffers" index "uri") (constantly "fuzz-case.bin")))
          (when (fz-chance prng 0.3) (setf json (fzm-mutate-gltf-json prng case json)))
          (fzm-utf8 (fzm-json-text json)))
        (fzm-utf8 (fzm-json-text (fzm-mutate-gltf-json prng case json))))))

(defun fzm-make-glb (prng case octets)
  "The bytes of CASE, a mutated .glb made from OCTETS."
  (multiple-value-bind (text binary) (fzm-glb-chunks octets)
    (let ((json (fzm-json-parse text)))
      (when (and binary (fz-chance prng 0.3))
        (setf binary (fzm-mutate-buffer prng case binary)))
      (when (or (null (fzmc-kinds case)) (fz-chance prng 0.3))
        (setf json (fzm-mutate-gltf-json prng case json)))
      (fzm-glb-pack (fzm-json-text json) binary))))

(defun fzm-make-x-text (prng case octets)
  "The bytes of CASE, a .x text file made from OCTETS with its counts, numbers or lines changed."
  (let ((text (fzm-octets-text octets)))
    (loop repeat (if (fz-chance prng 0.25) 2 1)
          do (let ((kind (fz-weighted prng *fzm-x-kinds*)))
               (multiple-value-bind (new note)
                   (if (eq kind :x-line)
                       (fzm-x-line prng text)
                       (let ((tokens (fzm-number-tokens text)))
                         (funcall (if (eq kind :x-count) #'fzm-x-count #'fzm-x-number) prng text tokens)))
                 (setf text new)
                 (push kind (fzmc-kinds case))
                 (push note (fzmc-notes case)))))
    (fzm-text-octets text)))

(defparameter *fzm-texture-seeds*
  '("glTF2/BoxTextured-glTF/CesiumLogoFlat.png" "X/test.png" "X/bottom.tga")
  "Images whose mutations are given as --texture.")

(defun fzm-generate (seed index)
  "The model case INDEX of SEED: a seed model mutated by bytes (any format),
JSON (glTF), its buffer (glTF) or its text (.x); every eighth case or so
also gets a mutated texture for --texture."
  (let* ((prng (make-fz-prng seed index #x6D6F64656C))
         (base (fz-pick prng (fzm-seeds)))
         (format (fzm-format base))
         (octets (fzm-seed-octets base))
         (case (make-fzm-case :seed seed :index index :base base :format format
                              :file-name (format nil "fuzz-case.~(~A~)" (pathname-type base)))))
    (setf (fzmc-octets case)
          (if (or (eq format :x-binary) (fz-chance prng (if (eq format :glb) 0.4 0.25)))
              (let ((kind (fz-weighted prng *fzm-byte-kinds*)))
                (multiple-value-bind (new note) (fzm-mutate-bytes prng kind octets)
                  (push kind (fzmc-kinds case))
                  (push note (fzmc-notes case))
                  new))
              (handler-case (ecase format
                              (:gltf (fzm-make-gltf prng case octets))
                              (:glb (fzm-make-glb prng case octets))
                              (:x-text (fzm-make-x-text prng case octets)))
                ;; A seed that is not JSON (Assimp keeps a few broken on purpose): bytes instead.
                (error ()
                  (multiple-value-bind (new note) (fzm-flip prng octets)
                    (push :flip (fzmc-kinds case))
                    (push note (fzmc-notes case))
                    new)))))
    (when (fz-chance prng 0.12)
      (let* ((image (fz-pick prng *fzm-texture-seeds*))
             (path (merge-pathnames image *fzm-models-directory*)))
        (when (probe-file path)
          (multiple-value-bind (new note)
              (fzm-mutate-bytes prng (fz-weighted prng *fzm-byte-kinds*) (alexandria:read-file-into-byte-vector path))
            (setf (fzmc-texture case) (format nil "fuzz-texture.~A" (pathname-type image)))
            (push (cons (fzmc-texture case) new) (fzmc-extras case))
            (push :texture (fzmc-kinds case))
            (push (format nil "texture ~A: ~A" image note) (fzmc-notes case))))))
    (setf (fzmc-kinds case) (reverse (fzmc-kinds case))
          (fzmc-notes case) (reverse (fzmc-notes case)))
    case))

;;; ---------------------------------------------------------------------------
;;; Targets: what runs on a case

(defstruct (fzm-target (:conc-name fzmt-))
  "A command run on each model case: NAME, and BUILDER, a function of the
case, the case file's name and the folder it is in, returning bin/player's
arguments (it may write further files there, a script library naming the
model, say), or NIL when the target does not apply to the case; ERROR-NAMES,
further text an error line may name instead of the case's files (`check`
says \"check found N errors\" and lists them on standard output)."
  name builder (error-names '()))

(defun fzm-write-stage (case file directory)
  "Write into DIRECTORY fuzz-lib.lisp, a script library whose (model ...)
names the case FILE (with its mutated texture, if any), and fuzz-spec.lisp,
a spec of one state playing it; the spec's name."
  (with-open-file (out (merge-pathnames "fuzz-lib.lisp" directory) :direction :output :if-exists :supersede)
    (format out "(model ~S~@[ :texture ~S~])~%(defscript stand () (:at 0 :set (:self visible) t))~%"
            file (fzmc-texture case)))
  (with-open-file (out (merge-pathnames "fuzz-spec.lisp" directory) :direction :output :if-exists :supersede)
    (format out "(in-package :player-user)~%(defspec fuzz-stage \"A mutated model as the character.\"~%  (:scripts \"fuzz-lib.lisp\")~%  (state-variable up boolean false)~%  (op stand :add up :duration 0.1)~%  (event ev-stand :op stand))~%"))
  "fuzz-spec.lisp")

(defun fzm-write-prop-stage (case file directory)
  "Write into DIRECTORY fuzz-prop-lib.lisp, a script library declaring the
case FILE as a prop (most seeds have no joints, so as a character they stop
at that), and fuzz-prop-spec.lisp, a spec playing it on a humanoid; the spec."
  (with-open-file (out (merge-pathnames "fuzz-prop-lib.lisp" directory) :direction :output :if-exists :supersede)
    (format out "(defobject thing :kind :prop :model ~S~@[ :texture ~S~] :height 0.3 :position (0.3 1 0.2))~%"
            file (fzmc-texture case)))
  (with-open-file (out (merge-pathnames "fuzz-prop-spec.lisp" directory) :direction :output :if-exists :supersede)
    (format out "(in-package :player-user)~%(defspec fuzz-props \"A mutated model as a prop.\"~%  (:scripts \"fuzz-prop-lib.lisp\")~%  (:body humanoid)~%  (state-variable up boolean false))~%"))
  "fuzz-prop-spec.lisp")

(defparameter *fzm-targets*
  (list (make-fzm-target :name "model"
                         :builder (lambda (case file directory)
                                    (declare (ignore directory))
                                    (append (list "model" file)
                                            (when (fzmc-texture case) (list "--texture" (fzmc-texture case))))))
        (make-fzm-target :name "check"
                         :builder (lambda (case file directory)
                                    (list "check" (fzm-write-stage case file directory)))
                         :error-names '("check found"))
        (make-fzm-target :name "render"
                         :builder (lambda (case file directory)
                                    (list "render" (fzm-write-stage case file directory) "--events" "ev-stand"
                                          "--fps" "4" "--at" "0.1" "--size" "48x36" "--silent" "--out" "fuzz-render/"))
                         :error-names '("fuzz-lib.lisp"))
        (make-fzm-target :name "render-prop"
                         :builder (lambda (case file directory)
                                    (list "render" (fzm-write-prop-stage case file directory)
                                          "--size" "48x36" "--silent" "--out" "fuzz-render/"))
                         :error-names '("fuzz-prop-lib.lisp")))
  "The commands run on every model case, in order: `model`, then `check` and
`render` (one frame, tiny) of a spec whose script library's (model ...)
names the case, and `render` of one declaring it a prop (defobject :model).")

(defun fzm-targets-named (&rest names)
  "The targets of *FZM-TARGETS* called NAMES, in their order."
  (remove-if-not (lambda (target) (member (fzmt-name target) names :test #'string=)) *fzm-targets*))

;;; ---------------------------------------------------------------------------
;;; Running cases

(defstruct (fzm-result (:conc-name fzmr-))
  "One target run on one case: ARGUMENTS given to bin/player, EXIT (a code or
:TIMEOUT), STATUS (:EXITED, :SIGNALED or :TIMEOUT), STDERR cut short,
PROBLEMS (none when it passed), SECONDS it took."
  seed index base format kinds notes target arguments exit status stderr (problems '()) seconds)

(defparameter *fzm-crash-marks*
  '(("fatal error" . "crash: SBCL fatal error") ("memory fault" . "crash: memory fault")
    ("CORRUPTION WARNING" . "crash: memory fault") ("heap exhausted" . "heap exhausted")
    ("the heap is exhausted" . "heap exhausted") ("control stack exhausted" . "stack exhausted")
    ("debugger" . "debugger") ("backtrace" . "backtrace") ("#<" . "Lisp object printed")
    ("Unhandled" . "unhandled condition"))
  "Text on the output that marks a run as failed, with the problem's label.")

(defun fzm-problems (exit status stdout stderr names)
  "What is wrong with a run of bin/player on a model case that ended with
EXIT and STATUS printing STDOUT and STDERR; NAMES are the case's file names,
one of which its error line must name."
  (let ((lines (remove-if (lambda (line) (or (string= line "") (eql 0 (search *fz-build-line* line))
                                             ;; render's progress bar, "[####...] 1/1 frames"
                                             (and (eql 0 (search "[" line)) (search "frames" line))))
                          (fz-split-lines (substitute #\Newline #\Return stderr))))
        (problems '()))
    (case status
      (:timeout (push "hang" problems))
      (:signaled (push (format nil "crash: signal ~D" exit) problems))
      (t (unless (member exit '(0 1)) (push (format nil "exit code ~A" exit) problems))))
    (loop for (mark . label) in *fzm-crash-marks*
          when (or (search mark stderr :test #'char-equal) (search mark stdout :test #'char-equal))
            do (pushnew label problems :test #'string=))
    (cond ((eql exit 0)
           (when lines (push "stderr after success" problems)))
          ((eql exit 1)
           (cond ((rest lines) (push "stderr has more than one line" problems))
                 ((not (eql 0 (search "player: error: " (first lines))))
                  (push "stderr line is not \"player: error: ...\"" problems))
                 ((notany (lambda (name) (search name (first lines))) names)
                  (push "error does not name the file" problems)))))
    (nreverse problems)))

(defun fzm-base-folder (run-directory base folders)
  "The copy of BASE's folder (its files only) under RUN-DIRECTORY, made on
first use and remembered in the hash table FOLDERS."
  (let ((source (uiop:pathname-directory-pathname (merge-pathnames base *fzm-models-directory*))))
    (or (gethash source folders)
        (let ((to (merge-pathnames (format nil "base-~D/" (hash-table-count folders)) run-directory)))
          (ensure-directories-exist to)
          (dolist (file (uiop:directory-files source))
            (alexandria:copy-file file (merge-pathnames (file-namestring file) to)))
          (setf (gethash source folders) to)))))

(defun fzm-write-case (case folder)
  "Write CASE's files into FOLDER (a copy of its base's folder); their paths."
  (loop for (name . octets) in (cons (cons (fzmc-file-name case) (fzmc-octets case)) (fzmc-extras case))
        collect (let ((path (merge-pathnames name folder)))
                  (with-open-file (out path :direction :output :if-exists :supersede :element-type '(unsigned-byte 8))
                    (write-sequence octets out))
                  path)))

(defun fzm-run-case (case player folder targets timeout)
  "Run each of TARGETS on CASE, written into FOLDER, with bin/player PLAYER;
a list of FZM-RESULTs."
  (let ((paths (fzm-write-case case folder)))
    (unwind-protect
         (loop for target in targets
               for arguments = (funcall (fzmt-builder target) case (fzmc-file-name case) folder)
               when arguments
                 collect (let ((start (get-internal-real-time)))
                           (multiple-value-bind (exit stdout stderr status)
                               (fz-run-process player arguments folder timeout)
                             (make-fzm-result
                              :seed (fzmc-seed case) :index (fzmc-index case) :base (fzmc-base case)
                              :format (fzmc-format case) :kinds (fzmc-kinds case) :notes (fzmc-notes case)
                              :target (fzmt-name target) :arguments arguments :exit exit :status status
                              :stderr (fz-clip stderr 400)
                              :problems (fzm-problems exit status stdout stderr
                                                      (append (list (fzmc-file-name case))
                                                              (and (fzmc-texture case) (list (fzmc-texture case)))
                                                              (fzmt-error-names target)))
                              :seconds (/ (- (get-internal-real-time) start) internal-time-units-per-second)))))
      (dolist (path paths) (ignore-errors (delete-file path))))))

(defun fuzz-models (&key (seed 1) (cases 300) (from 0) (timeout 20) (targets *fzm-targets*) progress)
  "Run CASES mutated models (numbered FROM on) through each of TARGETS with
bin/player, each run killed after TIMEOUT seconds; a list of FZM-RESULTs.
NIL when Assimp's test models are not installed."
  (when (and (probe-file *fzm-models-directory*) (fzm-seeds))
    (let ((player (namestring (checkout-file "bin/player")))
          (directory (fz-make-directory "player-fuzz-models"))
          (folders (make-hash-table :test 'equal))
          (results '()))
      (unwind-protect
           (progn
             ;; Built once here, so no case's stderr holds the build's line or its time.
             (fz-run-process player '("help") directory 600)
             (loop for index from from below (+ from cases)
                   for i from 1
                   do (let ((case (fzm-generate seed index)))
                        (setf results (revappend (fzm-run-case case player
                                                               (fzm-base-folder directory (fzmc-base case) folders)
                                                               targets timeout)
                                                 results)))
                      (when (and progress (zerop (mod i 50)))
                        (write-char #\. progress) (force-output progress))))
        (fz-delete-tree directory))
      (nreverse results))))

(defun fuzz-model-case (seed index directory)
  "Write model case INDEX of SEED, with a copy of its base's folder, into
DIRECTORY (a reproducer); the bin/player command lines of its targets."
  (let* ((case (fzm-generate seed index))
         (folder (uiop:ensure-directory-pathname directory)))
    (ensure-directories-exist folder)
    (dolist (file (uiop:directory-files (uiop:pathname-directory-pathname
                                         (merge-pathnames (fzmc-base case) *fzm-models-directory*))))
      (alexandria:copy-file file (merge-pathnames (file-namestring file) folder)))
    (fzm-write-case case folder)
    (loop for target in *fzm-targets*
          for arguments = (funcall (fzmt-builder target) case (fzmc-file-name case) folder)
          when arguments collect (format nil "cd ~A && bin/player ~{~A~^ ~}" (namestring folder) arguments))))

(defun fzm-report (results seconds &optional (stream *standard-output*))
  "Print the model cases: by format and outcome, then each kind of problem once
with a reproducer; the number of failed runs."
  (format stream "~&~%Models: ~:D runs in ~,1F s~%~%  ~10A ~8@A ~8@A ~8@A~%" (length results) seconds
          "format" "exit 0" "exit 1" "failed")
  (dolist (format '(:gltf :glb :x-text :x-binary))
    (let ((mine (remove format results :key #'fzmr-format :test-not #'eq)))
      (format stream "  ~10A ~8:D ~8:D ~8:D~%" (string-downcase format) (count 0 mine :key #'fzmr-exit)
              (count 1 mine :key #'fzmr-exit) (count-if #'fzmr-problems mine))))
  (let ((groups '()))
    (dolist (result results)
      (dolist (problem (fzmr-problems result))
        (let ((entry (assoc problem groups :test #'string=)))
          (if entry
              (incf (second entry))
              (setf groups (append groups (list (list problem 1 result))))))))
    (if groups
        (progn
          (format stream "~%Model failures, by kind (one reproducer each):~%")
          (loop for (label count result) in groups
                do (format stream "~A: ~D run~:P~%    seed ~D case ~D: ~(~A~), base ~A, ~A~%    mutations: ~{~A~^; ~}~%    exit ~A; stderr: ~A~%    the files: (player-tests::fuzz-model-case ~D ~D \"/tmp/model-case/\")~%"
                           label count (fzmr-seed result) (fzmr-index result) (fzmr-format result)
                           (fzmr-base result) (fzmr-target result) (fzmr-notes result)
                           (fzmr-exit result) (fzmr-stderr result) (fzmr-seed result) (fzmr-index result))))
        (format stream "~%No model failures.~%"))
    (count-if #'fzmr-problems results)))
