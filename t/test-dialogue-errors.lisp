;;;; test-dialogue-errors.lisp -- bad dialogues are errors naming the form:
;;;; unknown states, empty template categories, probabilities outside 0..1,
;;;; Player events the spec lacks, and the rest; from a file, with its line.

(in-package #:player-tests)

(def-suite* dialogue-errors :in player-tests)

(defparameter *dialogue-base*
  '((:player dlg-mini)
    (state stA) (state stB)
    (input evGo) (input evHuh)
    (utterance evGo "go")
    (animation peGo ev-go)
    (template hi 1 "hi"))
  "A small dialogue the error cases add one bad form to.")

(defmacro with-dialogue-spec (&body body)
  "Run BODY with the Player spec DLG-MINI (events ev-go, ev-stop) defined."
  `(with-spec (spec dlg-mini (state-variable on boolean false)
                    (op start :add on) (op halt :sub on)
                    (event ev-go :op start) (event ev-stop :op halt))
     spec
     ,@body))

(defun dialogue-error-text (&rest forms)
  "The report of the DIALOGUE-ERROR defining *DIALOGUE-BASE* plus FORMS signals, or NIL."
  (handler-case (progn (define-dialogue 'dlg-bad (append *dialogue-base* forms)) nil)
    (dialogue-error (e) (princ-to-string e))))

(defmacro check-dialogue-error (fragment &rest forms)
  "Defining the base dialogue plus FORMS must signal a DIALOGUE-ERROR whose report has FRAGMENT."
  `(let ((text (dialogue-error-text ,@(mapcar (lambda (f) `',f) forms))))
     ;; Forms read at the REPL are upper case: compare without regard to case.
     (is (and text (search ,fragment text :test #'char-equal)) "~S gave ~S, not ~S" ',forms text ,fragment)))

(test the-base-dialogue-is-fine
  (with-dialogue-spec
    (is (null (dialogue-error-text '(on stA evGo :to stB :do ((do peGo) (say hi))))))))

(test bad-dialogues-are-errors-naming-the-form
  (with-dialogue-spec
    (check-dialogue-error "unknown conversational state stC" (on stA evGo :to stC))
    (check-dialogue-error "unknown conversational state stNowhere" (on stNowhere evGo))
    (check-dialogue-error "(say bye): the template category bye has no templates" (on stA evGo :do ((say bye))))
    (check-dialogue-error "template probability 1.5 is outside 0..1" (template hi 1.5 "hello"))
    (check-dialogue-error "template probability -0.1 is outside 0..1" (template hi -0.1 "hello"))
    (check-dialogue-error "template probability many is outside 0..1" (template hi many "hello"))
    (check-dialogue-error "(do ev-nope): ev-nope is neither an animation of the dialogue nor an event of Player spec dlg-mini"
                          (on stA evGo :do ((do ev-nope))))
    (check-dialogue-error "dialogue dlg-bad, animation peNope: ev-nope is not an event of Player spec dlg-mini" (animation peNope ev-nope))
    (check-dialogue-error "unknown input event evNope" (on stA evNope))
    (check-dialogue-error "unknown input event evNope" (utterance evNope "nope"))
    (check-dialogue-error "unknown action frobnicate" (on stA evGo :do ((frobnicate))))
    (check-dialogue-error "action say takes 1 argument, not 2" (on stA evGo :do ((say hi hi))))
    (check-dialogue-error "unknown operator ~ in" (on stA evGo :if (~ cnt0 1)))
    (check-dialogue-error "unknown slot colour" (utterance evGo "paint it" (:slot colour)))
    (check-dialogue-error "state stA is declared twice" (state stA))
    (check-dialogue-error "unknown dialogue form banana" (banana 1))
    (check-dialogue-error ":limit must be :conversation or :user" (template hi 1 "x" :limit :week))
    (check-dialogue-error "unknown action nothing" (input evMore :query ((nothing))))))

(test a-missing-player-spec-or-state-is-an-error
  (is (search "no Player spec dlg-nowhere is defined"
              (handler-case (define-dialogue 'dlg-bad '((:player dlg-nowhere) (state a)))
                (dialogue-error (e) (princ-to-string e)))))
  (is (search "unknown conversational state b"
              (handler-case (define-dialogue 'dlg-bad '((:initial b) (state a)))
                (dialogue-error (e) (princ-to-string e)))))
  (is (search "a dialogue needs at least one (state NAME)"
              (handler-case (define-dialogue 'dlg-bad '())
                (dialogue-error (e) (princ-to-string e))))))

(defun dialogue-file-error (text)
  "The report of loading the dialogue file TEXT, or NIL when it loads."
  (uiop:with-temporary-file (:pathname path :stream out :type "lisp")
    (write-string text out)
    :close-stream
    (handler-case (progn (load-dialogue path) nil)
      (dialogue-error (e) (princ-to-string e)))))

(test errors-in-a-file-name-its-line
  (with-dialogue-spec
    (let ((text (dialogue-file-error "(in-package :player-user)
(defdialogue d
  (:player dlg-mini)
  (state stA)
  (input evGo)
  (on stA evGo :to stGotCD))
")))
      (is (search ":6: on stA: unknown conversational state stGotCD (known: stA)" text) "~S" text))
    (let ((text (dialogue-file-error "(defdialogue d (:player dlg-mini) (state stA) (input evGo)
  (template x 2 \"two\"))")))
      (is (search ":2: template x: template probability 2 is outside 0..1" text) "~S" text))
    ;; Data, never code.
    (is (search ":1: cannot read form" (dialogue-file-error "#.(delete-file \"x\")")))
    (is (search "holds only in-package and defdialogue forms" (dialogue-file-error "(defun f () 1)")))))
