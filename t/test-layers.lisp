;;;; test-layers.lisp -- the layers stay layers (issue 25, item 3): each
;;;; module of player.asd is one package, uses only the layers the system
;;;; definition puts below it, and no source file reaches into another layer
;;;; with a package prefix.  doc/internals/architecture.md draws the map.

(in-package #:player-tests)

(def-suite* layers :in player-tests)

(defun layer-modules ()
  "The modules of the PLAYER system (the layers), in the order player.asd gives them."
  (remove-if-not (lambda (c) (typep c 'asdf:module))
                 (asdf:component-children (asdf:find-system "player"))))

(defun layer-package-name (module)
  "The package MODULE's files are in: PLAYER.<module name>, upper-cased."
  (string-upcase (format nil "player.~A" (asdf:component-name module))))

(defun layer-dependency-closure (module)
  "The names of the modules MODULE depends on, directly or through others."
  (let ((seen '()))
    (labels ((visit (name)
               (dolist (dependency (asdf:component-sideway-dependencies
                                    (asdf:find-component "player" name)))
                 (unless (member dependency seen :test #'string=)
                   (push dependency seen)
                   (visit dependency)))))
      (visit (asdf:component-name module)))
    seen))

(defun player-package-p (package)
  "Is PACKAGE one of Player's own (PLAYER, PLAYER-USER or a layer's)?"
  (let ((name (package-name package)))
    (or (string= name "PLAYER") (string= name "PLAYER-USER") (eql 0 (search "PLAYER." name)))))

(test every-layer-is-a-package-using-only-layers-below-it
  (let ((modules (layer-modules)))
    (is (<= 14 (length modules)) "player.asd names the layers as modules")
    (loop for (module . above) on modules
          for package = (find-package (layer-package-name module))
          for below = (layer-dependency-closure module)
          do (is (not (null package)) "the module ~A has no package ~A"
                 (asdf:component-name module) (layer-package-name module))
             (when package
               ;; :USE holds exactly the layers the module depends on, with CL.
               (is (equal (sort (mapcar #'string-upcase
                                        (mapcar (lambda (name) (format nil "player.~A" name)) below))
                                #'string<)
                          (sort (mapcar #'package-name
                                        (remove (find-package '#:cl) (package-use-list package)))
                                #'string<))
                   "~A uses ~{~A~^ ~}, but its module depends on ~{~A~^ ~}"
                   (package-name package) (mapcar #'package-name (package-use-list package)) below)
               ;; Nothing above it.
               (dolist (higher above)
                 (is (not (member (asdf:component-name higher) below :test #'string=))
                     "~A depends on ~A, which player.asd loads after it"
                     (asdf:component-name module) (asdf:component-name higher)))))))

(test no-layer-symbol-is-homed-in-a-higher-layer
  ;; A symbol a layer's package holds must be its own, CL's, Alexandria's or a
  ;; lower layer's: otherwise the lower layer reaches up.
  (let* ((modules (layer-modules))
         (rank (loop for module in modules for k from 0
                     collect (cons (layer-package-name module) k))))
    (dolist (module modules)
      (let* ((package (find-package (layer-package-name module)))
             (own (cdr (assoc (package-name package) rank :test #'string=))))
        (do-symbols (symbol package)
          (let ((home (cdr (assoc (package-name (or (symbol-package symbol) package)) rank
                                  :test #'string=))))
            (when (and home (> home own))
              (fail "~A holds ~S from the higher layer ~A"
                    (package-name package) symbol (package-name (symbol-package symbol))))))))))

(defun source-files ()
  "Every Lisp source file of the PLAYER system, with the module it belongs to."
  (let ((files '()))
    (labels ((walk (component module)
               (typecase component
                 (asdf:cl-source-file (push (cons component module) files))
                 (asdf:module (dolist (child (asdf:component-children component))
                                (walk child module))))))
      (dolist (module (layer-modules))
        (walk module module)))
    (nreverse files)))

(defun package-prefixes (text)
  "Each package prefix into Player in TEXT: (PACKAGE-NAME . DOUBLE-COLON-P),
PACKAGE-NAME upper-cased, for every PLAYER: PLAYER:: PLAYER.X: or PLAYER.X::."
  (loop with start = 0
        for at = (search "player" text :test #'char-equal :start2 start)
        while at
        do (setf start (1+ at))
        when (or (zerop at) (not (or (alphanumericp (char text (1- at))) (find (char text (1- at)) "-.*:"))))
          append (let ((end (position-if-not (lambda (c) (or (alphanumericp c) (find c "-+."))) text
                                             :start at)))
                   (when (and end (char= (char text end) #\:)
                              ;; "player: error: ..." is a message, not a prefix.
                              (let ((next (position #\: text :start end :test-not #'char=)))
                                (and next (graphic-char-p (char text next))
                                     (not (find (char text next) " \"'`()")))))
                     (list (cons (string-upcase (subseq text at end))
                                 (and (< (1+ end) (length text)) (char= (char text (1+ end)) #\:))))))))

(test every-file-is-in-its-layers-package-and-reaches-no-other-by-prefix
  (dolist (entry (source-files))
    (destructuring-bind (file . module) entry
      (let* ((text (uiop:read-file-string (asdf:component-pathname file)))
             (name (enough-namestring (asdf:component-pathname file) *root*))
             (own (layer-package-name module))
             (allowed (cons own (mapcar (lambda (m) (string-upcase (format nil "player.~A" m)))
                                        (layer-dependency-closure module)))))
        (is (search (format nil (if (string= (asdf:component-name file) "package")
                                    "(defpackage #:~(~A~)"
                                    "(in-package #:~(~A~))")
                                own)
                    text)
            "~A is not in its layer's package ~A" name own)
        (loop for (package . double) in (package-prefixes text)
              ;; PLAYER-USER is where spec files are read, not a layer.
              unless (string= package "PLAYER-USER")
                do (is (not double) "~A reaches an internal name with ~A::" name package)
                   (is (member package allowed :test #'string=)
                       "~A names ~A:, a package its layer does not use" name package))))))

(test the-facade-exports-only-what-the-layers-define
  ;; PLAYER holds no symbol of its own: every exported name is a layer's.
  (let ((strays '()))
    (do-external-symbols (symbol '#:player)
      (unless (and (symbol-package symbol)
                   (player-package-p (symbol-package symbol))
                   (not (eq (symbol-package symbol) (find-package '#:player))))
        (push symbol strays)))
    (is (null strays) "PLAYER exports names no layer defines: ~S" strays)))

;;; The test files share one package, PLAYER-TESTS: a helper one file defines
;;; silently replaces another's of the same name (a suite then fails, or worse
;;; passes, far from the cause).  So no two test files may define one name.

(defun test-file-definitions (path)
  "The (NAME . LINE) of each top-level definition in the test file PATH: defun,
defmacro, defgeneric, defstruct, defclass, define-condition, deftype and
defparameter, and a defvar that gives a value (one without is a declaration
another file's definition completes)."
  (with-open-file (in path)
    (loop for line = (read-line in nil)
          for number from 1
          while line
          for start = (and (> (length line) 1) (char= (char line 0) #\()
                           (let ((space (position #\Space line)))
                             (and space (subseq line 1 space))))
          when (and start (member start '("defun" "defmacro" "defgeneric" "defstruct" "defclass"
                                          "define-condition" "deftype" "defparameter" "defvar")
                                  :test #'string-equal))
            nconc (let* ((rest (string-left-trim "( " (subseq line (1+ (length start)))))
                         (end (position-if (lambda (c) (member c '(#\Space #\) #\())) rest))
                         (name (string-downcase (subseq rest 0 end))))
                    (unless (and (string-equal start "defvar")
                                 (string= (string-trim " )" (subseq rest (length name))) ""))
                      (list (cons name number)))))))

(test no-two-test-files-define-one-name
  (let ((homes (make-hash-table :test #'equal)))
    (dolist (path (directory (merge-pathnames "t/*.lisp" *root*)))
      (loop for (name . line) in (test-file-definitions path)
            do (push (format nil "~A:~D" (file-namestring path) line) (gethash name homes))))
    (maphash (lambda (name places)
               (let ((files (remove-duplicates (mapcar (lambda (p) (subseq p 0 (position #\: p))) places)
                                               :test #'string=)))
                 (is (null (rest files)) "~A is defined in ~{~A~^ and ~}: the later load replaces the earlier"
                     name (reverse places))))
             homes)))
