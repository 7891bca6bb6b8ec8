;;;; cpp-timeline.lisp -- the C++ backend's timed layer: the twin of
;;;; src/control/timeline/ (MAKE-CONTROLLER :TIMED T), emitted only when
;;;; C++-SOURCES is asked for it (EMIT-C++ :TIMED T, or RUN-C++-TRACE with a
;;;; timed scenario), so the whole-event code is exactly what it always was.
;;;;
;;;; The Controller gets send_timed, advance and finish_events.  An event is
;;;; planned ahead when it starts by planning twins of the whole-event
;;;; procedures (plan_achieve_goalN_, plan_op_X_, one plan_ev_E_(from) per
;;;; event with a case per top-level directive, so an interrupted event can
;;;; resume); they record agenda items instead of presenting.  The agenda is a
;;;; heap of items ordered by (time, seq); cuts, policies, timers and triggers
;;;; follow the Lisp runtime step for step, so the traces are identical:
;;;; several runs play at once when their footprints (the channels ops
;;;; declare, the fields and runtime variables a plan touches) are disjoint,
;;;; an event arriving while others play is planned on trial to learn its
;;;; footprint, and the events timers and triggers send wait until the rest
;;;; of their instant has happened.
;;;;
;;;; This file: checks, names, the header's declarations and the tables.
;;;; The machine-independent C++ is in resources/ (timed-*.hpp, timed-constants.cpp,
;;;; timeline-*.cpp); cpp-timeline-machine.lisp writes what is generated for each machine.

