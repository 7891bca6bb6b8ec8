;;;; cpp-resources.lisp -- the fixed C++ the generator copies into every
;;;; controller (helpers, the timed layer's runtime, the test drivers) lives in
;;;; real .hpp and .cpp files in resources/, beside this file, where an editor
;;;; and a compiler's eye can read it; only the code that depends on a machine
;;;; is written by emit functions in Lisp.

(in-package #:player.cpp)

(defparameter *c++-resources-directory*
  (merge-pathnames "resources/" #.(or *compile-file-truename* *load-truename*))
  "Where the fixed C++ files live: the directory resources/ beside this source
file, fixed when it is compiled.")

(defun c++-resource (name)
  "The text of the fixed C++ file NAME (\"timeline-clock.cpp\") in
*C++-RESOURCES-DIRECTORY*, without the newline that ends the file.  Signals a
PLAYER-ERROR naming the file when it is missing or unreadable."
  (let* ((path (merge-pathnames name *c++-resources-directory*))
         (text (handler-case (read-file-into-string path :external-format :utf-8)
                 (error (e)
                   (error 'player-error-with-message
                          :message (format nil "cannot read Player's C++ resource ~A (~A): is Player's src/cpp/resources/ complete?"
                                           (native-namestring path) (condition-reason e)))))))
    ;; Files end with a newline, as editors write them; the text is what comes before it.
    (if (and (plusp (length text)) (char= (char text (1- (length text))) #\Newline))
        (subseq text 0 (1- (length text)))
        text)))

(defun emit-resource (name)
  "Write the fixed C++ file NAME as it is, and a newline (see C++-RESOURCE)."
  (emit-text (c++-resource name)))
