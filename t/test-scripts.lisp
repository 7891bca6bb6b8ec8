;;;; test-scripts.lisp -- the script-library language: DEFSCRIPT items and
;;;; durations, critical times, DEFDIRECTOR schedules, DEFOBJECT, POSES, library
;;;; files, and one clear SCRIPT-ERROR for each kind of mistake.

(in-package #:player-tests)

(def-suite* scripts :in player-tests)

;;; Scripts call motor functions, which their drivers define; the tests use one
;;; of their own, added to a copy of the registry so other suites never see it.

(defun motor-functions-for-tests ()
  "A copy of the motor-function registry with :test-nod added."
  (let ((player.body::*motor-functions* (alexandria:copy-hash-table player.body::*motor-functions*)))
    (player::define-motor-function :test-nod player::driver "Nod, for the script tests."
      (:angle :angle 10 "how far to nod, degrees")
      (:target :target :required "what to nod at"))
    player.body::*motor-functions*))

(defun library (&rest forms)
  "The script library of FORMS, with the test motor functions defined."
  (let ((player.body::*motor-functions* (motor-functions-for-tests)))
    (player.performance::parse-script-library-forms forms)))

(defun script (library name)
  "LIBRARY's script NAME, which must exist."
  (player::find-script library name t))

(defun schedule (library director &optional (start 0))
  "The schedule of LIBRARY's DIRECTOR started at START, times rounded to microseconds,
and its duration."
  (multiple-value-bind (entries duration)
      (player::director-schedule (player::find-director library director t) library start)
    (values (mapcar (lambda (entry)
                      (list (string-downcase (first entry))
                            (round-time (second entry)) (and (third entry) (round-time (third entry)))))
                    entries)
            (and duration (round-time duration)))))

(defun secs= (a b)
  "Are the times A and B equal to the microsecond?  (Test literals are single-floats.)"
  (< (abs (- a b)) 1d-6))

(defun round-time (seconds)
  "SECONDS rounded to microseconds, as a rational, so schedules compare with EQUAL."
  (/ (round (* seconds 1000000)) 1000000))

(defun check-script-error (thunk fragments description)
  "Check that calling THUNK signals a SCRIPT-ERROR, a SPEC-ERROR, whose report
contains every string of FRAGMENTS; DESCRIPTION says what THUNK does."
  (let ((condition (handler-case (progn (funcall thunk) nil)
                     (player-error (c) c))))
    (is (typep condition 'player::script-error)
        "~S signalled ~S, not a script-error" description condition)
    (when condition
      (is (typep condition 'spec-error))
      (let ((report (princ-to-string condition)))
        (dolist (fragment fragments)
          (is (search fragment report) "report ~S does not mention ~S" report fragment))))))

(defmacro signals-script-error ((&rest fragments) &body body)
  "Check that BODY signals a SCRIPT-ERROR whose report contains every string of FRAGMENTS."
  `(check-script-error (lambda () ,@body) (list ,@fragments) ',body))

;;; ---------------------------------------------------------------------------
;;; Items

(test item-kinds
  (let* ((library (library '(defscript greet (:documentation "Hello.")
                             (:at 0 :motor (:test-nod :target (:object user)) :for 1)
                             (:at 0.5 :animate (note position) (:keys ((0 :vec3 0 0 0) (1 :vec3 0 1 0))))
                             (:at 1 :set (note visible) nil)
                             (:at 1 :set (:self glow) 0.5)
                             (:at 1.5 :play blink :for 0.2)
                             (:at 2 :attach note :to (:self :right-hand))
                             (:at 2 :attach hat :to nil :keep-world nil))
                           '(defscript blink (:duration 0.3))))
         (items (player.performance::script-items (script library 'greet))))
    (is (equal "Hello." (player.performance::script-documentation (script library 'greet))))
    (destructuring-bind (motor animate set-visible set-glow play attach detach) items
      (is (typep motor 'player.performance::motor-item))
      (is (eq :test-nod (player.body::motor-call-function (player.performance::motor-item-call motor))))
      (is (= 10 (player.body::motor-arg (player.performance::motor-item-call motor) :angle)))
      (is (= 1 (player.performance::script-item-until motor)))
      (is (typep animate 'player.performance::animate-item))
      (is (= 0.5 (player.performance::script-item-at animate)))
      (is (null (player.performance::script-item-until animate)))
      (is (string-equal "NOTE" (player.performance::animate-item-object animate)))
      (is (string-equal "POSITION" (player.performance::animate-item-property animate)))
      (is (eq :vec3 (player.body::control-kind (player.performance::animate-item-control animate))))
      (is (null (player.performance::set-item-value set-visible)))
      (is (eq :self (player.performance::set-item-object set-glow)))
      (is (= 0.5d0 (player.performance::set-item-value set-glow)))
      (is (string-equal "BLINK" (player.performance::play-item-script play)))
      (is (secs= 1.7 (player.performance::script-item-end play)))
      (is (equal '(:self :right-hand) (player.performance::attach-item-parent attach)))
      (is-true (player.performance::attach-item-keep-world attach))
      (is (null (player.performance::attach-item-parent detach)))
      (is-false (player.performance::attach-item-keep-world detach)))))

(test durations-and-loops
  (let ((library (library '(defscript explicit (:duration 2.5 :loop t) (:at 1 :set (a b) 1))
                          '(defscript starts-count (:documentation "no :for anywhere")
                            (:at 0.4 :set (a b) 1) (:at 1.2 :motor (:test-nod :target (:point 0 1 2))))
                          '(defscript for-counts () (:at 0.5 :motor (:test-nod :target (:object a)) :for 2))
                          '(defscript keys-count () (:at 1 :animate (a b) (:keys ((0 . 0) (3 . 1)))))
                          '(defscript looping-keys-count ()
                            (:at 1 :animate (a b) (:keys ((0 . 0) (3 . 1)) :loop t)))
                          ;; NESTED plays a script defined after it.
                          '(defscript nested () (:at 1 :play for-counts) (:at 0 :play inner :for 0.5))
                          '(defscript inner (:duration 9))
                          '(defscript empty ()))))
    (flet ((duration (name) (player::script-duration (script library name))))
      (is (= 2.5d0 (duration 'explicit)))
      (is-true (player.performance::script-loop (script library 'explicit)))
      (is-false (player.performance::script-loop (script library 'nested)))
      (is (secs= 1.2 (duration 'starts-count)))
      (is (= 2.5d0 (duration 'for-counts)))
      (is (= 4d0 (duration 'keys-count)))
      (is (= 1d0 (duration 'looping-keys-count)))
      (is (= 3.5d0 (duration 'nested)))
      (is (= 0d0 (duration 'empty))))))

(test critical-times
  (let* ((library (library '(defscript hammer (:critical ((lift . 0.2) (strike 0.9)))
                             (:at strike :set (nail depth) 1)
                             (:at lift :motor (:test-nod :target (:object nail)) :for 0.5))))
         (hammer (script library "HAMMER")))
    (is (secs= 0.9 (player::script-critical-time hammer 'strike)))
    (is (secs= 0.2 (player::script-critical-time hammer "lift")))
    (is (null (player::script-critical-time hammer 'miss nil)))
    (is (every #'secs= '(0.9 0.2) (mapcar #'player.performance::script-item-at (player.performance::script-items hammer))))
    (is (secs= 0.9 (player::script-duration hammer)))
    (signals-script-error ("unknown critical time miss in script hammer" "known: lift strike")
      (player::script-critical-time hammer 'miss))))

;;; ---------------------------------------------------------------------------
;;; Directors

(defparameter *director-scripts*
  '((defscript wave (:duration 2 :critical ((peak . 0.5))))
    (defscript bow (:duration 1.5 :critical ((stroke . 1))))
    (defscript idle (:duration 4 :loop t))
    (defscript speak (:duration 3)))
  "Scripts the director tests start.")

(defun director-library (&rest directors)
  "A library of *DIRECTOR-SCRIPTS* and DIRECTORS."
  (apply #'library (append *director-scripts* directors)))

(test director-sequencing
  (let ((library (director-library '(defdirector greet "Wave, then bow, then speak."
                                     (:start wave) (:start bow) (:start speak)))))
    (is (equal "Wave, then bow, then speak."
               (player.performance::director-documentation (player::find-director library 'greet))))
    (multiple-value-bind (entries duration) (schedule library 'greet)
      (is (equal '(("wave" 0 nil) ("bow" 2 nil) ("speak" 7/2 nil)) entries))
      (is (= 13/2 duration)))
    (multiple-value-bind (entries duration) (schedule library 'greet 10)
      (is (equal '(("wave" 10 nil) ("bow" 12 nil) ("speak" 27/2 nil)) entries))
      (is (= 13/2 duration) "the duration is relative"))))

(test director-synchronisation
  (let ((library (director-library
                  '(defdirector sync
                    (:start wave :as w :at 1)
                    (:start bow :at (:critical w peak))           ; bow starts at wave's peak
                    (:start speak :at (:critical bow stroke -0.25))
                    (:start wave :as w2 :at (:end bow 0.5))
                    (:start idle :at (:start w2)))
                  '(defdirector stopped
                    (:start idle :as i)
                    (:start speak :at 0.5)
                    (:stop i)                                     ; when speak ends
                    (:start bow :at (:end i))
                    (:stop bow :at 10)))))
    (multiple-value-bind (entries duration) (schedule library 'sync)
      (is (equal '(("wave" 1 nil) ("bow" 3/2 nil) ("speak" 9/4 nil) ("wave" 7/2 nil) ("idle" 7/2 nil))
                 entries))
      (is (null duration) "an unstopped looping script runs for ever"))
    (multiple-value-bind (entries duration) (schedule library 'stopped)
      (is (equal '(("idle" 0 7/2) ("speak" 1/2 nil) ("bow" 7/2 nil)) entries)
          "a stop after the script's end does not cut it")
      (is (= 5 duration)))))

(test director-stop-cuts-short
  (let ((library (director-library '(defdirector cut (:start speak) (:stop speak :at 1) (:start bow)))))
    (multiple-value-bind (entries duration) (schedule library 'cut)
      (is (equal '(("speak" 0 1) ("bow" 1 nil)) entries))
      (is (= 5/2 duration)))))

;;; ---------------------------------------------------------------------------
;;; Objects, poses, files

(test objects
  (let* ((library (library '(defobject note :kind :prop :parent (peedy :right-hand)
                             :position (0 0.1 0) :rotation (:euler 0 90 0)
                             :properties ((ink :colour (1 0 0)) (folded :boolean t) (size :number 2)))
                           '(defobject lamp :kind :light :rotation (2 0 0 0))
                           '(defscript fold ()
                             (:at 0 :set (note folded) nil)
                             (:at 0 :animate (note ink) (:keys ((0 :vec3 1 0 0) (1 :vec3 0 0 1))))
                             (:at 0 :set (note rotation) (:euler 0 0 1)))))
         (objects (player.performance::script-library-objects library))
         (note (first objects)))
    (is (equal '("NOTE" "LAMP") (mapcar (lambda (o) (string (player.performance::scene-object-spec-name o))) objects)))
    (is (eq :prop (player.performance::scene-object-spec-kind note)))
    (is (equal '(peedy :right-hand) (player.performance::scene-object-spec-parent note)))
    (is (secs= 0.1 (player.body::vec3-y (player.performance::scene-object-spec-position note))))
    (let ((rotation (player.performance::scene-object-spec-rotation note)))   ; 90 degrees about y
      (is (< (abs (- (player.body::quat-w rotation) (sqrt 0.5d0))) 1d-9))
      (is (< (abs (- (player.body::quat-y rotation) (sqrt 0.5d0))) 1d-9)))
    (is (= 1d0 (player.body::quat-w (player.performance::scene-object-spec-rotation (second objects)))))
    (is (equal '(:colour :boolean :number) (mapcar #'second (player.performance::scene-object-spec-properties note))))
    (is (= 1d0 (player.body::vec3-x (third (first (player.performance::scene-object-spec-properties note))))))))

(defmacro with-library-file ((path text) &body body)
  "Run BODY with PATH bound to a temporary .lisp file holding TEXT."
  `(uiop:with-temporary-file (:pathname ,path :stream out :type "lisp")
     (write-string ,text out)
     :close-stream
     ,@body))

(test library-files
  (with-library-file (poses "(poses-of-some-kind)")
    (with-library-file (path (format nil ";; a library~%(poses ~S)~%~%~
                                          (defscript nod (:duration 1)~%  ~
                                            (:at 0 :motor (:test-nod :target (:object user))))~%~
                                          (defdirector twice (:start nod) (:start nod :as again))~%"
                                     (file-namestring poses)))
      (let* ((library (let ((player.body::*motor-functions* (motor-functions-for-tests)))
                        (player::load-script-library path))))
        (is (equal (truename poses) (player.performance::script-library-poses library)))
        (is (equal (truename path) (player.performance::script-library-source library)))
        (is (= 1d0 (player::script-duration (player::find-script library "nod"))))
        (is (equal '(("nod" 0 nil) ("nod" 1 nil)) (schedule library 'twice)))
        (is (equal '(yawn "wave") (player.performance::missing-scripts library '(nod yawn twice "wave" yawn "NOD"))))
        (is (null (player::find-script library 'twice)))
        (signals-script-error ("unknown script yawn" "known: nod")
          (player::find-script library 'yawn t))))))

(test library-file-errors
  (with-library-file (path (format nil "(defscript a ())~%~%(defscript b (:duration 1)~%  (:at 2 :set (x y) 1))~%"))
    (signals-script-error ((format nil "~A:4: script b: the item starts at 2, after the script's duration 1 in (:at 2 :set"
                                   (file-namestring path)))
      (player::load-script-library path)))
  (with-library-file (path "(defscript a () #.(error \"no\"))")
    (signals-script-error ("unreadable script library" (file-namestring path))
      (player::load-script-library path)))
  (with-library-file (path "(defscript a () (:at 0 :set (x y) 1)")
    (signals-script-error ("unreadable script library")
      (player::load-script-library path)))
  (with-library-file (path "(poses \"no-such-poses.lisp\")")
    (signals-script-error ("no pose library file" "no-such-poses.lisp")
      (player::load-script-library path)))
  (signals-script-error ("there is no script library file")
    (player::load-script-library "/nonexistent/library.lisp")))

;;; ---------------------------------------------------------------------------
;;; Every mistake gets its own error

(defparameter *script-mistakes*
  '((("a script is written") (defscript))
    (("a script is written") (defscript :bow ()))
    (("defscript has no option :lenght") (defscript bow (:lenght 1)))
    ((":duration must be a positive number") (defscript bow (:duration 0)))
    ((":loop must be T or NIL") (defscript bow (:loop yes)))
    (("critical time stroke (2) lies after the script's duration 1") (defscript bow (:duration 1 :critical ((stroke . 2)))))
    (("critical time stroke (2) lies after the script's duration 1") (defscript bow (:critical ((stroke . 2))) (:at 1 :set (a b) 1)))
    (("critical time stroke is given twice") (defscript bow (:critical ((stroke . 1) (stroke . 2)))))
    (("a critical time is written (NAME . SECONDS)") (defscript bow (:critical (stroke))))
    (("an item is written (:at TIME KIND ...)") (defscript bow () (:motor (:test-nod))))
    (("script bow: unknown item kind :mtor" "in (:at 0 :mtor") (defscript bow () (:at 0 :mtor (:test-nod))))
    (("script bow: unknown critical time stroke" "known: none") (defscript bow () (:at stroke :set (a b) 1)))
    (("an item's time" "non-negative") (defscript bow () (:at -1 :set (a b) 1)))
    (("script bow: the item starts at 2, after the script's duration 1.6" "in (:at 2 :motor")
     (defscript bow (:duration 1.6) (:at 2 :motor (:test-nod :target (:object user)))))
    (("the item ends at 2.5, after the script's duration 2") (defscript bow (:duration 2) (:at 1 :play bow :for 1.5)))
    (("unknown motor function :gaze-at") (defscript bow () (:at 0 :motor (:gaze-at :target (:object user)))))
    (("needs :target") (defscript bow () (:at 0 :motor (:test-nod))))
    ((":for must be a positive number") (defscript bow () (:at 0 :motor (:test-nod :target (:object u)) :for 0)))
    (("the :motor item has no option :until (options: :for)") (defscript bow () (:at 0 :motor (:test-nod :target (:object u)) :until 1)))
    (("the :motor item gives the option :for twice")
     (defscript bow () (:at 0 :motor (:test-nod :target (:object u)) :for 1 :for 2)))
    (("the :set item has no option :for (it takes none)") (defscript bow () (:at 0 :set (a b) 1 :for 1)))
    (("the :animate item is missing its arguments") (defscript bow () (:at 0 :animate (a b))))
    (("a property is written (OBJECT PROPERTY)") (defscript bow () (:at 0 :animate a (:constant 1))))
    (("bad control") (defscript bow () (:at 0 :animate (a b) (:keys ((1 . 0) (0 . 1))))))
    (("bad value") (defscript bow () (:at 0 :set (a b) (:vec3 1 2))))
    (("position is a vector property, and this gives it a number") (defscript bow () (:at 0 :set (a position) 1)))
    (("visible is a boolean property: set it with :set") (defscript bow () (:at 0 :animate (a visible) (:constant 1))))
    (("rotation is a rotation property, and this gives it a boolean") (defscript bow () (:at 0 :set (a rotation) t)))
    ((":play takes the name of a script") (defscript bow () (:at 0 :play (bow))))
    (("script bow: wave is not a script of the library" "in (:at 0 :play wave)") (defscript bow () (:at 0 :play wave)))
    (("wave is a director; :play takes scripts") (defscript bow () (:at 0 :play wave)) (defdirector wave (:start bow)))
    (("nested scripts form a cycle: a -> b -> a") (defscript a () (:at 0 :play b)) (defscript b () (:at 1 :play a)))
    (("nested scripts form a cycle: c -> c") (defscript c () (:at 0 :play c)))
    ((":attach needs :to PARENT") (defscript bow () (:at 0 :attach note)))
    (("unknown role :right-claw") (defscript bow () (:at 0 :attach note :to (:self :right-claw))))
    (("a parent is an object's name") (defscript bow () (:at 0 :attach note :to (a b c))))
    ((":keep-world must be T or NIL") (defscript bow () (:at 0 :attach note :to nil :keep-world 1)))
    (("a looping script must last some time") (defscript bow (:loop t) (:at 0 :set (a b) 1)))
    (("script bow is defined twice") (defscript bow ()) (defscript bow ()))
    (("bow is defined both as a script and as a director") (defscript bow ()) (defdirector bow (:start bow)))
    (("a script library may contain defscript, defdirector, defobject, model, poses, idle and :pose-when forms, not a defun form") (defun f ()))
    (("a script library may contain" "not this") 42))
  "Each entry: (FRAGMENTS FORM...), a library whose error report contains every fragment.")

(defparameter *director-mistakes*
  '((("a director is written") (defdirector))
    (("director d: a director needs at least one step") (defdirector d "Nothing."))
    (("a director step is (:start SCRIPT") (defdirector d (:begin wave)))
    (("a :start step has no option :after") (defdirector d (:start wave :after bow)))
    (("no earlier step starts a script as w" "started: none") (defdirector d (:stop w)))
    (("no earlier step starts a script as w" "started: wave") (defdirector d (:start wave) (:start bow :at (:end w))))
    (("an earlier step already starts a script as wave") (defdirector d (:start wave) (:start wave)))
    ((":at takes seconds") (defdirector d (:start wave) (:start bow :at (:middle wave))))
    ((":at must be a non-negative number") (defdirector d (:start wave :at -1)))
    (("the step comes 1 s before the director starts") (defdirector d (:start wave) (:start bow :at (:start wave -1))))
    (("director d: yawn is not a script of the library" "in (:start yawn)") (defdirector d (:start yawn)))
    (("other is a director; directors start scripts") (defdirector other (:start wave)) (defdirector d (:start other)))
    (("script wave has no critical time stroke" "known: peak") (defdirector d (:start wave) (:start bow :at (:critical wave stroke))))
    (("script idle loops and never ends by itself") (defdirector d (:start idle) (:start bow)))
    (("script idle loops and never ends by itself") (defdirector d (:start idle) (:start bow :at (:end idle))))
    (("wave is stopped twice") (defdirector d (:start wave) (:stop wave :at 1) (:stop wave :at 1.5)))
    (("wave is stopped at 1, before it starts at 2") (defdirector d (:start wave :at 2) (:stop wave :at 1)))
    (("wave is stopped at 1, before its end (2) that an earlier step waits for")
     (defdirector d (:start wave) (:start bow) (:stop wave :at 1)))
    (("wave is stopped at 0.2, before its critical time peak (0.5)")
     (defdirector d (:start wave) (:stop wave :at 0.2) (:start bow :at (:critical wave peak)))))
  "Like *SCRIPT-MISTAKES*, with *DIRECTOR-SCRIPTS* added to each library.")

(defparameter *object-mistakes*
  '((("an object is written") (defobject))
    (("object note: defobject has no option :colour") (defobject note :colour (1 0 0)))
    ((":kind must be one of :prop :camera :light :group") (defobject note :kind :body))
    ((":position must be 3 numbers") (defobject note :position (0 1)))
    ((":rotation must be 3 numbers after :euler") (defobject note :rotation (:euler 0 1)))
    ((":rotation must be a nonzero quaternion") (defobject note :rotation (0 0 0 0)))
    (("ink is a colour: each of red, green and blue must lie in [0, 1]") (defobject note :properties ((ink :colour (2 0 0)))))
    (("property ink: unknown type :color") (defobject note :properties ((ink :color (1 0 0)))))
    (("every object has the property position already") (defobject note :properties ((position :vector (1 0 0)))))
    (("property ink is declared twice") (defobject note :properties ((ink :number 1) (ink :number 2))))
    (("a property is written (NAME TYPE VALUE)") (defobject note :properties ((ink :number))))
    (("size must be a number") (defobject note :properties ((size :number big))))
    (("object note is declared twice") (defobject note) (defobject note))
    (("objects hang from each other in a cycle: a -> b -> a") (defobject a :parent b) (defobject b :parent (a :head)))
    (("object note has no property ink (it has position rotation visible size)")
     (defobject note :properties ((size :number 1))) (defscript s () (:at 0 :set (note ink) 1)))
    (("size is a number property, and this gives it a vec3")
     (defobject note :properties ((size :number 1))) (defscript s () (:at 0 :animate (note size) (:constant (:vec3 1 2 3)))))
    (("tint is a colour: each of red, green and blue must lie in [0, 1]")
     (defobject note :properties ((tint :colour (0 0 0)))) (defscript s () (:at 0 :set (note tint) (:vec3 0 2 0))))
    (("the pose library is named (poses \"FILE\")") (poses poses.lisp))
    (("the pose library is named twice") (poses "test-scripts.lisp") (poses "test-scripts.lisp")))
  "Like *SCRIPT-MISTAKES*, for objects and poses.")

(defun check-mistakes (mistakes &optional prefix-forms)
  "Check that each of MISTAKES, with PREFIX-FORMS before its forms, gives its error."
  (let ((*default-pathname-defaults* (checkout-file "t/")))
    (loop for (fragments . forms) in mistakes
          do (check-script-error (lambda () (apply #'library (append prefix-forms forms)))
                                 fragments forms))))

(test script-errors (check-mistakes *script-mistakes*))
(test director-errors (check-mistakes *director-mistakes* *director-scripts*))
(test object-errors (check-mistakes *object-mistakes*))
