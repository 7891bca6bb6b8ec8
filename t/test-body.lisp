;;;; test-body.lisp -- the body model: skeleton files and channel arbitration.
;;;; Arbitration is checked as a property against PLAIN-ARBITER, a list-based
;;;; model of the rule "the owner is the best active request" written here.

(in-package #:player-tests)

(def-suite* body :in player-tests)

;;; ---------------------------------------------------------------------------
;;; Skeletons

(defparameter *h-anim-loa1*
  '((humanoid-root nil (0 0.8240 0.0277))
    (sacroiliac humanoid-root (0 0.9149 0.0016))
    (l_hip sacroiliac (0.0961 0.9124 -0.0001))
    (l_knee l_hip (0.1040 0.4867 0.0308))
    (l_ankle l_knee (0.1101 0.0656 -0.0736))
    (l_midtarsal l_ankle (0.1086 0.0001 0.0368))
    (r_hip sacroiliac (-0.0950 0.9171 0.0029))
    (r_knee r_hip (-0.0867 0.4913 0.0318))
    (r_ankle r_knee (-0.0801 0.0712 -0.0766))
    (r_midtarsal r_ankle (-0.0801 0 0.0368))
    (vl5 humanoid-root (0.0028 1.0568 -0.0776))
    (skullbase vl5 (0.0044 1.6209 0.0236))
    (l_shoulder vl5 (0.2029 1.4376 -0.0387))
    (l_elbow l_shoulder (0.2014 1.1357 -0.0682))
    (l_wrist l_elbow (0.1984 0.8663 -0.0583))
    (r_shoulder vl5 (-0.1907 1.4407 -0.0325))
    (r_elbow r_shoulder (-0.1949 1.1388 -0.0620))
    (r_wrist r_elbow (-0.1959 0.8694 -0.0521)))
  "The H-Anim LOA-1 joints: name, parent, centre in metres.")

