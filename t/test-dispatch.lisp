;;;; test-dispatch.lisp -- the whole-event controller's fast paths change
;;;; nothing: a silent presenter (one that does nothing with what it is told,
;;;; so the compiled closures skip telling it) leaves a controller exactly
;;;; where a presenter that is told everything does, and a machine whose
;;;; one-hot states are bignums (the general path) runs exactly as the same
;;;; spec whose states fit a fixnum (the typed path).

(in-package #:player-tests)

(def-suite* dispatch :in player-tests)

(defparameter *dispatch-seeds* (loop for seed from 1 to 30 collect seed)
  "Seeds of C++-RANDOM-SPEC (runtime numbers, time variables, :if with
comparisons, :time, labels, macros, autoscripts) the fast paths are checked on.")

(defclass told-presenter (null-presenter) ()
  (:documentation "A null presenter with one method of its own, so it is not
silent: the closures tell it everything, as they tell a trace presenter."))

(defmethod present-event ((presenter told-presenter) event time)
  (declare (ignore event time))
  nil)

(defun controller-after-events (machine initial events presenter &key (ignore '()))
  "Send EVENTS from INITIAL to a new controller of MACHINE with PRESENTER and
list, per event, what SEND-EVENT returned, the clock, and the state (without
the variables named in IGNORE)."
  (let ((controller (make-controller machine :initial-state initial :presenter presenter)))
    (loop for event in events
          collect (list (multiple-value-list (send-event controller event))
                        (controller-clock controller)
                        (remove-if (lambda (entry) (member (car entry) ignore))
                                   (controller-state controller))))))

(defun check-random-runs (seed check)
  "Define and compile C++-RANDOM-SPEC SEED and call CHECK with its FORMS, the
machine and each (INITIAL EVENTS) run of C++-RANDOM-RUNS; the spec is removed after."
  (multiple-value-bind (forms model extras) (c++-random-spec seed)
    (let ((name (rs-symbol "c++-random-~D" seed)))
      (unwind-protect
           (let* ((machine (compile-spec (define-spec name forms :package (find-package '#:player-user)))))
             (loop for (initial events) in (c++-random-runs seed machine model extras)
                   do (funcall check forms machine initial events)))
        (remove-spec name)))))

(test silent-presenter-runs-as-a-told-one
  "A null presenter is silent, a null presenter with a method of its own is
not; on random specs both leave the controller with the same results, clock
and state after every event."
  (is (player.control::silent-presenter-p (make-null-presenter)))
  (is (not (player.control::silent-presenter-p (make-instance 'told-presenter))))
  (is (not (player.control::silent-presenter-p (make-trace-presenter))))
  (dolist (seed *dispatch-seeds*)
    (check-random-runs
     seed (lambda (forms machine initial events)
            (declare (ignore forms))
            (is (equal (controller-after-events machine initial events (make-instance 'told-presenter))
                       (controller-after-events machine initial events (make-null-presenter)))
                "seed ~D, from ~S" seed initial)))))

(defun padded-forms (forms pad)
  "FORMS (a C++-RANDOM-SPEC body) with a first plannable variable PAD of 64
values, so every one-hot state of the spec takes more than 64 bits."
  (let ((values (loop for i below 64 collect (rs-symbol "p~D" i))))
    (append (list (first forms)
                  (list (rs-symbol "state-variable") pad (rs-symbol "string") (first values) values))
            (rest forms))))

(test bignum-states-run-as-fixnum-states
  "A random spec padded with a 64-value variable declared first has bignum
states, masks and cubes (the closures' general path); from the same initial
states and events it gives the same results, clocks and states (but for the
pad) as the spec itself, whose states are fixnums."
  (let ((pad (rs-symbol "pad")))
    (dolist (seed *dispatch-seeds*)
      (check-random-runs
       seed (lambda (forms machine initial events)
              (let ((name (rs-symbol "padded-random-~D" seed)))
                (unwind-protect
                     (let ((padded (compile-spec (define-spec name (padded-forms forms pad)
                                                   :package (find-package '#:player-user)))))
                       (is (player.control::fixnum-state-p machine))
                       (is (not (player.control::fixnum-state-p padded)))
                       (is (equal (controller-after-events machine initial events (make-null-presenter))
                                  (controller-after-events padded initial events (make-null-presenter)
                                                           :ignore (list pad)))
                           "seed ~D, from ~S" seed initial))
                  (remove-spec name))))))))

(defclass late-presenter (null-presenter) ()
  (:documentation "A null presenter that gets a method after a controller is made with it."))

(defvar *late-autoscripts* '()
  "What LATE-PRESENTER's late START-AUTOSCRIPT method was told, newest first.")

(test silence-follows-the-presenter-and-its-methods
  "A controller stops skipping its presenter when a method is defined for it
after the controller was made, and when another presenter is put in its place."
  (define-spec 'dispatch-silence
    '((state-variable lamp boolean false)
      (op switch-on :add lamp)
      (op switch-off :sub lamp)
      (autoscript lamp true (glow))
      (event ev-on :op switch-on)
      (event ev-off :op switch-off))
    :package (find-package '#:player-user))
  (unwind-protect
       (let ((controller (make-controller 'dispatch-silence :presenter (make-instance 'late-presenter)))
             (*late-autoscripts* '()))
         (send-event controller 'player-user::ev-on)
         (send-event controller 'player-user::ev-off)
         (let ((method (defmethod start-autoscript ((presenter late-presenter) proc variable value time)
                         (push (list proc time) *late-autoscripts*))))
           (unwind-protect
                (progn (send-event controller 'player-user::ev-on)
                       (is (equal '((glow 3)) *late-autoscripts*)))
             (remove-method #'start-autoscript method)))
         (send-event controller 'player-user::ev-off)
         (send-event controller 'player-user::ev-on)
         (is (= 1 (length *late-autoscripts*)) "the removed method is not called")
         (let ((trace (make-trace-presenter)))
           (setf (controller-presenter controller) trace)
           (send-event controller 'player-user::ev-off)
           (is (equal '((:event ev-off :time 5)
                        (:op switch-off :script switch-off :start 5 :end 6)
                        (:autoscript-stop glow :var lamp :value t :time 6)
                        (:state (lamp)))
                      (trace-lines trace)))))
    (remove-spec 'dispatch-silence)))

(defun same-number-p (a b)
  "Are A and B the same answer: EQL, or both NaN?"
  (or (eql a b)
      (and (floatp a) (floatp b) (sb-ext:float-nan-p a) (sb-ext:float-nan-p b))))

(test binary-numbers-match-masked-arithmetic
  "The closures' two-operand comparisons, sums, differences and products skip
masking float traps for plain numbers; over fixnums, bignums, ratios, doubles
small, huge and infinite, NaN and unset times (NIL), each answers what the
general path (every trap masked) answers."
  (let* ((inf sb-ext:double-float-positive-infinity)
         (nan (sb-int:with-float-traps-masked (:invalid)
                (locally (declare (notinline -)) (- inf inf)))) ; not folded at compile time
         (numbers (list nil 0 1 -3 most-positive-fixnum (1+ most-positive-fixnum) (expt 10 400) 1/3
                        0d0 -0d0 0.5d0 -2.5d0 1d149 -1d149 3d150 1d300 most-positive-double-float
                        least-positive-double-float inf (- inf) nan)))
    (flet ((constant (x) (lambda (controller) (declare (ignore controller)) x)))
      (macrolet ((answer (form)
                   ;; SBCL cannot compare a rational with an infinity or a
                   ;; NaN: both paths must then signal.
                   `(handler-case ,form (error () :error))))
        (dolist (a numbers)
          (dolist (b numbers)
            (dolist (operator '(< <= > >= = /=))
              (is (eq (answer (if (or (null a) (null b))
                                  (eq operator '/=)
                                  (sb-int:with-float-traps-masked (:invalid :overflow :inexact)
                                    (funcall operator a b))))
                      (answer (funcall (player.control::compile-binary-comparison operator (symbol-function operator)
                                                                          (constant a) (constant b))
                                       nil)))
                  "(~A ~S ~S)" operator a b))
            (dolist (operator '(+ - *))
              (is (same-number-p (answer (and a b (sb-int:with-float-traps-masked (:invalid :overflow :inexact :divide-by-zero)
                                                    (funcall operator a b))))
                                 (answer (funcall (player.control::compile-binary-arithmetic (symbol-function operator)
                                                                                     (constant a) (constant b))
                                                  nil)))
                  "(~A ~S ~S)" operator a b))))))))
