;;;; utilities.lisp -- the few general helpers every layer shares: lists
;;;; written as "a,b,c", directory designators, and programs found on PATH.

(in-package #:player.base)

(defun split-list (string &key (separator #\,))
  "STRING split at each SEPARATOR, blanks trimmed, empty parts dropped: \"a, b,,c\" is (\"a\" \"b\" \"c\")."
  (loop for part in (uiop:split-string string :separator (string separator))
        for trimmed = (string-trim '(#\Space #\Tab) part)
        unless (string= trimmed "") collect trimmed))

(defun directory-pathname (designator)
  "DESIGNATOR (a pathname, or a native file name with or without a trailing
slash) as a directory pathname merged with *DEFAULT-PATHNAME-DEFAULTS*."
  (merge-pathnames (uiop:ensure-directory-pathname
                    (if (stringp designator) (uiop:parse-native-namestring designator) designator))))

(defun find-executable (name)
  "The truename of the program NAME: NAME itself when it has a slash, else the
first file of that name in a directory of PATH; NIL when there is none."
  (flet ((file (path) (let ((found (probe-file path))) (and found (pathname-name found) found))))
    (if (find #\/ name)
        (file name)
        (loop for directory in (split-list (or (sb-ext:posix-getenv "PATH") "") :separator #\:)
              thereis (file (concatenate 'string (string-right-trim "/" directory) "/" name))))))

(defun load-first-foreign-library (sonames)
  "Load the first of SONAMES (strings: a library's versioned names, best first)
that CFFI can load, and return it; NIL when none can be, so the caller can
signal its own error naming the Debian package to install."
  (some (lambda (soname)
          (handler-case (cffi:load-foreign-library soname)
            (cffi:load-foreign-library-error () nil)))
        sonames))

(defun control-character-p (char)
  "Is CHAR a control character (C0, DEL, C1, or a Unicode line or paragraph
separator): one a terminal or a line-based file obeys instead of showing?"
  (let ((code (char-code char)))
    (or (< code 32) (<= 127 code 159) (= code #x2028) (= code #x2029))))
