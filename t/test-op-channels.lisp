;;;; test-op-channels.lisp -- the body channels an op drives, inferred from
;;;; the motor calls of its script (src/performance/op-channels.lisp):
;;;; Peedy's scripts on the parrot body, scripts that play others, directors,
;;;; gaze turning the head as its slave, additive idle noise, the character's
;;;; own placement, declared channel names as joints, and the body presenter's
;;;; per-op answer.

(in-package #:player-tests)

(def-suite* op-channels :in player-tests)

(defun parrot-skeleton ()
  "The shipped parrot skeleton."
  (player::load-skeleton 'parrot))

(defun peedy-scripts-path ()
  "specs/peedy-scripts.lisp in the checkout."
  (checkout-file "specs/peedy-scripts.lisp"))

(defun peedy-library-with (&rest forms)
  "Peedy's script library with FORMS added, read as if from its own file (so
its poses resolve)."
  (player.performance::parse-script-library-forms
   (append (mapcar #'first (player.spec::read-data-file (peedy-scripts-path) :what "script library"))
           forms)
   :source (probe-file (peedy-scripts-path))))

(defun parrot-joints (library name)
  "SCRIPT-JOINTS of NAME in LIBRARY on the parrot."
  (player.performance::script-joints library name (parrot-skeleton)))

(defun role-joints (&rest roles)
  "The lower-case names of the parrot's joints filling ROLES."
  (loop for role in roles
        append (mapcar (lambda (joint) (string-downcase (string (player.body::body-joint-name joint))))
                       (alexandria:ensure-list (player::skeleton-role (parrot-skeleton) role)))))

(defun same-names-p (a b)
  "Do the lists of strings A and B hold the same names?"
  (not (set-exclusive-or a b :test #'string=)))

(defparameter *wing-roles* '(:left-arm :right-arm :left-hand :right-hand)
  "The parrot's wings: the arm chains (shoulder, elbow, wrist) and the primaries.")

(test wing-beats-drive-the-wings-and-nothing-else
  (let ((joints (parrot-joints (peedy-library-with) 'flap-wings)))
    ;; fly-down and fly-up (peedy-poses.lisp) pose both whole wings.
    (is (same-names-p (apply #'role-joints *wing-roles*) joints))
    (is (null (intersection (role-joints :left-eye :right-eye :head) joints :test #'string=)))
    (is (equal joints (sort (copy-list joints) #'string<)) "sorted")))

(test a-blink-drives-only-the-lids
  (let ((library (player.performance::parse-script-library-forms
                  '((defscript just-blink (:duration 2) (:at 0 :motor (:blink)))))))
    (is (equal '("l_lid" "r_lid") (parrot-joints library 'just-blink))))
  ;; look-around: its gazes aim the eyes and, as their slave, turn neck and
  ;; head; its blink closes the lids; nothing else moves.
  (is (equal '("head" "l_eye" "l_lid" "neck" "r_eye" "r_lid")
             (parrot-joints (peedy-library-with) 'look-around))))

(test head-gestures-drive-the-head-chain
  (let ((library (peedy-library-with)))
    (is (equal '("head" "neck") (parrot-joints library 'nod)))
    (is (equal '("head" "neck") (parrot-joints library 'shake-head)))))

(test a-director-drives-what-its-scripts-drive
  (let* ((library (peedy-library-with))
         (look (parrot-joints library 'look-for-note))
         (fetch (parrot-joints library 'fetch-note))
         (stream (parrot-joints library 'stream)))
    (is (same-names-p (union look fetch :test #'string=) stream))
    (is (member "crest" look :test #'string=) "look-for-note raises the crest (:eyebrows on a parrot)")
    (is (not (member "crest" fetch :test #'string=)))
    (is (member "r_shoulder" fetch :test #'string=) "fetch-note reaches with the right wing")
    (is (not (member "r_shoulder" look :test #'string=)))))

(test a-script-drives-what-it-plays
  (let ((library (peedy-library-with
                  '(defscript flap-and-nod (:duration 0.5)
                    (:at 0 :play flap-wings :for 0.4)
                    (:at 0 :motor (:head :action :nod :duration 0.5))))))
    (is (same-names-p (union (parrot-joints library 'flap-wings) '("head" "neck") :test #'string=)
                      (parrot-joints library 'flap-and-nod)))))

(test idle-noise-and-camera-moves-drive-no-joint
  (let ((library (peedy-library-with
                  '(defscript fidget (:duration 1) (:at 0 :motor (:idle :joints (:head :tail)))))))
    (is (null (parrot-joints library 'fidget)) "additive noise owns no channel")
    (is (null (parrot-joints library 'camhello)) "it moves the camera, not Peedy")))

(test moving-the-character-is-the-root-pseudo-channel
  (let ((library (peedy-library-with)))
    (is (member "root" (parrot-joints library 'sit) :test #'string=) "sit animates (:self position)")
    (is (member "parrot-root" (parrot-joints library 'sit) :test #'string=) "and keys the root joint")
    (is (not (member "root" (parrot-joints library 'flap-wings) :test #'string=)))))

(test every-peedy-script-and-director-fits-the-parrot
  (let ((library (peedy-library-with))
        (skeleton (parrot-skeleton)))
    (dolist (definition (player.performance::script-library-definitions library))
      (let* ((name (if (player.performance::script-p definition)
                       (player.performance::script-name definition)
                       (player.performance::director-name definition)))
             (joints (player.performance::script-joints library name skeleton)))
        (is (every (lambda (joint) (or (string= joint "root") (player::find-joint skeleton joint)))
                   joints)
            "~A: every name is a joint of the parrot (or root)" name)
        (unless (member name '(camhello camgoodbye camwide) :test #'string-equal)
          (is (consp joints) "~A drives something" name))))))

(test unknown-scripts-are-script-errors
  (signals player::script-error (parrot-joints (peedy-library-with) 'no-such-script)))

(test declared-channel-names-become-joints
  (let ((skeleton (parrot-skeleton)))
    (is (equal '("l_elbow" "l_shoulder" "l_wrist") (player.performance::expand-channel-names '(:left-arm) skeleton))
        "a role becomes its joints")
    (is (equal '("head" "neck") (player.performance::expand-channel-names '(spine) skeleton)))
    (is (equal '("l_eye" "r_eye") (player.performance::expand-channel-names '("eyes") skeleton))
        "a plural of a left and right role becomes both sides")
    (is (equal '("l_lid" "r_lid") (player.performance::expand-channel-names '(upper-lids) skeleton)))
    (is (equal '("beak" "l_eye") (player.performance::expand-channel-names '("L_EYE" jaw) skeleton))
        "a joint stays, lower-case; the jaw role is the beak")
    (is (equal '("tail" "wings") (player.performance::expand-channel-names '(wings tail wings) skeleton))
        "a made-up name stays as it is, once")
    (is (null (player.performance::expand-channel-names '() skeleton)))))

(test body-presenters-answer-per-op
  (let* ((spec (peedy-body-spec))
         (presenter (make-body-presenter spec :stream nil))
         (library (player.performance::presenter-library presenter)))
    (flet ((op (name) (find name (player.spec::spec-ops spec) :key #'op-name :test #'string-equal)))
      (is (equal (parrot-joints library 'nod) (player.performance::op-joints presenter (op 'nod))))
      (is (equal (parrot-joints library 'stream) (player.performance::op-joints presenter (op 'search)))
          "search plays the director stream")
      (is (null (player.performance::op-joints presenter (op 'celebrate))) "a macro op plays no script")
      (is (eq (player.performance::op-joints presenter (op 'greet)) (player.performance::op-joints presenter (op 'greet)))
          "worked out once"))))
