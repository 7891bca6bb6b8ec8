;;;; test-reactive-directors.lisp -- issue 29, item 3: directors that start
;;;; by themselves, (:when EXPRESSION) on a state or a property, (:on EVENT)
;;;; on a Player event, (:after DIRECTOR) when another ends; their :set and
;;;; :send steps; and the old fixed-schedule forms, unchanged.

(in-package #:player-tests)

(def-suite* reactive-directors :in player-tests)

(defparameter *reactive-library-forms*
  '((defobject ball :position (0 0 0))
    (defscript light (:duration 1))
    (defscript wave (:duration 1))
    (defscript dim (:duration 0.5))
    (defscript glow (:duration 0.5))
    (defscript cheer (:duration 0.25))
    (defscript lift (:duration 2)
      (:at 0 :animate (ball position) (:keys ((0 :vec3 0 0 0) (2 :vec3 0 2 0)))))
    (defdirector on-lit (:when lit) (:start glow))
    (defdirector on-wave (:on ev-wave) (:start cheer) (:send ev-dim))
    (defdirector after-wave (:after on-wave) (:start glow :as again))
    (defdirector ball-high (:when (> (:property ball position :y) 1))
      (:start cheer) (:set (ball visible) nil :at 0.5))
    (defdirector fixed (:start light) (:start glow :at (:end light)) (:stop glow :at 1.25)))
  "Scripts and directors of every trigger kind, and one of the old kind.")

(defun reactive-library ()
  "The library of *REACTIVE-LIBRARY-FORMS*."
  (player.performance::parse-script-library-forms *reactive-library-forms*))

