;;;; op-channels.lisp -- which body channels an op drives, for a timed controller
;;;; that plays two events in parallel when their ops drive disjoint channels.
;;;; An op's channels are the joints of the script (or director) it plays: the
;;;; motor calls of the script and of every script it plays or starts, each set
;;;; up as a real driver on a scratch body, so the answer is exactly what
;;;; arbitration would see.  Declared :channels names become joints here too.

(in-package #:player.performance)

;;;# What a driver may drive

(defparameter *self-channel* "root"
  "The pseudo-channel of a script that moves the character itself (an :animate,
:set or :attach of :self): not a joint, but two ops that both place the
character conflict as surely as two that turn its head.")

(defgeneric potential-slave-channels (driver)
  (:documentation "The pose indices DRIVER's slaves may drive.  SLAVE-DRIVERS
only exist after DRIVER-BEGIN, and whether a driver makes one depends on the
scene at its start, so this is every channel its slaves could request.")
  (:method ((driver driver))
    nil))

(defmethod potential-slave-channels ((driver gaze-driver))
  ;; As GAZE-DRIVER's DRIVER-BEGIN: the head chain, with the trunk for a big shift;
  ;; a head that cannot aim makes no slave.
  (and (skeleton-role (driver-skeleton driver) :head)
       (handler-case (aim-link-channels (head-chain driver :trunk-yaw-share *gaze-trunk-yaw-share*))
         (motor-error () nil))))

(defun driver-reachable-channels (driver)
  "The pose indices DRIVER moves, its possible slaves' too; NIL for idle noise
and idle life, which an op never claims (a nod, additive, still claims the head)."
  (if (driver-background-p driver)
      '()
      (union (driver-channels driver) (potential-slave-channels driver))))

;;;# Walking a script

(defun definition-items (library name)
  "The items of LIBRARY's script NAME, or for a director the names of the scripts
it starts, as two values; a SCRIPT-ERROR when NAME is neither."
  (let ((script (find-script library name)))
    (if script
        (values (script-items script) '())
        (let ((director (or (find-director library name)
                            (find-script library name t))))
          (values '() (loop for step in (director-steps director)
                            when (start-step-p step) collect (start-step-script step)))))))

(defun self-item-p (item)
  "Does ITEM place the character playing its script (:animate, :set or :attach of :self)?"
  (typecase item
    (animate-item (eq (animate-item-object item) :self))
    (set-item (eq (set-item-object item) :self))
    (attach-item (eq (attach-item-object item) :self))))

(defun script-reach (library name)
  "What playing the script or director NAME of LIBRARY does to its character: the
MOTOR-CALLs of it and of every script it plays or starts, each once, in order,
and as a second value whether any of them places the character itself."
  (let ((seen '()) (calls '()) (self nil))
    (labels ((walk (name)
               (unless (member name seen :test #'name=)
                 (push name seen)
                 (multiple-value-bind (items started) (definition-items library name)
                   (dolist (item items)
                     (typecase item
                       (motor-item (push (motor-item-call item) calls))
                       (say-item (push (say-item-motor-call '((0 :rest))) calls))
                       (play-item (walk (play-item-script item))))
                     (when (self-item-p item)
                       (setf self t)))
                   (mapc #'walk started)))))
      (walk name))
    (values (nreverse calls) self)))

;;;# Channels as joints

(defun joint-text (joint)
  "JOINT's name as a lower-case string."
  (string-downcase (string (body-joint-name joint))))

(defun channel-joint-names (skeleton channels)
  "The names of the joints of SKELETON owning the pose indices CHANNELS, sorted."
  (sort (remove-duplicates (mapcar (lambda (index)
                                     (let ((joint (skeleton-dof skeleton index)))
                                       (if joint
                                           (joint-text joint)
                                           ;; A morph target's weight: no joint owns it.
                                           (format nil "morph ~A" (svref (skeleton-morphs skeleton)
                                                                         (- index (skeleton-dof-count skeleton)))))))
                                   channels)
                           :test #'string=)
        #'string<))

(defun scratch-body (library skeleton poses)
  "A body of SKELETON in no scene for setting drivers up, finding poses in POSES,
else in LIBRARY's (poses FILE), else in the shipped library."
  (let ((body (make-body "scratch" skeleton))
        (poses (or poses
                   (and (script-library-poses library)
                        (load-pose-library (script-library-poses library) :skeleton skeleton
                                                            :fallback (shipped-pose-library skeleton))))))
    (when poses
      (setf (body-pose-library body) poses))
    body))

(defun script-joints (library name skeleton &key poses)
  "The sorted names (lower-case strings) of the joints whose DOFs the script or
director NAME of LIBRARY drives on a body of SKELETON: the channels every motor
call of it, and of every script it plays or starts, requests when set up on
such a body, the head a gaze may turn as its slave included, an additive call
(:idle) adding none.  When it also moves the character itself (:animate, :set
or :attach of :self) the list has *SELF-CHANNEL* too.  POSES is the pose
library the calls find poses in (default: LIBRARY's).  Signals SCRIPT-ERROR for
an unknown NAME, MOTOR-ERROR for a call SKELETON cannot perform."
  (check-argument 'script-joints 'library library #'script-library-p "a script library (from load-script-library)")
  (check-argument 'script-joints 'name name #'string-designator-p "a script's or director's name (a symbol or string)")
  (check-argument 'script-joints 'skeleton skeleton #'skeleton-p "a skeleton (from load-skeleton)")
  (multiple-value-bind (calls self) (script-reach library name)
    (let ((body (scratch-body library skeleton poses)))
      (merge 'list
             (channel-joint-names skeleton
                                  (reduce #'union calls
                                          :key (lambda (call) (driver-reachable-channels (make-driver call body 0)))
                                          :initial-value '()))
             (and self (list *self-channel*))
             #'string<))))

;;;# Ops

(defvar *script-joints-cache* (make-hash-table :test #'eq :weakness :key :synchronized t)
  "Per script library (weakly): an EQUAL table from (SKELETON NAME), NAME
lower-case, to SCRIPT-JOINTS' answer.")

(defun cached-script-joints (library name skeleton poses)
  "SCRIPT-JOINTS of NAME in LIBRARY on SKELETON, worked out once."
  (let* ((table (or (gethash library *script-joints-cache*)
                    (setf (gethash library *script-joints-cache*)
                          (make-hash-table :test #'equal :synchronized t))))
         (key (list skeleton (string-downcase (string name)))))
    (multiple-value-bind (joints found) (gethash key table)
      (if found
          joints
          (setf (gethash key table) (script-joints library name skeleton :poses poses))))))

(defun op-joints (presenter op)
  "The joints (see SCRIPT-JOINTS) of the script or director OP plays on the
character of the body presenter PRESENTER; NIL for a :code or macro op.
Worked out once per library and script."
  (check-argument 'op-joints 'presenter presenter (lambda (x) (typep x 'body-presenter))
                  "a body presenter (from make-body-presenter)")
  (check-argument 'op-joints 'op op #'op-def-p "an op of a spec")
  (let ((name (op-script-name op)))
    (when name
      (let ((performance (presenter-performance presenter)))
        (cached-script-joints (performance-library performance) name
                              (character-spec-skeleton (first (performance-characters performance)))
                              (performance-poses performance))))))

;;;# Declared channels

(defun role-keyword (name)
  "The role of *SKELETON-ROLES* called NAME (a lower-case string), or NIL."
  (car (find name *skeleton-roles* :key (lambda (entry) (string-downcase (string (car entry))))
                                   :test #'string=)))

(defun role-joint-names (skeleton name)
  "The names of the joints filling SKELETON's role NAME, or NIL when it fills no such role."
  (let ((role (role-keyword name)))
    (and role (mapcar #'joint-text (ensure-list (skeleton-role skeleton role))))))

(defun paired-role-joint-names (skeleton name)
  "For a plural NAME such as \"eyes\" or \"arms\": the joints of the left and
right roles it names (left-eye and right-eye), when SKELETON fills both; else NIL."
  (loop for stem in (remove-duplicates
                     (list name (and (> (length name) 1) (char= (char name (1- (length name))) #\s)
                                     (subseq name 0 (1- (length name)))))
                     :test #'equal)
        for left = (and stem (role-joint-names skeleton (format nil "left-~A" stem)))
        for right = (and stem (role-joint-names skeleton (format nil "right-~A" stem)))
        when (and left right) return (append left right)))

(defun expand-channel-name (name skeleton)
  "The joint names the declared channel NAME (a lower-case string) stands for."
  (let ((joint (find-joint skeleton name)))
    (cond (joint (list (joint-text joint)))
          ((role-joint-names skeleton name))
          ((paired-role-joint-names skeleton name))
          (t (list name)))))

(defun expand-channel-names (names skeleton)
  "The declared channel NAMES (symbols or strings) as sorted lower-case joint
names of SKELETON: a joint's name stays; a role it fills (head, left-arm, spine)
becomes its joints, and so does a plural of a left and right role (eyes, arms,
legs: both sides); any other name stays as it is, lower-case, so two ops
declaring the same made-up name still conflict."
  (check-argument 'expand-channel-names 'names names
                  (lambda (x) (and (alexandria:proper-list-p x) (every #'string-designator-p x)))
                  "a list of channel names (symbols or strings)")
  (check-argument 'expand-channel-names 'skeleton skeleton #'skeleton-p "a skeleton (from load-skeleton)")
  (sort (remove-duplicates (loop for name in names
                                 append (expand-channel-name (string-downcase (string name)) skeleton))
                           :test #'string=)
        #'string<))

;;;# What a timed controller asks

(defun presenter-skeleton (presenter)
  "The skeleton of body presenter PRESENTER's character."
  (character-spec-skeleton (first (performance-characters (presenter-performance presenter)))))

(defmethod op-channel-set ((presenter body-presenter) op)
  ;; Declared channels win (as joints where they name joints or roles); else
  ;; the joints its script drives; a :code op may do anything.
  (cond ((op-channels op) (expand-channel-names (op-channels op) (presenter-skeleton presenter)))
        ((member (op-kind op) '(:code :macro)) :all)
        (t (op-joints presenter op))))
