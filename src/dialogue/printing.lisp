;;;; printing.lisp -- dialogues and conversations at the REPL: one line each,
;;;; as specs and controllers print (DESCRIBE shows the slots).
;;;;   #<DIALOGUE peedy-dialogue 9 states, 14 inputs, 31 transitions>
;;;;   #<CONVERSATION peedy-dialogue in greeting after 2 turns, 3 events sent>

(in-package #:player.dialogue)

(defmethod print-object ((dialogue dialogue) stream)
  (print-unreadable-object (dialogue stream :type t)
    (format stream "~A ~D state~:P, ~D input~:P, ~D transition~:P"
            (lisp-text (dialogue-name dialogue)) (hash-table-count (dialogue-states dialogue))
            (hash-table-count (dialogue-inputs dialogue)) (length (dialogue-transitions dialogue)))))

(defmethod print-object ((conversation conversation) stream)
  (print-unreadable-object (conversation stream :type t)
    (let ((dialogue (conversation-dialogue conversation)))
      (format stream "~A in ~A after ~D turn~:P, ~D event~:P sent"
              (if (dialogue-p dialogue) (lisp-text (dialogue-name dialogue)) "?")
              (lisp-text (conversation-state conversation)) (conversation-turns conversation)
              (length (conversation-player-events conversation))))))