(defun run-starts (performance name)
  "The start times of PERFORMANCE's top-level runs of the script NAME, in order."
  (sort (loop for run in (player.performance::performance-runs performance)
              when (string-equal name (player.performance::script-name (player.performance::script-run-script run)))
                collect (player.performance::script-run-start run))
        #'<))

(defmacro with-reactive-spec ((spec) &body body)
  "Bind SPEC to a spec whose ops play the reactive library's scripts."
  `(with-spec (,spec reactive-spec
                (state-variable lit boolean false)
                (op light :add lit)
                (op wave)
                (op dim :sub lit)
                (event ev-light :op light)
                (event ev-wave :op wave)
                (event ev-dim :op dim))
     ,@body))

(test old-director-forms-keep-their-schedules
  (let* ((library (reactive-library))
         (director (player:find-director library 'fixed)))
    (is (null (player.performance::director-trigger director)))
    (multiple-value-bind (schedule duration actions) (player:director-schedule director library 2)
      (is (equal '((light 2d0 nil) (glow 3d0 3.25d0)) schedule))
      (is (= 1.25d0 duration))
      (is (null actions)))))

(test an-after-director-starts-when-the-other-ends
  (let ((performance (player:make-performance (reactive-library) '((bob humanoid)))))
    (player:perform-director performance 'on-wave 2)
    (is (equal '(2d0) (run-starts performance 'cheer)))
    (is (equal '(2.25d0) (run-starts performance 'glow)) "after-wave starts when on-wave's cheer ends")
    (is (equal '((2.25d0 ev-dim)) (player:performance-sent-events performance))
        "with no controller the send is noted")))

(test an-on-director-starts-on-its-event
  (let ((performance (player:make-performance (reactive-library) '((bob humanoid)))))
    (is (equal '(on-wave) (player:performance-signal performance 'ev-wave 4)))
    (is (null (player:performance-signal performance 'ev-light 5)) "no director waits for ev-light")
    (is (equal '(4d0) (run-starts performance 'cheer)))))

(test a-property-director-starts-when-its-expression-becomes-true
  (let ((performance (player:make-performance (reactive-library) '((bob humanoid)))))
    (player:perform-script performance 'lift 0)
    (flet ((visible-at (time)
             (player:property-value (player:find-object (player:performance-frame performance time) 'ball) 'visible)))
      (loop for time from 0 to 3 by 0.1d0 do (player:performance-frame performance time))
      (let ((starts (run-starts performance 'cheer)))
        (is (= 1 (length starts)) "one rising edge, one start: ~A" starts)
        ;; The ball rises 1 m/s: y > 1 first at the frame after 1 s.
        (is (and starts (< 1d0 (first starts) 1.15d0)) "started at ~A" starts))
      (is (eq t (visible-at 1.5)))
      (is (null (visible-at 1.8)) "its :set step hid the ball 0.5 s after it started")
      ;; Scrubbing back and playing again does not start it twice.
      (loop for time from 0 to 3 by 0.1d0 do (player:performance-frame performance time))
      (is (= 1 (length (run-starts performance 'cheer)))))))

(test state-and-event-directors-follow-the-controller
  (with-reactive-spec (spec)
    (let* ((presenter (player:make-body-presenter spec :scripts (reactive-library) :body 'humanoid))
           (controller (player:make-controller spec :presenter presenter))
           (performance (player:presenter-performance presenter)))
      (player:send-event controller 'ev-light)
      (is (eq t (player:state-value controller 'lit)))
      (is (equal '(1d0) (run-starts performance 'glow)) "on-lit starts when lit becomes true, at 1 s")
      (player:send-event controller 'ev-wave)
      (is (equal '(1d0) (run-starts performance 'cheer)) "on-wave starts as ev-wave is processed")
      (is (equal '((1.25d0 ev-dim)) (player:performance-sent-events performance)))
      (is (null (player:state-value controller 'lit)) "its :send reached the controller, which dimmed")
      (is (equal '(1d0 1.25d0) (run-starts performance 'glow)) "and after-wave followed on-wave")
      (player:send-event controller 'ev-light)
      (is (= 3 (length (run-starts performance 'glow))) "lit rose again: on-lit again"))))

(test reactive-directors-are-checked
  (loop for (form fragment)
          in '(((defdirector d (:when) (:start glow)) "trigger is")
               ((defdirector d (:on 3) (:start glow)) ":on takes the name of a Player event")
               ((defdirector d (:after :x) (:start glow)) ":after takes the name of a director")
               ((defdirector d (:when (> (:property ball) 1)) (:start glow)) "a property is read as")
               ((defdirector d (:when (frob (:property ball y) 1)) (:start glow)) "is not part of a property expression")
               ((defdirector d (:on ev-wave)) "at least one step")
               ((defdirector d (:after nonesuch) (:start glow)) "the library has no director nonesuch")
               ((defdirector d (:when (> (:property ball . y) 1)) (:start glow)) "a property is read as")
               ((defdirector d (:start glow) (:set (ball visible))) "a :set step is")
               ((defdirector d (:start glow) (:send ev-wave :at)) "must be :keyword value pairs")
               ((defdirector d (:send 3)) ":send takes the name of a Player event")
               ((defdirector d (:set (ball) 1)) "a property is written"))
        do (let ((text (handler-case (progn (player.performance::parse-script-library-forms
                                             (list '(defscript glow (:duration 1)) form))
                                            nil)
                         (player:script-error (e) (princ-to-string e)))))
             (is (and text (search fragment text)) "~S: ~A" form text)))
  (with-reactive-spec (spec)
    (loop for (form fragment) in '(((defdirector d (:when nonesuch) (:start glow)) "not a state expression of spec")
                                   ((defdirector d (:on ev-nonesuch) (:start glow)) "has no event ev-nonesuch")
                                   ((defdirector d (:start glow) (:send ev-nope)) "has no event ev-nope"))
          do (let* ((library (player.performance::parse-script-library-forms
                              (append *reactive-library-forms* (list form))))
                    (text (handler-case (progn (player:make-controller
                                                spec :presenter (player:make-body-presenter spec :scripts library
                                                                                                 :body 'humanoid))
                                               nil)
                            (player:script-error (e) (princ-to-string e)))))
               (is (and text (search fragment text)) "~S: ~A" form text)))))

(test reactive-directors-follow-a-timed-controller-too
  (with-reactive-spec (spec)
    (let* ((presenter (player:make-body-presenter spec :scripts (reactive-library) :body 'humanoid))
           (controller (player:make-controller spec :presenter presenter :timed t))
           (performance (player:presenter-performance presenter)))
      (player:send-event controller 'ev-light)
      (player:advance controller 2)
      (is (equal '(1d0) (run-starts performance 'glow)))
      (player:send-event controller 'ev-wave)
      (player:advance controller 6)
      (is (equal '(2d0) (run-starts performance 'cheer)))
      (is (equal '(1d0 2.25d0) (run-starts performance 'glow)))
      (is (member "(:event ev-dim :time 2.25)" (trace-of controller) :test #'string=)
          "the sent event arrives when on-wave's cheer ends")
      (is (null (player:state-value controller 'lit))))))

(test a-reloaded-library-s-directors-react
  (with-reactive-spec (spec)
    (let* ((file (format nil "~Areactive.lisp" (scratch-directory "reactive-reload")))
           (presenter (player:make-body-presenter spec :scripts (reactive-library) :body 'humanoid))
           (controller (player:make-controller spec :presenter presenter))
           (performance (player:presenter-performance presenter)))
      (with-open-file (out file :direction :output :if-exists :supersede)
        (let ((*package* (find-package '#:player-tests)))
          (dolist (form (append (remove-if (lambda (form) (eq (first form) 'defdirector)) *reactive-library-forms*)
                                '((defdirector cheer-on-light (:on ev-light) (:start cheer)))))
            (print form out))))
      (player:reload-script-library presenter spec file)
      (player:send-event controller 'ev-light)
      (is (equal '(0d0) (run-starts performance 'cheer)) "the new director reacts")
      (is (null (run-starts performance 'glow)) "the old ones are gone"))))

(test check-reports-what-reactive-directors-name-that-the-spec-lacks
  (with-reactive-spec (spec)
    (flet ((diagnostics (&rest forms)
             (player.performance::script-diagnostics
              spec (player.performance::parse-script-library-forms (append *reactive-library-forms* forms)))))
      (is (notany #'player.performance::diagnostic-error-p (diagnostics)) "the library as it is: no error")
      (let ((found (diagnostics '(defdirector d (:on ev-nonesuch) (:start glow)))))
        (is (some (lambda (d) (and (player.performance::diagnostic-error-p d)
                                   (search "has no event ev-nonesuch" (player:diagnostic-message d))))
                  found)
            "~A" (mapcar #'player:diagnostic-message found)))
      ;; A reactive director's scripts must play on the body, as an op's must.
      (let ((found (diagnostics '(defscript bend (:duration 1) (:at 0 :motor (:keyframe :keys ((0 ((r_elbow x 500)))))))
                                '(defdirector bender (:when lit) (:start bend)))))
        (is (some #'player.performance::diagnostic-error-p found) "~A" (mapcar #'player:diagnostic-message found))))))
