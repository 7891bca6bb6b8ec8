;;;; expressions.lisp -- the predicates of transitions and templates (Figure 8's
;;;; cnt0=1), over context variables and episodic memory.
;;;; An expression is a number, a string or a keyword (itself); a name (the
;;;; context variable's value, NIL when unset; `mood` is the remembered mood);
;;;; (= A B), (/= A B), (< A B), (<= A B), (> A B), (>= A B); (and E...),
;;;; (or E...), (not E); (streak EV): how many of the latest inputs in a row
;;;; were EV, this one included; (count EV): how often EV came this
;;;; conversation; (asked-before VAR): did an earlier input carry VAR's value
;;;; in the slot VAR (a repeated request, in this conversation or an earlier one).

(in-package #:player.dialogue)

(defparameter *expression-operators*
  '(("=" 2) ("/=" 2) ("<" 2) ("<=" 2) (">" 2) (">=" 2)
    ("AND" nil) ("OR" nil) ("NOT" 1) ("STREAK" 1) ("COUNT" 1) ("ASKED-BEFORE" 1))
  "Operators of dialogue expressions, with their argument counts (NIL: any).")

(defun check-expression (expression form)
  "Signal a DIALOGUE-ERROR naming FORM unless EXPRESSION is well formed."
  (cond ((or (realp expression) (stringp expression) (keywordp expression)))
        ((symbolp expression))
        ((not (and (alexandria:proper-list-p expression) (symbolp (first expression))))
         (dialogue-fail form "~A is not an expression" (bounded-lisp-text expression 80)))
        (t (let ((entry (assoc (dialogue-key (first expression)) *expression-operators* :test #'string=)))
             (unless entry
               (dialogue-fail form "unknown operator ~A in ~A (known: ~{~(~A~)~^ ~})"
                              (display-name (first expression)) (bounded-lisp-text expression 80)
                              (mapcar #'first *expression-operators*)))
             (when (and (second entry) (/= (second entry) (length (rest expression))))
               (dialogue-fail form "~A takes ~D argument~:P, in ~A" (display-name (first expression))
                              (second entry) (bounded-lisp-text expression 80)))
             (if (member (first entry) '("STREAK" "COUNT" "ASKED-BEFORE") :test #'string=)
                 (unless (and (symbolp (second expression)) (second expression))
                   (dialogue-fail form "~A needs a name, in ~A" (display-name (first expression))
                                  (bounded-lisp-text expression 80)))
                 (dolist (argument (rest expression))
                   (check-expression argument form)))))))

(defun dialogue-equal (a b)
  "Are A and B the same value?  Numbers by =, strings without regard to case."
  (if (and (realp a) (realp b)) (= a b) (equalp a b)))

(defun evaluate-expression (expression conversation)
  "The value of EXPRESSION (checked by CHECK-EXPRESSION) in CONVERSATION."
  (cond ((or (realp expression) (stringp expression) (keywordp expression) (null expression)) expression)
        ((eq expression t) t)
        ((symbolp expression) (context-value conversation expression))
        (t (let ((operator (dialogue-key (first expression)))
                 (arguments (rest expression)))
             (flet ((value (e) (evaluate-expression e conversation))
                    (compare (test)
                      (let ((a (evaluate-expression (first arguments) conversation))
                            (b (evaluate-expression (second arguments) conversation)))
                        (and (realp a) (realp b) (funcall test a b)))))
               (alexandria:switch (operator :test #'string=)
                 ("=" (dialogue-equal (value (first arguments)) (value (second arguments))))
                 ("/=" (not (dialogue-equal (value (first arguments)) (value (second arguments)))))
                 ("<" (compare #'<)) ("<=" (compare #'<=)) (">" (compare #'>)) (">=" (compare #'>=))
                 ("AND" (every #'value arguments))
                 ("OR" (some #'value arguments))
                 ("NOT" (not (value (first arguments))))
                 ("STREAK" (memory-streak (conversation-memory conversation) (first arguments)))
                 ("COUNT" (memory-count (conversation-memory conversation) (first arguments)))
                 ("ASKED-BEFORE" (let ((value (context-value conversation (first arguments))))
                                   (and value (memory-asked-before-p (conversation-memory conversation)
                                                                     (first arguments) value))))))))))
