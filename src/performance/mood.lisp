;;;; mood.lisp -- setting a character's mood on a running performance, the hook
;;;; a dialogue's emotion reaches the body by (Persona's (mood NAME) action):
;;;; from then on its gestures are performed bigger and faster, or smaller
;;;; and slower (src/body/mood.lisp).  Like a script's :set item, so a replay
;;;; from the start sets it again at the same time.

(in-package #:player.performance)

(defun performance-set-mood (performance mood &key (at 0) body)
  "Set the mood of BODY (default: the first character) of PERFORMANCE from AT
seconds: MOOD is a number from -1 (sad) to 1 (happy), or an emotion's name
\(HAPPY, SAD, ...: EMOTION-MOOD).  Returns the number set and the SCRIPT-RUN."
  (check-argument 'performance-set-mood 'performance performance #'performance-p "a performance (from make-performance)")
  (check-argument 'performance-set-mood 'mood mood
                  (lambda (x) (or (and (realp x) (<= -1 x 1)) (and x (symbolp x)) (stringp x)))
                  "a number from -1 to 1, or an emotion's name (a symbol or string)")
  (check-seconds 'performance-set-mood :at at :minimum 0)
  (when body (check-body-name 'performance-set-mood performance body))
  (let* ((value (if (realp mood) (float mood 1d0) (emotion-mood mood)))
         (item (make-set-item :at 0d0 :form (list :at 0 :set '(:self mood) value)
                              :object :self :property 'mood :value value))
         (script (%make-script :name (make-symbol "MOOD") :duration 0d0 :items (list item)
                               :form (list :mood mood))))
    (values value
            (add-script-run performance
                            (make-script-run script (float at 1d0) nil
                                             (or body (performance-character performance)) nil)))))