(defun skeleton-from (&rest clauses)
  "A skeleton parsed from CLAUSES, a tiny valid body (root, child) prepended."
  (player.body::parse-skeleton
   `(skeleton test
      (:joint root :parent nil :center (0 0 0) :dofs ((:x -10 10)))
      (:joint child :parent root :center (0 1 0))
      ,@clauses)))

(test shipped-skeletons-load
  (dolist (name '(humanoid parrot))
    (let ((skeleton (player::load-skeleton name)))
      (is (typep skeleton 'player.body::skeleton))
      (is (string-equal (string name) (string (player.body::skeleton-name skeleton))))))
  (is (string-equal "PARROT" (player.body::skeleton-name (player::load-skeleton "parrot")))))

(test humanoid-h-anim-centres-and-hierarchy
  (let ((skeleton (player::load-skeleton 'humanoid)))
    (loop for (name parent centre) in *h-anim-loa1*
          for joint = (player::find-joint skeleton name)
          do (is-true joint "joint ~A is missing" name)
             (when joint
               ;; Exact to the 0.1 mm of the table: the file is read as double-floats.
               (is (every (lambda (x y) (< (abs (- (rational x) (rational y))) 1/1000000))
                          centre (coerce (player.body::body-joint-center joint) 'list))
                   "joint ~A's centre" name)
               (is (string-equal (string (or parent ""))
                                 (string (or (player.body::body-joint-parent-name joint) "")))
                   "joint ~A's parent" name)))
    (is (string-equal "HUMANOID-ROOT"
                      (player.body::body-joint-name (player.body::skeleton-root skeleton))))
    ;; Five finger curls a hand, and eyes, lids, brows and jaw.
    (dolist (role '(:left-fingers :right-fingers))
      (let ((fingers (player::skeleton-role skeleton role)))
        (is (= 5 (length fingers)))
        (is (every (lambda (finger) (player.body::body-joint-dof finger 'curl)) fingers))))))

(test skeleton-joints-parent-before-child
  (dolist (name '(humanoid parrot))
    (let ((joints (player::skeleton-joints (player::load-skeleton name))))
      (is (null (player.body::body-joint-parent (svref joints 0))))
      (is (loop for joint across joints
                for index from 0
                always (and (= index (player.body::body-joint-index joint))
                            (or (zerop index)
                                (< (player.body::body-joint-index (player.body::body-joint-parent joint))
                                   index))))))))

(test skeleton-roles-resolve
  (let ((humanoid (player::load-skeleton 'humanoid))
        (parrot (player::load-skeleton 'parrot)))
    (dolist (role '(:head :left-eye :right-eye :left-upper-lid :right-upper-lid
                    :left-brow :right-brow :jaw :left-arm :right-arm :left-hand
                    :right-hand :left-fingers :right-fingers :spine))
      (is-true (player::skeleton-role humanoid role) "humanoid role ~A" role))
    (dolist (role '(:head :left-eye :right-eye :left-upper-lid :right-upper-lid
                    :jaw :crest :tail :left-arm :right-arm :left-hand :right-hand
                    :left-leg :right-leg :spine))
      (is-true (player::skeleton-role parrot role) "parrot role ~A" role))
    (is (equal '("L_SHOULDER" "L_ELBOW" "L_WRIST")
               (mapcar (lambda (j) (symbol-name (player.body::body-joint-name j)))
                       (player::skeleton-role humanoid :left-arm))))
    (is (string-equal "SKULLBASE"
                      (player.body::body-joint-name (player::skeleton-role humanoid :head))))
    (is (string-equal "BEAK" (player.body::body-joint-name (player::skeleton-role parrot :jaw))))))

(test skeleton-limits-sane
  (dolist (name '(humanoid parrot))
    (let ((skeleton (player::load-skeleton name)))
      (is (every (lambda (joint)
                   (every (lambda (dof)
                            (<= -180 (player.body::body-dof-min dof) (player.body::body-dof-max dof) 180))
                          (player.body::body-joint-dofs joint)))
                 (player::skeleton-joints skeleton)))
      (is (every (lambda (joint) (plusp (player.body::body-joint-radius joint)))
                 (player::skeleton-joints skeleton)))))
  (let* ((humanoid (player::load-skeleton 'humanoid))
         (knee (player::find-joint humanoid "l_knee"))
         (flexion (player.body::body-joint-dof knee :x)))
    (is (= 0 (player.body::body-dof-min flexion)))
    (is (= 135 (player.body::body-dof-max flexion))))
  ;; The parrot is about 0.35 m tall.
  (let ((heights (map 'list (lambda (joint) (svref (player.body::body-joint-center joint) 1))
                      (player::skeleton-joints (player::load-skeleton 'parrot)))))
    (is (< 0.25 (- (reduce #'max heights) (reduce #'min heights)) 0.4))))

(test skeleton-channels
  (let ((channels (player.body::skeleton-channels (skeleton-from))))
    (is (= 1 (length channels)))
    (is (string-equal "ROOT" (car (first channels))))
    (is (eq :x (cdr (first channels))))))

(defmacro signals-skeleton-error ((&optional (text nil)) &body body)
  "Check that BODY signals a SKELETON-ERROR (a SPEC-ERROR) whose report contains TEXT."
  `(let ((condition (handler-case (progn ,@body nil)
                      (player::skeleton-error (c) c))))
     (is (typep condition 'player::skeleton-error) "no skeleton-error from ~S" ',body)
     (when condition
       (is (typep condition 'player-error))
       (is (typep condition 'spec-error))
       ,@(when text
           `((is (search ,text (princ-to-string condition))
                 "~S does not mention ~S" (princ-to-string condition) ,text))))))

(test skeleton-errors
  (signals-skeleton-error ("unknown parent")
    (skeleton-from '(:joint hand :parent arm :center (0 0 0))))
  (signals-skeleton-error ("defined twice")
    (skeleton-from '(:joint child :parent root :center (0 0 0))))
  (signals-skeleton-error ("cycle")
    (skeleton-from '(:joint a :parent b :center (0 0 0))
                   '(:joint b :parent a :center (0 0 0))))
  (signals-skeleton-error ("limits")
    (skeleton-from '(:joint a :parent root :center (0 0 0) :dofs ((:x 10 -10)))))
  (signals-skeleton-error ("limits")
    (skeleton-from '(:joint a :parent root :center (0 0 0) :dofs ((:y -200 10)))))
  (signals-skeleton-error ("unknown axis")
    (skeleton-from '(:joint a :parent root :center (0 0 0) :dofs ((:w 0 10)))))
  (signals-skeleton-error ("not a joint")
    (skeleton-from '(:role :head nose)))
  (signals-skeleton-error ("unknown role")
    (skeleton-from '(:role :nose child)))
  (signals-skeleton-error ("chain")
    (skeleton-from '(:joint a :parent root :center (0 0 0))
                   '(:joint b :parent root :center (0 0 0))
                   '(:joint c :parent b :center (0 0 0))
                   '(:role :left-arm (a b c))))
  (signals-skeleton-error ("exactly one root")
    (skeleton-from '(:joint other-root :parent nil :center (0 0 0))))
  (signals-skeleton-error ("(skeleton NAME")
    (player.body::parse-skeleton '(skeletn test)))
  (signals-skeleton-error (":center")
    (skeleton-from '(:joint a :parent root :center (0 0))))
  (signals-skeleton-error ("unknown option")
    (skeleton-from '(:joint a :parent root :center (0 0 0) :colour red)))
  (signals-skeleton-error ("clause")
    (skeleton-from '(:bone a)))
  (signals-skeleton-error ("unknown skeleton")
    (player::load-skeleton 'dragon)))

(test skeleton-file-errors
  (uiop:with-temporary-file (:pathname path :stream out :type "lisp")
    (write-string "(skeleton a (:joint r :parent nil :center (0 0 0))) (extra)" out)
    :close-stream
    (signals-skeleton-error ("more than one form") (player::load-skeleton path)))
  (uiop:with-temporary-file (:pathname path :stream out :type "lisp")
    (write-string "(skeleton a #.(error \"no\"))" out)
    :close-stream
    (signals-skeleton-error ("could not read") (player::load-skeleton path)))
  (uiop:with-temporary-file (:pathname path :stream out :type "lisp")
    (write-string "(skeleton a (:joint r :parent nil :center (0 0 0)) (:role :head r))" out)
    :close-stream
    (is (string-equal "R" (player.body::body-joint-name
                           (player::skeleton-role (player::load-skeleton path) :head))))))

;;; ---------------------------------------------------------------------------
;;; Arbitration

(defvar *notifications* '()
  "Notifications recorded by RECORDING-DRIVERs, newest first: (KIND DRIVER CHANNEL OTHER).")

(defclass recording-driver ()
  ((id :initarg :id :reader driver-id))
  (:documentation "A driver that records every loss and grant in *NOTIFICATIONS*."))

(defmethod print-object ((driver recording-driver) stream)
  (print-unreadable-object (driver stream :type t)
    (format stream "~A" (driver-id driver))))

(defmethod player::on-channel-loss ((driver recording-driver) channel new-owner)
  (push (list :loss driver channel new-owner) *notifications*))

(defmethod player::on-channel-grant ((driver recording-driver) channel previous-owner)
  (push (list :grant driver channel previous-owner) *notifications*))

;;; The model: per channel, a list of (DRIVER PRIORITY SERIAL); the owner is the
;;; request with the highest priority, the lowest serial on ties.

(defstruct plain-arbiter
  (requests (make-hash-table :test #'equal))
  (serial 0))

(defun plain-owner (model channel)
  "The driver the rule says owns CHANNEL in MODEL, or NIL."
  (let ((best nil))
    (dolist (request (gethash channel (plain-arbiter-requests model)))
      (when (or (null best)
                (> (second request) (second best))
                (and (= (second request) (second best)) (< (third request) (third best))))
        (setf best request)))
    (first best)))

(defun plain-has-request-p (model channel driver)
  (find driver (gethash channel (plain-arbiter-requests model)) :key #'first))

(defun plain-request (model driver channels priority)
  (dolist (channel channels)
    (let ((request (plain-has-request-p model channel driver)))
      (if request
          (setf (second request) priority)
          (push (list driver priority (incf (plain-arbiter-serial model)))
                (gethash channel (plain-arbiter-requests model)))))))

(defun plain-release (model driver channels)
  (dolist (channel channels)
    (setf (gethash channel (plain-arbiter-requests model))
          (remove driver (gethash channel (plain-arbiter-requests model)) :key #'first))))

(defun plain-channels-of (model driver)
  (loop for channel being the hash-keys of (plain-arbiter-requests model)
        when (plain-has-request-p model channel driver) collect channel))

(defun expected-notifications (model before channels requester)
  "The notifications the rule implies after a step that touched CHANNELS, given
BEFORE, an alist of (CHANNEL . OWNER) from before the step."
  (loop for channel in channels
        for old = (cdr (assoc channel before :test #'equal))
        for new = (plain-owner model channel)
        unless (eq old new)
          append (append (and old (plain-has-request-p model channel old)
                              (list (list :loss old channel new)))
                         (and new (not (eq new requester))
                              (list (list :grant new channel old))))))

(defun notification-key (notification)
  (destructuring-bind (kind driver channel other) notification
    (format nil "~A ~A ~A ~A" kind (driver-id driver) channel
            (if other (driver-id other) "-"))))

(defun run-arbitration-sequence (random-state steps)
  "Run STEPS random operations against an arbitrator and the model; return NIL,
or a description of the first disagreement."
  (let* ((arbitrator (player::make-arbitrator))
         (model (make-plain-arbiter))
         (drivers (loop for id below 5 collect (make-instance 'recording-driver :id id)))
         (channels '(:head :jaw (l_elbow . :x) (l_elbow . :y) :l-eye :r-eye)))
    (flet ((pick (list) (nth (random (length list) random-state) list))
           (subset (list) (remove-if (lambda (x) (declare (ignore x))
                                       (zerop (random 2 random-state)))
                                     list)))
      (dotimes (step steps)
        (let* ((driver (pick drivers))
               (kind (pick '(:request :request :request :release :release-driver)))
               (chosen (if (eq kind :release-driver)
                           (plain-channels-of model driver)
                           (remove-duplicates (subset channels) :test #'equal)))
               (before (mapcar (lambda (c) (cons c (plain-owner model c))) channels))
               (*notifications* '()))
          (ecase kind
            (:request
             (let ((priority (random 4 random-state)))
               (player::request-channels arbitrator driver chosen :priority priority)
               (plain-request model driver chosen priority)))
            (:release
             (player::release-channels arbitrator driver chosen)
             (plain-release model driver chosen))
            (:release-driver
             (player::release-driver arbitrator driver)
             (plain-release model driver chosen)))
          (dolist (channel channels)
            (unless (eq (player::channel-owner arbitrator channel) (plain-owner model channel))
              (return-from run-arbitration-sequence
                (format nil "step ~D (~A): channel ~A owned by ~A, the rule says ~A"
                        step kind channel (player::channel-owner arbitrator channel)
                        (plain-owner model channel)))))
          (let ((expected (sort (mapcar #'notification-key
                                        (expected-notifications
                                         model before chosen
                                         (and (eq kind :request) driver)))
                                #'string<))
                (seen (sort (mapcar #'notification-key *notifications*) #'string<)))
            (unless (equal expected seen)
              (return-from run-arbitration-sequence
                (format nil "step ~D (~A): notified ~S, the rule says ~S"
                        step kind seen expected))))))
      ;; Release everything: nothing is owned, waiting or remembered.
      (dolist (driver drivers)
        (player::release-driver arbitrator driver))
      (cond ((some (lambda (c) (or (player::channel-owner arbitrator c)
                                   (player.body::channel-waiting arbitrator c)))
                   channels)
             "a channel is still held after releasing every driver")
            ((player.body::known-drivers arbitrator)
             "the arbitrator still refers to a driver after releasing them all")))))

(test arbitration-matches-the-rule
  (let ((random-state (sb-ext:seed-random-state 20240501))
        (failure nil)
        (sequences 2000))
    (loop repeat sequences
          until (setf failure (run-arbitration-sequence random-state 30)))
    (is (null failure) "~A" failure)))

(test arbitration-usurp-and-return
  (let ((arbitrator (player::make-arbitrator))
        (low (make-instance 'recording-driver :id 'low))
        (high (make-instance 'recording-driver :id 'high))
        (*notifications* '()))
    (is (equal '(:head :jaw) (player::request-channels arbitrator low '(:head :jaw) :priority 1)))
    (is (equal '(:head) (player::request-channels arbitrator high :head :priority 5)))
    (is (eq high (player::channel-owner arbitrator :head)))
    (is (equal (list (list :loss low :head high)) *notifications*))
    (is (equal '(:head :jaw) (player.body::channels-of arbitrator low)))
    (is (equal '(:jaw) (player.body::channels-of arbitrator low :owned-only t)))
    (setf *notifications* '())
    (player::release-driver arbitrator high)
    (is (eq low (player::channel-owner arbitrator :head)))
    (is (equal (list (list :grant low :head high)) *notifications*))
    ;; An equal priority never usurps: the earlier request keeps the channel.
    (is (null (player::request-channels arbitrator high :head :priority 1)))
    (is (eq low (player::channel-owner arbitrator :head)))
    (is (equal (list high) (player.body::channel-waiting arbitrator :head)))))

(defvar *test-arbitrator* nil
  "The arbitrator QUITTING-DRIVERs release themselves from.")

(defclass quitting-driver (recording-driver) ()
  (:documentation "A driver that ends (releases everything) when it loses a channel."))

(defmethod player::on-channel-loss ((driver quitting-driver) channel new-owner)
  (declare (ignore channel new-owner))
  (call-next-method)
  (player::release-driver *test-arbitrator* driver))

(test arbitration-loser-may-end
  (let* ((arbitrator (player::make-arbitrator))
         (*test-arbitrator* arbitrator)
         (quitter (make-instance 'quitting-driver :id 'quitter))
         (boss (make-instance 'recording-driver :id 'boss))
         (*notifications* '()))
    (player::request-channels arbitrator quitter '(:a :b :c) :priority 1)
    (player::request-channels arbitrator boss '(:a :b) :priority 2)
    ;; Told once per lost channel (the second loss finds it already gone).
    (is (= 1 (count :loss *notifications* :key #'first)))
    (is (null (player::channel-owner arbitrator :c)))
    (is (null (player.body::channels-of arbitrator quitter)))
    (player::release-driver arbitrator boss)
    (is (null (player.body::known-drivers arbitrator)))))

(test arbitration-master-slave
  (let ((arbitrator (player::make-arbitrator))
        (master (make-instance 'recording-driver :id 'master))
        (slave (make-instance 'recording-driver :id 'slave))
        (grandslave (make-instance 'recording-driver :id 'grandslave))
        (rival (make-instance 'recording-driver :id 'rival))
        (*notifications* '()))
    (player::request-channels arbitrator master :head :priority 3)
    (player::add-slave arbitrator master slave)
    (player::add-slave arbitrator slave grandslave)
    (is (eq master (player.body::driver-master arbitrator slave)))
    (is (equal (list slave) (player.body::driver-slaves arbitrator master)))
    ;; Slaves request at the master's priority ...
    (player::request-channels arbitrator slave :jaw)
    (player::request-channels arbitrator grandslave :l-arm)
    (player::request-channels arbitrator rival '(:jaw :l-arm) :priority 3)
    (is (eq slave (player::channel-owner arbitrator :jaw)))
    (is (eq grandslave (player::channel-owner arbitrator :l-arm)))
    ;; ... a loss reaches the slave first, then its masters.
    (player::request-channels arbitrator rival :l-arm :priority 4)
    (is (equal (list (list :loss grandslave :l-arm rival)
                     (list :loss slave :l-arm rival)
                     (list :loss master :l-arm rival))
               (reverse *notifications*)))
    ;; A slave's priority may be reset.
    (player::request-channels arbitrator slave :l-arm :priority 9)
    (is (eq slave (player::channel-owner arbitrator :l-arm)))
    ;; Cycles are refused.
    (signals player::arbitration-error (player::add-slave arbitrator grandslave master))
    (signals player::arbitration-error
      (player::request-channels arbitrator (make-instance 'recording-driver :id 'x) :head))
    ;; Releasing the master releases its slaves; nothing refers to them after.
    (player::release-driver arbitrator master)
    (is (eq rival (player::channel-owner arbitrator :jaw)))
    (is (eq rival (player::channel-owner arbitrator :l-arm)))
    (is (null (player::channel-owner arbitrator :head)))
    (is (null (player.body::channels-of arbitrator slave)))
    (is (equal (list rival) (player.body::known-drivers arbitrator)))))

(test arbitration-blend-weight
  (let ((arbitrator (player::make-arbitrator :blend-time 0.5))
        (a (make-instance 'recording-driver :id 'a))
        (b (make-instance 'recording-driver :id 'b)))
    (is (= 1 (player::channel-blend-weight arbitrator :head 0)))
    (player::request-channels arbitrator a :head :priority 1 :time 1)
    (is (= 0 (player::channel-blend-weight arbitrator :head 1)))
    (is (= 1/2 (player::channel-blend-weight arbitrator :head 1.25d0)))
    (is (= 1 (player::channel-blend-weight arbitrator :head 2)))
    (is (= 0 (player::channel-blend-weight arbitrator :head 0)))
    (player::request-channels arbitrator b :head :priority 2 :time 3 :blend 2)
    (is (equal '(3 2) (multiple-value-list (player.body::channel-handover arbitrator :head))))
    (is (= 1/4 (player::channel-blend-weight arbitrator :head 7/2)))
    ;; No change of owner, no new handover.
    (player::request-channels arbitrator a :head :priority 1 :time 4)
    (is (= 3 (player.body::channel-handover arbitrator :head)))
    (player::release-channels arbitrator b :head :time 10 :blend 0)
    (is (eq a (player::channel-owner arbitrator :head)))
    (is (= 1 (player::channel-blend-weight arbitrator :head 10)))
    (is (= 0 (player::channel-blend-weight arbitrator :head 9)))))
