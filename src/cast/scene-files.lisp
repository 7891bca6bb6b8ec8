;;;; scene-files.lisp -- LOAD-SCENE-FILE: a file of DEFSCENE (and DEFSPEC)
;;;; forms, read as data like a spec file (nothing is evaluated).  A member
;;;; naming a spec that is not defined yet is looked for in SPEC.lisp beside
;;;; the scene's file, so specs/two-peedys.lisp can cast specs/peedy.lisp;
;;;; only there: a member's name never leads out of that folder.

(in-package #:player.cast)

(defun defscene-form-p (form)
  "Is FORM a (defscene ...) form?"
  (and (consp form) (eq (first form) 'defscene)))

(defun load-member-specs (form file allow-code)
  "Load, for each member of the DEFSCENE FORM whose spec is not defined, the
spec file beside FILE named after it (peedy: peedy.lisp), when there is one."
  (dolist (member (and (alexandria:proper-list-p form) (cddr form)))
    (when (and (consp member) (symbolp (first member)) (first member)
               (not (scene-event-form-p member))
               (not (scene-set-form-p member))
               (not (find-spec (first member) nil)))
      (let* ((name (string-downcase (symbol-name (first member))))
             (sibling (and (sibling-file-name-p name)
                           (merge-pathnames (make-pathname :name name :type "lisp") file))))
        (when (and sibling (probe-file sibling) (regular-file-p sibling)
                   (equal (pathname-directory (probe-file sibling)) (pathname-directory (probe-file file))))
          (load-spec sibling :allow-code allow-code))))))

(defun sibling-file-name-p (name)
  "May NAME be looked up as NAME.lisp beside a scene file?  Only a plain name:
no / (|../secret| would lead out of the scene's folder), no leading dot, no
wildcard or control character."
  (and (plusp (length name))
       (char/= (char name 0) #\.)
       (notany (lambda (c) (or (find c "/\\*?[") (control-character-p c))) name)))

(defun load-scene-file (file &key (allow-code t))
  "Load FILE, which may hold IN-PACKAGE, DEFSPEC and DEFSCENE forms, as data.
Returns two values: the scenes (CASTs) and the specs it defines, in order.  A
member's spec, when not defined, is loaded from SPEC.lisp beside FILE.
Signals a SPEC-ERROR (or SCENE-ERROR) naming the file and line of the
offending form; unless ALLOW-CODE, a spec holding :code or :c++ is refused."
  (check-argument 'load-scene-file 'file file #'pathname-designator-p *path-phrase*)
  (multiple-value-bind (entries text) (read-data-file file :what "scene file" :fail (spec-file-fail file))
    (let ((file (probe-file file))
          (*defined-specs* '())
          (casts '()))
      (loop for (form position package) in entries
            do (let ((*package* package))
                 (with-spec-context (:source-position (cons file position))
                   (cond ((defspec-form-p form)
                          (let ((rest (rest form)))
                            (define-spec (if (consp rest) (first rest) nil) (if (consp rest) (rest rest) nil)
                                         :source-file file :package package :allow-code allow-code
                                         :form-positions (cddr (list-element-positions text position)))))
                         ((defscene-form-p form)
                          (let ((specs *defined-specs*))
                            (load-member-specs form file allow-code)
                            ;; Specs loaded from beside the file are not this file's own.
                            (setf *defined-specs* specs))
                          (let ((rest (rest form)))
                            (push (define-cast (if (consp rest) (first rest) nil) (if (consp rest) (rest rest) nil)
                                               :source-file file
                                               :form-positions (cddr (list-element-positions text position)))
                                  casts)))
                         (t (spec-fail 'spec-syntax-error form
                                       "a scene file holds only in-package, defspec and defscene forms, not ~A"
                                       (bounded-lisp-text form 60)))))))
      (values (nreverse casts) (reverse *defined-specs*)))))
