;;;; cpp.lisp -- the C++ backend: a machine as standalone C++17 source.
;;;;
;;;; The structure is the paper's: a state struct; one state-achieving
;;;; procedure per goal (its plans as if/else in breadth-first order); one
;;;; operator-execution procedure per op; one procedure per event. Steps are the
;;;; IR of ir.lisp, emitted by EMIT-STEP methods beside COMPILE-STEP's. The
;;;; one-hot state is one 64-bit word, or as many as a wide spec needs
;;;; (cpp-words.lisp). The code needs only the standard library; traces print
;;;; exactly as Lisp's.

(in-package #:player.cpp)

(defvar *out* *standard-output* "Where the C++ being generated goes.")

(defvar *names* nil "The C++NAMES of the machine being generated.")

(defvar *c++-timed* nil
  "True while the machine being generated gets the timed layer too (see
cpp-timeline.lisp): advance, send_timed and finish_events on the Controller.")

(defstruct (c++-names (:constructor %make-c++-names))
  "Identifiers for every named thing of one machine."
  (table (make-identifier-table))
  (machine nil))

(defun emit (control &rest arguments)
  "Write one formatted line of C++."
  (apply #'format *out* control arguments)
  (terpri *out*))

(defun id (object name &optional (prefix ""))
  "OBJECT's identifier in the current machine."
  (c++-identifier object name (c++-names-table *names*) :prefix prefix))

(defun var-id (var) (id var (var-name var) "v_"))
(defun op-id (op) (id op (op-name op) "op_"))
(defun goal-fn-id (goal) (id goal (format nil "goal~D" (goal-id goal)) "achieve_"))
(defun event-id (event) (id event (event-name event) "ev_"))
(defun event-enum (event) (id (cons :enum event) (event-name event)))
(defun enum-type (var) (id (cons :type var) (concatenate 'string (symbol-name (var-name var)) "-value") "T_"))

(defun value-text (var index)
  "The trace text of plannable VAR's INDEXth value."
  (if (eq (var-kind var) :boolean)
      (if (= index 1) "t" "nil")
      (lisp-text (aref (var-domain var) index))))

(defun spec-ops-of (machine) (spec-ops (machine-spec machine)))

;;; Errors

(define-condition c++-name-error (player-error)
  ((argument :initarg :argument :reader c++-name-error-argument)
   (value :initarg :value :reader c++-name-error-value)
   (reason :initarg :reason :reader c++-name-error-reason))
  (:report (lambda (condition stream)
             (format stream "emit-c++: ~(~S~) ~A is ~A"
                     (c++-name-error-argument condition)
                     (let ((value (c++-name-error-value condition)))
                       (if (stringp value)
                           (c++-string value)
                           (let ((*print-length* 10) (*print-level* 3) (*print-circle* t))
                             (truncate-text (prin1-to-string value) 60))))
                     (c++-name-error-reason condition))))
  (:documentation "EMIT-C++'s :NAME or :NAMESPACE is not a usable C++ identifier."))

(define-condition c++-range-error (player-error)
  ((spec :initarg :spec :reader c++-range-error-spec)
   (variable :initarg :variable :reader c++-range-error-variable)
   (value :initarg :value :reader c++-range-error-value)
   (what :initarg :what :reader c++-range-error-what
         :documentation "Which number: \"value\", \"initial value\", \"autoscript value\" or \":add/:sub delta\"."))
  (:report (lambda (condition stream)
             (format stream "in spec ~A: the ~A ~D of variable ~A does not fit in a 64-bit signed integer (the C++ backend's long long)"
                     (lisp-text (c++-range-error-spec condition))
                     (c++-range-error-what condition)
                     (c++-range-error-value condition)
                     (lisp-text (c++-range-error-variable condition)))))
  (:documentation "An integer of a spec lies outside the C++ backend's 64 bits."))

(defun check-c++-int64 (spec var value what)
  "Signal a C++-RANGE-ERROR unless VALUE (the WHAT of integer VAR in SPEC) fits 64 bits."
  (unless (c++-int64-p value)
    (error 'c++-range-error :spec (spec-name spec) :variable (var-name var) :value value :what what)))

(defun check-c++-deltas (spec steps)
  "Check the integer :add/:sub deltas among STEPS (and inside their :if bodies).
A delta of 2^63 is the :sub of -2^63, which the C++ writes as a subtraction."
  (dolist (step steps)
    (typecase step
      (if-step (check-c++-deltas spec (if-step-body step)))
      (increment-step
       (let ((var (increment-step-variable step)) (delta (increment-step-delta step)))
         (when (and (eq (var-type var) :integer) (not (c++-int64-p (- delta))))
           (check-c++-int64 spec var delta ":add/:sub delta")))))))

(defun check-c++-integers (machine)
  "Signal a C++-RANGE-ERROR for the first integer of MACHINE's spec that a C++
long long cannot hold: an enumerated value, a runtime initial value, a value an
autoscript watches, or an :add/:sub delta."
  (let ((spec (machine-spec machine)))
    (dolist (var (spec-variables spec))
      (when (eq (var-type var) :integer)
        (if (eq (var-kind var) :enumerated)
            (loop for value across (var-domain var) do (check-c++-int64 spec var value "value"))
            (check-c++-int64 spec var (var-initial var) "initial value"))))
    (dolist (auto (spec-autoscripts spec))
      (let ((var (autoscript-variable auto)))
        (when (and (eq (var-kind var) :number) (eq (var-type var) :integer))
          (check-c++-int64 spec var (autoscript-value-index auto) "autoscript value"))))
    (dolist (event (spec-events spec))
      (check-c++-deltas spec (directive-steps (event-directives event) machine)))))

;;; Entry points

(defparameter *c++-name-limit* 200
  "The longest :NAME EMIT-C++ takes, so NAME.hpp stays a legal file name.")

(defun check-c++-name (argument value)
  "VALUE, when it can be EMIT-C++'s ARGUMENT (:name or :namespace); else a C++-NAME-ERROR."
  (flet ((fail (reason) (error 'c++-name-error :argument argument :value value :reason reason)))
    (unless (c++-identifier-text-p value)
      (fail "not a C++ identifier (an ASCII letter or _, then letters, digits or _; no __, no _ before a capital, not a keyword or a macro of the C headers)"))
    (when (> (length value) *c++-name-limit*)
      (fail (format nil "longer than ~D characters" *c++-name-limit*)))
    value))

(defun output-file (directory name type)
  "The pathname of file NAME.TYPE in DIRECTORY, checked to lie directly inside it."
  (let ((path (merge-pathnames (make-pathname :name name :type type) directory)))
    (unless (and (equal (pathname-directory path) (pathname-directory directory))
                 (equal (pathname-name path) name)
                 (equal (pathname-type path) type)
                 (not (wild-pathname-p path)))
      (error 'player-error-with-message
             :message (format nil "emit-c++: ~A would be written outside ~A"
                              (namestring path) (namestring directory))))
    path))

(defun emit-c++ (machine directory &key name namespace timed)
  "Write NAME.hpp and NAME.cpp for MACHINE (or a spec or its name) into
DIRECTORY: standalone C++17 with a Presenter to implement and a Controller
class. NAME defaults to the spec's name, NAMESPACE to NAME, both made C++
identifiers; given, each must satisfy C++-IDENTIFIER-TEXT-P (else a
C++-NAME-ERROR). Integers beyond 64 bits are a C++-RANGE-ERROR; the one-hot
state may have any number of bits (kStateWords words of 64). With TIMED,
the Controller also has the timed API of MAKE-CONTROLLER :TIMED T (advance,
send_timed, finish_events; policies, cuts, timers and triggers); a spec
whose :interrupt names critical times is then a PLAYER-ERROR. Returns the
two pathnames, both inside DIRECTORY."
  (check-argument 'emit-c++ 'directory directory #'pathname-designator-p *path-phrase*)
  (let* ((machine (ensure-machine machine 'emit-c++))
         (name (if name
                   (check-c++-name :name name)
                   (c++-safe-identifier (spec-name (machine-spec machine)))))
         (namespace (if namespace (check-c++-name :namespace namespace) name))
         (directory (directory-pathname directory))
         (hpp (output-file directory name "hpp"))
         (cpp (output-file directory name "cpp")))
    (multiple-value-bind (header source) (c++-sources machine name namespace :timed timed)
      ;; Both on the disk before either is replaced: the pair always matches.
      (write-files-together (list (cons hpp header) (cons cpp source)) :make-directories t))))

(defun write-text-file (path text)
  "Write TEXT to PATH in UTF-8, replacing it atomically (never through a link)."
  (write-file-string path text))

(defun c++-sources (machine name namespace &key timed)
  "(VALUES HEADER-TEXT SOURCE-TEXT) for MACHINE; with TIMED, the Controller
also has the timed API (see cpp-timeline.lisp), and a spec whose :interrupt
names critical times is a PLAYER-ERROR."
  (let* ((*c++-timed* timed)
         (*names* (%make-c++-names :machine machine))
         (spec (machine-spec machine))
         (*state-words* (state-word-count spec))
         (*state-bit-count* (spec-bit-count spec)))
    (check-c++-integers machine)
    (when timed
      (check-c++-interruption-points spec)
      (reserve-timed-names (c++-names-table *names*)))
    (values (with-output-to-string (*out*) (emit-header machine name namespace))
            (with-output-to-string (*out*) (emit-source machine name namespace)))))

;;; Header

(defun emit-banner (machine file)
  "The comment that opens each generated file."
  (let ((spec (machine-spec machine)))
    (emit "// ~A -- generated by Player from spec ~A; do not edit."
          file (c++-comment-text (lisp-text (spec-name spec))))
    (when (spec-documentation spec)
      (emit "// ~A" (c++-comment-text (spec-documentation spec))))
    (emit "// Standard C++17; needs nothing but the standard library.")))

(defun plannable-vars (machine) (plannable-variables (machine-spec machine)))
(defun runtime-vars (machine) (remove-if #'plannable-p (spec-variables (machine-spec machine))))

(defun emit-header (machine name namespace)
  "The .hpp: events, ops, the Presenter interface, the State and the Controller."
  (let* ((spec (machine-spec machine))
         (guard (string-upcase (format nil "PLAYER_~A_HPP" (c++-base-identifier name)))))
    (emit-banner machine (format nil "~A.hpp" name))
    (emit "#ifndef ~A~%#define ~A~%" guard guard)
    (when (wide-state-p) (emit "#include <array>"))
    (if *c++-timed*
        (emit "#include <cstdint>~%#include <deque>~%#include <memory>~%#include <string>~%#include <vector>~%")
        (emit "#include <cstdint>~%#include <string>~%"))
    (emit "namespace ~A {~%" namespace)
    (emit-state-bits-type)
    (emit "/// The events the controller accepts.")
    (emit "enum class Event : int {~{~%  ~A,~}~%};" (mapcar #'event-enum (spec-events spec)))
    (emit "constexpr int event_count = ~D;" (length (spec-events spec)))
    (emit "/// The Lisp name of E, e.g. \"ev-search\".")
    (emit "const char* event_name(Event e);")
    (emit "/// Look an event up by its Lisp name; false when there is none.")
    (emit "bool find_event(const std::string& name, Event& out);~%")
    (emit "/// A time or number as Player's trace prints it: rounded to the microsecond,")
    (emit "/// integral values without a fraction, trailing zeros dropped.")
    (emit "std::string format_number(double x);~%")
    (emit-resource "time.hpp")
    (emit "")
    (emit "/// An operator as the presenter sees it. KIND is \"script\", \"director\", \"code\" or \"macro\";")
    (emit "/// SCRIPT names the script (or the director); DURATION is the declared :duration.")
    (emit "struct Op { const char* name; const char* kind; const char* script; double duration; };~%")
    (emit "class Controller;~%")
    (emit-presenter-class)
    (dolist (var (plannable-vars machine))
      (when (eq (var-kind var) :enumerated)
        (emit "enum class ~A : int {~{ ~A~^,~} };" (enum-type var)
              (loop for value across (var-domain var)
                    for i from 0
                    collect (id (cons var i) (value-name value) "k_")))))
    (emit-state-struct machine)
    (emit "/// The declared initial state.")
    (emit "State initial_state();")
    (emit "/// Set VARIABLE to VALUE (both as Player prints them, e.g. \"posture\", \"sit\", \"t\", \"2.5\") in STATE.")
    (emit "bool assign(State& state, const std::string& variable, const std::string& value);~%")
    (emit-controller-class machine)
    (emit "}  // namespace ~A~%~%#endif" namespace)))

(defun emit-presenter-class ()
  "The abstract presenter an embedding program implements."
  (emit-resource "presenter.hpp")
  (when *c++-timed* (emit-timed-presenter-members))
  (emit "};~%"))

(defun runtime-c++-type (var)
  "The C++ type of runtime variable VAR."
  (if (and (eq (var-kind var) :number) (eq (var-type var) :integer)) "long long" "double"))

(defun emit-state-struct (machine)
  "The State struct: one-hot plannable bits, runtime variables, labels."
  (let ((spec (machine-spec machine)))
    (emit "~%/// One agent's state. Plannable variables live one-hot in BITS (read them")
    (emit "/// through the Controller's accessors); time variables are NaN until set.")
    (emit "struct State {")
    (emit "  StateBits bits = {};")
    (dolist (var (runtime-vars machine))
      (emit "  ~A ~A = 0;  // ~A" (runtime-c++-type var) (var-id var)
            (c++-comment-text (lisp-text (var-name var)))))
    (emit "  Time labels[~D] = {};" (max 1 (spec-label-count spec)))
    (emit "};~%")))

(defun emit-controller-class (machine)
  "The Controller class declaration."
  (let ((spec (machine-spec machine)))
    (emit "/// One agent. Any number can run side by side; there are no globals.")
    (emit "class Controller {")
    (emit "public:")
    (emit "  Controller(Presenter& presenter, const State& state = initial_state(), Time clock = Time{});")
    (emit "  Controller(Presenter& presenter, const State& state, double clock)")
    (emit "      : Controller(presenter, state, Time::from_seconds(clock)) {}")
    (emit "  /// Process E at clock() (or AT); true on success. On failure failed_goal() says why.")
    (emit "  bool send(Event e) { return send_at(e, clock_); }")
    (emit "  bool send_at(Event e, Time at);")
    (emit "  bool send_at(Event e, double at) { return send_at(e, Time::from_seconds(at)); }")
    (emit "  const char* failed_goal() const { return failed_goal_; }")
    (emit "  /// When the next event starts: the end of the last op of the previous one.")
    (emit "  Time clock() const { return clock_; }")
    (emit "  const State& state() const { return state_; }")
    (emit "  /// The state as Player's trace prints it: (:state (var . value) ...).")
    (emit "  std::string state_line() const;")
    (dolist (var (spec-variables spec))
      (emit "  ~A ~A() const;" (accessor-type var) (id (cons :get var) (var-name var))))
    (emit "private:")
    (emit "  Presenter& presenter_;")
    (emit "  State state_;")
    (emit "  Time clock_, schedule_, span_start_, span_end_;")
    (emit "  const char* failed_goal_ = \"\";")
    (emit "  bool active_[~D] = {};" (max 1 (length (spec-ops spec))))
    (emit "  int fail(const char* goal) { failed_goal_ = goal; return 2; }")
    (emit "  void note_op_end(Time end) { schedule_ = end; if (end > span_end_) span_end_ = end; }")
    (emit "  void transition(~A, Time time);" (c++-bits-parameter "next"))
    (when (watched-plannable-vars machine)
      (emit "  void notify_autoscripts_(~A, ~A, Time time);"
            (c++-bits-parameter "before") (c++-bits-parameter "next")))
    (emit "  void start_initial_autoscripts(Time time);")
    (dolist (var (runtime-vars machine))
      (when (eq (var-kind var) :number)
        (emit "  void set_~A(~A value, Time time);" (var-id var) (runtime-c++-type var))))
    ;; Inline, though defined in the .cpp (the only place that calls them), so
    ;; the compiler may flatten an event, its plans and its ops into one procedure.
    (emit "  // The procedures of goals, ops and events (defined and used in the .cpp).")
    (loop for goal across (machine-goal-table machine)
          do (emit "  inline int ~A();" (goal-fn-id goal)))
    (dolist (op (spec-ops spec))
      (emit "  inline int ~A();" (op-id op))
      (when (eq (op-kind op) :macro) (emit "  inline int ~A_seq();" (op-id op))))
    (dolist (event (spec-events spec))
      (emit "  inline int ~A();" (event-id event)))
    (when *c++-timed* (emit-timed-members machine))
    (emit "};~%")))

(defun accessor-type (var)
  "The C++ type a Controller accessor returns for VAR."
  (ecase (var-kind var)
    (:boolean "bool")
    (:enumerated (enum-type var))
    (:number (runtime-c++-type var))
    (:time "double")))
