;;;; cpp-source.lisp -- the C++ backend's .cpp: procedures for goals, ops, events.

(in-package #:player.cpp)

(defun op-index (op machine) (position op (spec-ops-of machine)))

(defun field-index-expression (var bits)
  "C++ for the value index of plannable VAR in the one-hot BITS expression."
  (format nil "field_index(~A, ~D, ~D)" bits (var-bit-offset var) (var-domain-size var)))

(defun emit-text (text)
  "Write TEXT, C++ taken as it is (no FORMAT directives), and a newline."
  (write-string text *out*)
  (terpri *out*))

(defun emit-source (machine name namespace)
  "The .cpp: helpers, tables, and every procedure."
  (let ((spec (machine-spec machine)))
    (emit-banner machine (format nil "~A.cpp" name))
    (emit "#include \"~A.hpp\"~%" name)
    (when *c++-timed* (emit "#include <algorithm>~%#include <cstring>"))
    (emit-text "#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <string>
")
    (emit "namespace ~A {~%namespace {~%" namespace)
    (emit-state-bits-helpers)
    (emit-resource "helpers.cpp")
    (dolist (var (plannable-vars machine))
      (when (and (eq (var-kind var) :enumerated) (every #'integerp (var-domain var)))
        (emit "[[maybe_unused]] const long long kValues_~A[] = {~{~A~^, ~}};" (var-id var)
              (map 'list #'c++-int64 (var-domain var)))))
    (emit-op-table machine)
    (emit "const char* const kEventNames[] = {~{~A, ~}nullptr};~%"
          (mapcar (lambda (e) (c++-string (lisp-text (event-name e)))) (spec-events spec)))
    (emit "}  // namespace~%")
    (emit-resource "format-number.cpp")  ; printing exactly as FORMAT-NUMBER does
    (emit-resource "time.cpp")           ; exact times, as EXACT-TIMES.LISP
    (emit "const char* event_name(Event e) { return kEventNames[static_cast<int>(e)]; }~%")
    (emit "bool find_event(const std::string& name, Event& out) {")
    (emit "  for (int i = 0; i < event_count; ++i)")
    (emit "    if (name == kEventNames[i]) { out = static_cast<Event>(i); return true; }")
    (emit "  return false;~%}~%")
    (emit-initial-state machine)
    (emit-assign machine)
    (emit-controller-basics machine)
    (emit-transition machine)
    (loop for goal across (machine-goal-table machine) do (emit-achiever goal machine))
    (dolist (op (spec-ops spec)) (emit-executor op machine))
    (dolist (event (spec-events spec)) (emit-event event machine))
    (when *c++-timed* (emit-timed-source machine))
    (emit "}  // namespace ~A" namespace)))

(defun op-script-text (op)
  "What kOps lists as OP's script: the director, the script, or (for :code) its name."
  (lisp-text (case (op-kind op)
               (:director (op-director op))
               ((:script :macro) (op-script op))
               (t (op-name op)))))

(defun op-row (op)
  "OP's initializer in kOps: {name, kind, script, duration}."
  (format nil "{~{~A~^, ~}}"
          (list (c++-string (lisp-text (op-name op)))
                (c++-string (string-downcase (symbol-name (op-kind op))))
                (c++-string (op-script-text op))
                (c++-double (op-duration op)))))

(defun emit-op-table (machine)
  "kOps: every op as the presenter sees it, in spec order (one dummy when there are none)."
  (emit "[[maybe_unused]] const Op kOps[] = {")
  (dolist (op (spec-ops-of machine))
    (emit "  ~A,  // ~A" (op-row op) (op-id op)))
  (when (null (spec-ops-of machine)) (emit "  {\"\", \"script\", \"\", 0.0}"))
  (emit "};~%"))

(defun runtime-literal (var value)
  "C++ for VALUE of runtime VAR: a long long or a double literal."
  (if (and (eq (var-kind var) :number) (eq (var-type var) :integer))
      (c++-int64 value)
      (c++-double value)))

(defun emit-initial-state (machine)
  "initial_state(): the declared initial values."
  (emit "State initial_state() {~%  State s;")
  (emit "  s.bits = ~A;" (c++-bits (machine-initial-state machine)))
  (dolist (var (runtime-vars machine))
    (emit "  s.~A = ~A;" (var-id var)
          (if (eq (var-kind var) :time)
              "std::nan(\"\")"
              (runtime-literal var (var-initial var)))))
  (emit "  return s;~%}~%"))

(defun value-texts (var index)
  "The texts assign() takes for plannable VAR's INDEXth value."
  (if (eq (var-kind var) :boolean)
      (if (= index 1) '("t" "true") '("nil" "false"))
      (list (value-text var index))))

(defun emit-assign-plannable (var)
  "The body of assign() for plannable VAR: one test per value."
  (loop for i below (var-domain-size var)
        do (emit "    if (~{value == ~A~^ || ~}) { s.bits = ~A; return true; }"
                 (mapcar #'c++-string (value-texts var i))
                 (c++-with-delta "s.bits" (var-field-mask var) (var-value-bit var i))))
  (emit "    return false;"))

(defun emit-assign-number (var)
  "The body of assign() for runtime VAR: the whole text must be a number of its
type, in range (a long long, or a finite double)."
  (emit "    char* end = nullptr;")
  (if (string= (runtime-c++-type var) "long long")
      (progn
        (emit "    errno = 0;")
        (emit "    const long long v = std::strtoll(value.c_str(), &end, 10);")
        (emit "    if (end == value.c_str() || *end != 0 || errno == ERANGE) return false;"))
      (progn
        (emit "    const double v = std::strtod(value.c_str(), &end);")
        (emit "    if (end == value.c_str() || *end != 0 || !std::isfinite(v)) return false;")))
  (emit "    s.~A = v;" (var-id var))
  (emit "    return true;"))

(defun emit-assign (machine)
  "assign(): set one variable from its printed name and value."
  (let ((variables (spec-variables (machine-spec machine))))
    (emit "bool assign(State& s, const std::string& variable, const std::string& value) {")
    (unless variables
      (emit "  (void)s; (void)variable; (void)value;"))
    (dolist (var variables)
      (emit "  if (variable == ~A) {" (c++-string (lisp-text (var-name var))))
      (if (plannable-p var) (emit-assign-plannable var) (emit-assign-number var))
      (emit "  }"))
    (emit "  return false;~%}~%")))

(defun emit-controller-basics (machine)
  "Constructor, send, accessors and state_line."
  (let ((spec (machine-spec machine)))
    (emit "Controller::Controller(Presenter& presenter, const State& state, Time clock)")
    (emit "    : presenter_(presenter), state_(state), clock_(clock) {")
    (emit "  start_initial_autoscripts(clock);~%}~%")
    (emit "bool Controller::send_at(Event e, Time at) {")
    (emit "  schedule_ = span_start_ = span_end_ = at;")
    (emit "  failed_goal_ = \"\";")
    (emit "  presenter_.event_start(event_name(e), at);")
    (emit "  int result = 1;")
    (emit "  switch (e) {")
    (dolist (event (spec-events spec))
      (emit "    case Event::~A:" (event-enum event))
      (dolist (var (event-time-variables event))
        (emit "      state_.~A = at.to_double();" (var-id var)))
      (emit "      result = ~A();~%      break;" (event-id event)))
    (emit "  }")
    (emit "  if (result != 1) presenter_.event_failed(event_name(e), failed_goal_, schedule_);")
    (emit "  clock_ = span_end_;")
    (emit "  presenter_.event_end(*this);")
    (emit "  return result == 1;~%}~%")
    (dolist (var (spec-variables spec))
      (let ((getter (id (cons :get var) (var-name var))))
        (ecase (var-kind var)
          (:boolean (emit "bool Controller::~A() const { return ~A; }"
                          getter (c++-bit-set-p (var-value-bit var 1) "state_.bits")))
          (:enumerated (emit "~A Controller::~A() const { return static_cast<~A>(~A); }"
                             (enum-type var) getter (enum-type var)
                             (field-index-expression var "state_.bits")))
          ((:number :time) (emit "~A Controller::~A() const { return state_.~A; }"
                                 (accessor-type var) getter (var-id var))))))
    (emit "~%std::string Controller::state_line() const {~%  std::string line = \"(:state\";")
    (dolist (var (spec-variables spec))
      (emit "  line += ~A;" (c++-string (format nil " (~A . " (lisp-text (var-name var)))))
      (ecase (var-kind var)
        ((:boolean :enumerated)
         (emit "  switch (~A) {" (field-index-expression var "state_.bits"))
         (loop for i below (var-domain-size var)
               do (emit "    case ~D: line += ~A; break;" i (c++-string (value-text var i))))
         (emit "    default: break;~%  }"))
        (:number (if (eq (var-type var) :integer)
                     (emit "  line += std::to_string(state_.~A);" (var-id var))
                     (emit "  line += format_number(state_.~A);" (var-id var))))
        (:time (emit "  line += std::isnan(state_.~A) ? std::string(\"nil\") : format_number(state_.~A);"
                     (var-id var) (var-id var))))
      (emit "  line += \")\";"))
    (emit "  return line + \")\";~%}~%")))

(defun autoscript-test (auto current)
  "C++ true when CURRENT, an expression of AUTO's variable (a value index for a
plannable one), holds the value AUTO watches; numbers compare as EQL does."
  (let ((var (autoscript-variable auto)) (value (autoscript-value-index auto)))
    (if (plannable-p var)
        (format nil "~A == ~D" current value)
        (format nil "same_value(~A, ~A)" current (runtime-literal var value)))))

(defun autoscript-call (auto proc function-name test &optional (time "time"))
  "C++ calling the presenter's FUNCTION-NAME for PROC of AUTO at TIME (a C++
expression) when TEST holds."
  (format nil "if (~A) presenter_.~A(~{~A~^, ~}, ~A);" test function-name
          (mapcar #'c++-string (list (lisp-text proc)
                                     (lisp-text (var-name (autoscript-variable auto)))
                                     (lisp-text (autoscript-value auto))))
          time))

(defun autoscript-calls (machine var function-name value-expression)
  "C++ lines calling FUNCTION-NAME for VAR's autoscripts whose value equals VALUE-EXPRESSION."
  (loop for auto in (spec-autoscripts (machine-spec machine))
        when (eq (autoscript-variable auto) var)
          append (loop for proc in (autoscript-procs auto)
                       collect (autoscript-call auto proc function-name
                                                (autoscript-test auto value-expression)))))

(defun watched-vars (machine)
  "Variables some autoscript watches, in declaration order."
  (let ((watched (mapcar #'autoscript-variable (spec-autoscripts (machine-spec machine)))))
    (remove-if-not (lambda (var) (member var watched)) (spec-variables (machine-spec machine)))))

(defun watched-plannable-vars (machine)
  "Plannable variables some autoscript watches, in declaration order."
  (remove-if-not #'plannable-p (watched-vars machine)))

(defun plannable-autoscript-calls (machine var function-name bits &optional (time "time"))
  "C++ lines calling FUNCTION-NAME (at TIME) for plannable VAR's autoscripts
whose value is set in the StateBits expression BITS (one bit test each)."
  (loop for auto in (spec-autoscripts (machine-spec machine))
        when (eq (autoscript-variable auto) var)
          append (loop with test = (c++-bit-set-p (var-value-bit var (autoscript-value-index auto)) bits)
                       for proc in (autoscript-procs auto)
                       collect (autoscript-call auto proc function-name test time))))

(defun autoscript-change-lines (machine var before after time)
  "C++ lines stopping and starting watched plannable VAR's autoscripts when
its field differs between the StateBits expressions BEFORE and AFTER, at TIME."
  (append (list (format nil "if (~A) {" (c++-bits-differ before after (var-field-mask var))))
          (mapcar (lambda (line) (concatenate 'string "  " line))
                  (append (plannable-autoscript-calls machine var "stop_autoscript" before time)
                          (plannable-autoscript-calls machine var "start_autoscript" after time)))
          (list "}")))

(defun state-change-lines (machine time mask values)
  "C++ lines setting the fields MASK of the state to VALUES at TIME: an op's
effects or an :add/:sub. The autoscripts of just those fields are told,
inline, so a change that no autoscript watches is one store (a store per
word it touches)."
  (let ((watched (remove-if (lambda (var) (zerop (logand mask (var-field-mask var))))
                            (watched-plannable-vars machine))))
    (if (null watched)
        (c++-delta-statements "state_.bits" mask values)
        ;; NEXT held in a constant, so the compiler folds the tests the effects decide.
        (append (list "{"
                      "  const StateBits before = state_.bits;"
                      (format nil "  const StateBits next = ~A;" (c++-with-delta "before" mask values))
                      "  state_.bits = next;")
                (loop for var in watched
                      append (mapcar (lambda (line) (concatenate 'string "  " line))
                                     (autoscript-change-lines machine var "before" "next" time)))
                (list "}")))))

(defun emit-transition (machine)
  "transition(), number setters and the initial autoscripts. transition() is
any state change (a macro's end, the timed layer's changes); small enough to
inline: a store and, when a watched field changed, the call of
notify_autoscripts_(). An op's own change is STATE-CHANGE-LINES'."
  (let ((watched (watched-plannable-vars machine)))
    (emit "void Controller::transition(~A, Time time) {" (c++-bits-parameter "next"))
    (if watched
        (progn
          (emit "  const StateBits before = state_.bits;")
          (emit "  state_.bits = next;")
          (emit "  if (~A) notify_autoscripts_(before, next, time);"
                (c++-bits-differ "before" "next" (machine-autoscript-mask machine))))
        (emit "  state_.bits = next;~%  (void)time;"))
    (emit "}~%")
    (when watched
      (emit "// Stop the autoscripts of the values watched fields left, start those of the values they took.")
      (emit "void Controller::notify_autoscripts_(~A, ~A, Time time) {"
            (c++-bits-parameter "before") (c++-bits-parameter "next"))
      (dolist (var watched)
        (dolist (line (autoscript-change-lines machine var "before" "next" "time"))
          (emit "  ~A" line)))
      (emit "}~%")))
  (dolist (var (runtime-vars machine))
    (when (eq (var-kind var) :number)
      (emit "void Controller::set_~A(~A value, Time time) {" (var-id var) (runtime-c++-type var))
      (emit "  const ~A old_value = state_.~A;" (runtime-c++-type var) (var-id var))
      (emit "  state_.~A = value;" (var-id var))
      (emit "  if (same_value(old_value, value)) return;")
      (emit "  const ~A new_value = value;" (runtime-c++-type var))
      (emit "  (void)time; (void)new_value;")
      (dolist (line (autoscript-calls machine var "stop_autoscript" "old_value")) (emit "  ~A" line))
      (dolist (line (autoscript-calls machine var "start_autoscript" "new_value")) (emit "  ~A" line))
      (emit "}~%")))
  (emit "void Controller::start_initial_autoscripts(Time time) {")
  (emit "  (void)time;")
  (dolist (auto (spec-autoscripts (machine-spec machine)))
    (let* ((var (autoscript-variable auto))
           (current (if (plannable-p var)
                        (field-index-expression var "state_.bits")
                        (format nil "state_.~A" (var-id var)))))
      (dolist (proc (autoscript-procs auto))
        (emit "  ~A" (autoscript-call auto proc "start_autoscript" (autoscript-test auto current))))))
  (emit "}~%"))

(defun emit-achiever (goal machine)
  "GOAL's state-achieving procedure: 1 reached, 0 no plan, 2 a macro inside failed."
  (let ((spec (machine-spec machine)))
    (emit "// Goal ~A" (c++-comment-text (lisp-text (goal-expression goal))))
    (emit "int Controller::~A() {" (goal-call-id goal))
    (emit "  const StateBits~:[~;&~] s = state_.bits;" (wide-state-p))
    (emit "  (void)s;")
    (loop for plan across (goal-plans goal)
          for keyword = "if" then "else if"
          do (emit "  ~A (~A) {  // ~A" keyword (c++-cube-holds (plan-condition plan) "s")
                   (c++-comment-text (lisp-text (cube-expression (plan-condition plan) spec))))
             (dolist (op (plan-ops plan))
               (emit "    if (~A() != 1) return 2;" (op-call-id op)))
             (emit "    return 1;~%  }"))
    (emit "  return 0;~%}~%")))

(defun effects-expression (op bits-expression)
  "C++ for BITS-EXPRESSION (StateBits) with OP's effects applied."
  (c++-with-delta bits-expression (op-effect-mask op) (op-effect-bits op)))

(defun emit-op-procedure-opening (op id)
  "Open the procedure ID that plays OP: its :c++ text, and for a :code op the
embedder's hook (the whole-event procedure and its timed planning twin alike)."
  (emit "int Controller::~A() {" id)
  (when (op-c++ op) (emit "  ~A" (op-c++ op)))
  (when (eq (op-kind op) :code)
    (emit "  // :code ~A has no C++ meaning: the embedder implements the hook."
          (code-comment-text (op-code op)))
    (emit "  presenter_.code_hook(~A);" (c++-string (lisp-text (op-name op))))))

(defun emit-executor (op machine)
  "OP's operator-execution procedure (its precondition is the caller's business)."
  (let ((index (op-index op machine)))
    (if (eq (op-kind op) :macro)
        (emit-macro-executor op index machine)
        (progn
          (emit-op-procedure-opening op (op-id op))
          (emit "  const Time start = schedule_;")
          (emit "  const Time end = start + Time::from_seconds(presenter_.~A(kOps[~D], start));"
                (if (eq (op-kind op) :director) "run_director" "play") index)
          (emit "  note_op_end(end);")
          (when (op-effects op)
            (dolist (line (state-change-lines machine "end" (op-effect-mask op) (op-effect-bits op)))
              (emit "  ~A" line)))
          (emit "  return 1;~%}~%")))))

(defun emit-macro-executor (op index machine)
  "A macro-op: its :SEQ on its own span, then the declared effects on the state it started from."
  (emit "int Controller::~A() {" (op-id op))
  (emit "  if (active_[~D]) return fail(~A);" index (c++-string (lisp-text (op-name op))))
  (when (op-c++ op) (emit "  ~A" (op-c++ op)))
  (emit "  const Time start = schedule_, outer_start = span_start_, outer_end = span_end_;")
  (emit "  const StateBits before = state_.bits;")
  (emit "  presenter_.macro_start(kOps[~D], start);" index)
  (emit "  span_start_ = span_end_ = start;")
  (emit "  active_[~D] = true;" index)
  (emit "  const int result = ~A_seq();" (op-id op))
  (emit "  const Time end = span_end_;")
  (emit "  active_[~D] = false;" index)
  (emit "  span_start_ = outer_start;")
  (emit "  span_end_ = outer_end > end ? outer_end : end;")
  (emit "  schedule_ = end;")
  (emit "  presenter_.macro_end(kOps[~D], start, end);" index)
  (emit "  if (result == 1) transition(~A, end);" (effects-expression op "before"))
  (emit "  return result;~%}~%")
  (emit "int Controller::~A_seq() {" (op-id op))
  (emit-steps (directive-steps (op-seq op) machine) "  " machine (op-name op))
  (emit "  return 1;~%}~%"))

(defun emit-event (event machine)
  "An event procedure: its steps in order; 1 on success, 2 after a failure."
  (emit "int Controller::~A() {" (event-id event))
  (emit-steps (directive-steps (event-directives event) machine) "  " machine (event-name event))
  (emit "  return 1;~%}~%"))
