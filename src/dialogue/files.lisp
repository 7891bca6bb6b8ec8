;;;; files.lisp -- LOAD-DIALOGUE: a dialogue file is data, as a spec file is.
;;;; It may hold only in-package and defdialogue forms, read with the readtable
;;;; case :INVERT (so the paper's stGotCD keeps its spelling) and never
;;;; evaluated; the Player spec and catalogue it names are read as data too.

(in-package #:player.dialogue)

(defun load-dialogue (file)
  "Load the dialogue file FILE and return the dialogues it defines, in order.
Nothing in it is evaluated.  Signals a DIALOGUE-ERROR (a SPEC-ERROR) naming
the file and line of the offending form."
  (multiple-value-bind (entries text)
      (read-data-file file :what "dialogue file" :readtable *dialogue-readtable*
                           :fail (lambda (position message &optional kind)
                                   (declare (ignore kind))
                                   (error 'dialogue-error :position (and position (cons file position))
                                                          :spec nil :form nil :message message)))
    (let ((file (probe-file file)))
      (loop for (form position) in entries
            collect (with-spec-context (:source-position (cons file position))
                      (unless (form-head-p form "defdialogue")
                        (dialogue-fail form "a dialogue file holds only in-package and defdialogue forms, not ~A"
                                       (bounded-lisp-text form 60)))
                      (unless (and (alexandria:proper-list-p form) (cdr form))
                        (dialogue-fail form "expected (defdialogue NAME FORM...)"))
                      (define-dialogue (second form) (cddr form)
                                       :source-file file
                                       ;; DEFDIALOGUE and NAME come first.
                                       :form-positions (cddr (list-element-positions text position))))))))