(in-package #:player.cpp)

;;;# Checks and names

(defun check-c++-interruption-points (spec)
  "Signal a PLAYER-ERROR when an op of SPEC gives :interrupt (:at NAME): a
critical time needs a script library, which the C++ controller has not."
  (dolist (op (spec-ops spec))
    (let ((interrupt (op-interrupt op)))
      (when (and (listp interrupt) (notevery #'realp interrupt))
        (error 'player-error-with-message
               :message (format nil "op ~A: :interrupt (:at ~{~A~^ ~}) names critical times; give seconds for C++ (only a script library knows critical times)"
                                (lisp-text (op-name op)) (mapcar #'lisp-text interrupt)))))))

(defparameter *c++-timed-members*
  '("send_timed" "advance" "finish_events" "busy" "now" "timeline_error" "WhenBusy")
  "The public names the timed layer adds to the Controller, kept from user names.")

(defun reserve-timed-names (table)
  "Take the timed layer's public member names in identifier TABLE."
  (dolist (name *c++-timed-members*)
    (setf (gethash name (cdr table)) t)))

(defun var-setter-id (var) (format nil "set_~A" (var-id var)))

(defun runtime-slot (var)
  "The number by which the timed layer's value items name runtime VAR."
  (var-slot var))

;;;# The header

(defun emit-timed-presenter-members ()
  "The Presenter's virtual members for the timed API."
  (emit-resource "timed-presenter-members.hpp"))

(defun emit-footprint-struct (channel-words runtime-words)
  "The Footprint struct, in the Controller; its arrays hold CHANNEL-WORDS and
RUNTIME-WORDS 64-bit words, sized for the machine (so it is written here, not
kept in resources/)."
  (emit "  // What a planned event touches (see src/control/timeline/footprints.lisp):")
  (emit "  // the channels its ops declare (ALL when one declares none), the one-hot")
  (emit "  // fields and the runtime variables (by slot) it mentions.")
  (emit "  struct Footprint {")
  (emit "    bool all = false;")
  (emit "    std::uint64_t channels[~D] = {};" channel-words)
  (emit "    StateBits fields{};")
  (emit "    std::uint64_t runtime[~D] = {};" runtime-words)
  (emit "  };"))

(defun spec-channel-names (spec)
  "The channel names SPEC's ops declare, each once, in order of first mention."
  (let ((names '()))
    (dolist (op (spec-ops spec) (nreverse names))
      (dolist (name (op-channels op))
        (pushnew name names :test #'string=)))))

(defun channel-words (spec)
  "How many 64-bit words hold a set of SPEC's channels (at least one)."
  (max 1 (ceiling (length (spec-channel-names spec)) 64)))

(defun runtime-words (machine)
  "How many 64-bit words hold a set of MACHINE's runtime variables (at least one)."
  (max 1 (ceiling (length (runtime-vars machine)) 64)))

(defun emit-timed-members (machine)
  "The timed layer's part of the Controller declaration: the API, the agenda,
and the planning twins of the machine's procedures."
  (let* ((spec (machine-spec machine))
         (timers (max 1 (length (spec-timers spec)))))
    (emit-resource "timed-api.hpp")
    (emit-resource "timed-item.hpp")
    (emit-footprint-struct (channel-words spec) (runtime-words machine))
    (emit-resource "timed-types.hpp")
    (emit "  std::shared_ptr<Item> timer_items_[~D];" timers)
    (emit "  Time timer_due_[~D] = {};" timers)
    (emit "  long long timer_seq_[~D] = {};" timers)
    (emit "  bool trigger_held_[~D] = {};" (max 1 (length (spec-triggers spec))))
    (dolist (var (runtime-vars machine))
      (when (eq (var-kind var) :number)
        (emit "  void ~A(~A value, Time time);" (planning-id (var-setter-id var)) (runtime-c++-type var))))
    (loop for goal across (machine-goal-table machine)
          do (emit "  int ~A();" (planning-id (goal-fn-id goal))))
    (dolist (op (spec-ops spec))
      (emit "  int ~A();" (planning-id (op-id op)))
      (when (eq (op-kind op) :macro)
        (emit "  int ~A();" (planning-id (macro-seq-id op)))))
    (dolist (event (spec-events spec))
      (emit "  int ~A(int from);" (planning-id (event-id event))))))

(defun macro-seq-id (op) (format nil "~A_seq" (op-id op)))

;;;# Tables

(defun policy-number (policy)
  "POLICY's number in Controller::WhenBusy."
  (1+ (position policy *when-busy-policies*)))

(defun emit-table (type name items &optional (dummy "0"))
  "const TYPE NAME[] = {ITEMS..., DUMMY}: never empty."
  (emit "[[maybe_unused]] const ~A ~A[] = {~{~A, ~}~A};" type name items dummy))

(defun emit-timed-tables (machine)
  "The timed layer's tables: policies, field masks, timers and triggers."
  (let ((spec (machine-spec machine)))
    (emit "namespace {~%")
    (emit-resource "timed-constants.cpp")  ; policy numbers as in Controller::WhenBusy
    (emit-table "int" "kEventPolicies"
                (mapcar (lambda (event) (princ-to-string (policy-number (event-policy event spec))))
                        (spec-events spec)))
    (emit-table "StateBits" "kFieldMasks" (mapcar (lambda (var) (c++-bits (var-field-mask var)))
                                                  (plannable-vars machine))
                "StateBits{}")
    (emit-table "char* const" "kTimerNames"
                (mapcar (lambda (timer) (c++-string (lisp-text (timer-name timer)))) (spec-timers spec))
                "nullptr")
    (emit-table "Time" "kTimerAfter" (mapcar (lambda (timer) (c++-time (timer-after timer))) (spec-timers spec))
                "Time{}")
    (emit-table "int" "kTimerEvents" (mapcar (lambda (timer) (princ-to-string (event-number (timer-event timer) spec)))
                                             (spec-timers spec)))
    (emit-op-footprint-tables machine)
    (emit-clash-name-tables machine)
    (emit-table "bool" "kEventRunsCode" (mapcar (lambda (event) (if (event-runs-code-p event) "true" "false"))
                                                (spec-events spec))
                "false")
    (emit-table "bool" "kTimerRepeats" (mapcar (lambda (timer) (if (timer-repeat timer) "true" "false"))
                                               (spec-timers spec))
                "false")
    (emit-table "char* const" "kTriggerNames"
                (mapcar (lambda (trigger) (c++-string (lisp-text (trigger-name trigger)))) (spec-triggers spec))
                "nullptr")
    (emit-table "int" "kTriggerEvents"
                (mapcar (lambda (trigger) (princ-to-string (event-number (trigger-event trigger) spec)))
                        (spec-triggers spec)))
    (emit "~%// The one-hot fields that differ between two states.")
    (emit "[[maybe_unused]] StateBits changed_fields(const StateBits& old_bits, const StateBits& new_bits) {")
    (emit "  const StateBits differing = differing_bits(old_bits, new_bits);")
    (emit "  StateBits mask{};")
    (emit "  for (const StateBits& field : kFieldMasks)")
    (emit "    if (bits_meet(differing, field)) add_bits(mask, field);")
    (emit "  return mask;~%}~%")
    (emit "}  // namespace~%")))

(defun op-channel-words (op names words)
  "OP's declared channels as WORDS 64-bit words, bit I for the Ith of NAMES."
  (let ((bits (reduce #'logior (op-channels op)
                      :key (lambda (name) (ash 1 (position name names :test #'string=)))
                      :initial-value 0)))
    (loop for word below words collect (c++-hex (ldb (byte 64 (* 64 word)) bits)))))

(defun emit-op-footprint-tables (machine)
  "What each op touches (OP-FOOTPRINT's twin): whether it declares no channels
(then it meets every op), the channels it declares, the fields it mentions."
  (let* ((spec (machine-spec machine))
         (ops (spec-ops-of machine))
         (names (spec-channel-names spec))
         (words (channel-words spec)))
    (emit-table "bool" "kOpChannelsAll" (mapcar (lambda (op) (if (op-channels op) "false" "true")) ops) "true")
    (emit "[[maybe_unused]] const std::uint64_t kOpChannels[][~D] = {~{{~{~A~^, ~}}, ~}{0}};"
          words (mapcar (lambda (op) (op-channel-words op names words)) ops))
    (emit-table "StateBits" "kOpFields" (mapcar (lambda (op) (c++-bits (op-variable-fields op spec))) ops)
                "StateBits{}")))

(defun emit-clash-name-tables (machine)
  "The names a :dropped line's :clash prints, as Player's trace writes them:
each channel by its bit (kChannelNames), each plannable variable beside its
field in kFieldMasks (kFieldNames), each runtime variable by its slot
\(kRuntimeNames)."
  (let* ((spec (machine-spec machine))
         (runtime (runtime-vars machine))
         (slots (make-array (1+ (reduce #'max runtime :key #'runtime-slot :initial-value -1))
                            :initial-element nil)))
    (dolist (var runtime)
      (setf (aref slots (runtime-slot var)) var))
    (flet ((text (object) (c++-string (lisp-text object))))
      (emit-table "char* const" "kChannelNames" (mapcar #'text (spec-channel-names spec)) "nullptr")
      (emit-table "char* const" "kFieldNames" (mapcar (lambda (var) (text (var-name var))) (plannable-vars machine))
                  "nullptr")
      (emit-table "char* const" "kRuntimeNames"
                  (map 'list (lambda (var) (if var (text (var-name var)) "nullptr")) slots) "nullptr"))))

(defun event-number (event spec)
  "EVENT's index among SPEC's events (its Event value)."
  (position event (spec-events spec)))
