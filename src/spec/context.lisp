;;;; context.lisp -- the shared context of parsing: the spec being parsed and
;;;; where the form being read came from, bound in one place.
;;;;
;;;; Parsing functions find the spec they work on in *SPEC*, and the errors they
;;;; signal take their spec name, form label and place from the five variables
;;;; of base/conditions.lisp (a SPEC-ERROR reads them when it is made).  Other
;;;; layers reuse those functions -- for a pose library, a scene, a dialogue --
;;;; and so must set that context; they do it with WITH-SPEC-CONTEXT, never with
;;;; a LET of the variables themselves, so the context has one definition.

(in-package #:player.spec)

(defvar *spec* nil "The spec being parsed.")

(defun call-with-spec-context (function &key (spec nil spec-p) (spec-name nil spec-name-p)
                                             (form-label nil form-label-p)
                                             (source-position nil source-position-p)
                                             (form-places nil form-places-p)
                                             (sub-form-places nil sub-form-places-p))
  "Call FUNCTION with no arguments, with each part of the parsing context given
bound for its dynamic extent and the others left as they are:
SPEC (*SPEC*), the spec whose names parsing functions look up; SPEC-NAME
\(*CURRENT-SPEC-NAME*), the name errors say they are in, or NIL for none;
FORM-LABEL (*CURRENT-FORM-LABEL*), the kind and name of the form being read
\(\"op whistle\"); SOURCE-POSITION (*SOURCE-POSITION*), its (FILE . POSITION);
FORM-PLACES (*FORM-PLACES*), a table from top-level forms to their places;
SUB-FORM-PLACES (*SUB-FORM-PLACES*), the same for the lists inside them.
Returns FUNCTION's values."
  ;; PROGV over the parts given, so a part not given keeps its outer binding.
  (let ((variables '()) (values '()))
    (flet ((part (givenp variable value)
             (when givenp
               (push variable variables)
               (push value values))))
      (part spec-p '*spec* spec)
      (part spec-name-p '*current-spec-name* spec-name)
      (part form-label-p '*current-form-label* form-label)
      (part source-position-p '*source-position* source-position)
      (part form-places-p '*form-places* form-places)
      (part sub-form-places-p '*sub-form-places* sub-form-places))
    (progv variables values
      (funcall function))))

(defmacro with-spec-context ((&rest parts &key spec spec-name form-label source-position
                                               form-places sub-form-places)
                             &body body)
  "Run BODY with the parts of the parsing context given bound, the others left
as they are; see CALL-WITH-SPEC-CONTEXT for the parts (:SPEC, :SPEC-NAME,
:FORM-LABEL, :SOURCE-POSITION, :FORM-PLACES, :SUB-FORM-PLACES).  The parts'
forms are evaluated left to right before any is bound, as in LET."
  (declare (ignore spec spec-name form-label source-position form-places sub-form-places))
  `(call-with-spec-context (lambda () ,@body) ,@parts))
