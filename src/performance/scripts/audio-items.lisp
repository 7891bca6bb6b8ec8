;;;; audio-items.lisp -- the script items that sound: (:say TEXT) speaks with
;;;; the beak moving, (:sound FILE) plays a sound effect (see the language
;;;; reference at the top of scripts.lisp).

(in-package #:player.performance)

(defstruct (say-item (:include script-item))
  "TEXT spoken by VOICE (or NIL for the default) at RATE words a minute (or
NIL); NAME (or NIL) is what word sync points call it (word-sync.lisp)."
  (name nil :type symbol :read-only t)
  (text "" :type string :read-only t)
  (voice nil :read-only t)
  (rate nil :read-only t))

(defstruct (sound-item (:include script-item))
  "The sound effect read from the WAV file PATH; KIND :music for music
\(ducked under voices), else NIL."
  (path nil :read-only t)
  (sound nil :read-only t)
  (kind nil :read-only t))

;;; Speech and sounds: the text is checked now, spoken when it plays; a sound
;;; file is read now, so a missing one is an error at its line.

(defvar *library-directory* nil
  "While a library is read: the directory its file names (poses, sounds) are relative to.")

(defun parse-say-item (item at arguments)
  "(:at T :say \"TEXT\" [:voice \"VOICE\"] [:rate WPM] [:as NAME] [:for D])."
  (multiple-value-bind (parts options until) (item-parts item arguments 1 '(:voice :rate :as :for))
    (destructuring-bind (&key voice rate (as nil as-given) &allow-other-keys) options
      (when (and as-given (not (usable-name-p as)))
        (script-fail item ":as takes a name for the speech's word sync points, not ~A" (lisp-text as)))
      (unless (and (stringp (first parts)) (<= 1 (length (first parts)) 2000))
        (script-fail item ":say takes the text to speak, a string of 1 to 2000 characters, not ~A"
                     (argument-value-text (first parts))))
      (unless (or (null voice) (and (stringp voice) (< 0 (length voice) 40) (every #'graphic-char-p voice)))
        (script-fail item ":voice must be the name of an espeak-ng voice, such as \"en-us\""))
      (unless (or (null rate) (and (integerp rate) (<= 80 rate 450)))
        (script-fail item ":rate must be an integer from 80 to 450 (words a minute), not ~A"
                     (argument-value-text rate)))
      (make-say-item :at at :until until :form item :text (first parts) :voice voice :rate rate :name as))))

(defun say-item-motor-call (visemes)
  "The :lips call that moves the jaw through VISEMES, ((SECONDS VISEME) ...):
what a :say item drives, so channel and playability checks treat it as one."
  (parse-motor-frame (list :lips :visemes visemes)))

(defun parse-sound-item (item at arguments)
  "(:at T :sound \"FILE.wav\" [:for D]): the file is read now."
  (multiple-value-bind (parts options until) (item-parts item arguments 1 '(:for))
    (declare (ignore options))
    (unless (and (stringp (first parts)) (plusp (length (first parts))))
      (script-fail item ":sound takes a WAV file's name in a string, not ~A" (argument-value-text (first parts))))
    (let ((path (merge-pathnames (first parts) (or *library-directory* *default-pathname-defaults*))))
      (make-sound-item :at at :until until :form item :path path
                       :sound (handler-case (read-wav path)
                                (speech-error (error) (script-fail item "~A" error)))))))
