;;;; cpp-build.lisp -- compile generated C++ with a trace-printing driver and
;;;; run it: `bin/player run --backend c++`. Builds are cached by content.

(in-package #:player)

(defparameter *c++-flags* '("-std=c++17" "-O2" "-Wall" "-Wextra" "-Werror" "-pedantic")
  "How generated code is compiled; it must build cleanly with these.")

(defparameter *c++-compiler* "g++"
  "The compiler command, looked up on PATH.")

(defparameter *driver-presenter*
  "namespace {

std::string number(double x) { return ctl::format_number(x); }

void print_line(const std::string& line) {
  std::fwrite(line.data(), 1, line.size(), stdout);
  std::fputc(0, stdout);
}

// Records lines like Player's trace presenter; a macro's line waits for its end.
// Each line is written with a NUL after it, since names may hold newlines.
class TracePresenter : public ctl::Presenter {
public:
  double play(const ctl::Op& op, double start) override {
    line_op(op, start, start + op.duration);
    return op.duration;
  }
  double run_director(const ctl::Op& op, double start) override { return play(op, start); }
  void macro_start(const ctl::Op& op, double start) override {
    open_.push_back(lines_.size());
    line_op(op, start, start);
  }
  void macro_end(const ctl::Op& op, double start, double end) override {
    lines_[open_.back()] = op_text(op, start, end);
    open_.pop_back();
    flush();
  }
  void start_autoscript(const char* proc, const char* var, const char* value, double time) override {
    add(std::string(\"(:autoscript-start \") + proc + \" :var \" + var + \" :value \" + value + \" :time \" + number(time) + \")\");
  }
  void stop_autoscript(const char* proc, const char* var, const char* value, double time) override {
    add(std::string(\"(:autoscript-stop \") + proc + \" :var \" + var + \" :value \" + value + \" :time \" + number(time) + \")\");
  }
  void event_start(const char* event, double time) override {
    add(std::string(\"(:event \") + event + \" :time \" + number(time) + \")\");
  }
  void event_failed(const char* event, const char* goal, double time) override {
    add(std::string(\"(:fail \") + event + \" :goal \" + goal + \" :time \" + number(time) + \")\");
  }
  void event_end(const ctl::Controller& controller) override { add(controller.state_line()); }
"
  "The start of the trace-printing driver's code, after its header (it names
the controller's namespace through the alias ctl): a presenter recording
trace lines, up to its members for the timed API.")

(defparameter *driver-presenter-end*
  "
private:
  std::vector<std::string> lines_;
  std::vector<std::size_t> open_;
  std::size_t flushed_ = 0;

  static std::string op_text(const ctl::Op& op, double start, double end) {
    std::string kind = op.kind;
    std::string middle = kind == \"director\" ? std::string(\" :director \") + op.script
                       : kind == \"code\" ? std::string(\" :code t\")
                       : std::string(\" :script \") + op.script;
    return std::string(\"(:op \") + op.name + middle + \" :start \" + number(start) + \" :end \" + number(end) + \")\";
  }
  void line_op(const ctl::Op& op, double start, double end) { add(op_text(op, start, end)); }
  void add(const std::string& line) { lines_.push_back(line); flush(); }
  void flush() {
    if (!open_.empty()) return;
    for (; flushed_ < lines_.size(); ++flushed_) print_line(lines_[flushed_]);
  }
};

}  // namespace

"
  "The rest of the driver's presenter.")

(defparameter *driver-read-initial-state*
  "  ctl::State state = ctl::initial_state();
  const int pairs = argc > 1 ? std::atoi(argv[1]) : 0;
  int next = 2;
  for (int i = 0; i < pairs; ++i, next += 2) {
    if (next + 1 >= argc || !ctl::assign(state, argv[next], argv[next + 1])) {
      std::fprintf(stderr, \"bad initial value %s\\n\", next < argc ? argv[next] : \"(missing)\");
      return 2;
    }
  }
"
  "The start of both drivers' main(): the initial state from N, then N pairs
VARIABLE VALUE; NEXT is then the index of the first argument after them.")

(defparameter *driver-main*
  (concatenate 'string
   "// Arguments: N, then N pairs VARIABLE VALUE (as Player prints them), then the
// events' indices. Without events it prints the initial state line.
int main(int argc, char** argv) {
"
   *driver-read-initial-state*
   "  TracePresenter presenter;
  ctl::Controller controller(presenter, state);
  if (next >= argc) print_line(controller.state_line());
  for (; next < argc; ++next) {
    const int index = std::atoi(argv[next]);
    if (index < 0 || index >= ctl::event_count) {
      std::fprintf(stderr, \"unknown event index %s\\n\", argv[next]);
      return 2;
    }
    controller.send(static_cast<ctl::Event>(index));
  }
  return 0;
}
")
  "The driver's main() for the whole-event API.")

(defparameter *timed-driver-presenter*
  "  void cut(const ctl::Op* op, double, double time, const char* by) override {
    add(std::string(\"(:cut \") + (op ? op->name : \"nil\") + \" :time \" + number(time) + \" :by \" + by + \")\");
  }
  void dropped(const char* event, double time, const char* busy_with) override {
    add(std::string(\"(:dropped \") + event + \" :time \" + number(time) + \" :busy-with \" + busy_with + \")\");
  }
  void resumed(const char* event, double time) override {
    add(std::string(\"(:resume \") + event + \" :time \" + number(time) + \")\");
  }
  void timer(const char* name, double time) override {
    add(std::string(\"(:timer \") + name + \" :time \" + number(time) + \")\");
  }
  void trigger(const char* name, double time) override {
    add(std::string(\"(:trigger \") + name + \" :time \" + number(time) + \")\");
  }
  // At the end of a scenario stopped midway: the lines still waiting, an open
  // macro's with its end at its start (as Player's trace holds them).
  void print_rest() {
    for (; flushed_ < lines_.size(); ++flushed_) print_line(lines_[flushed_]);
  }
"
  "The driver presenter's members for the timed API, printing as Player's trace.")

(defparameter *timed-driver-main*
  (concatenate 'string
   "// Stop with the timeline's message when it cannot move on.
void check_timeline(const ctl::Controller& controller) {
  if (controller.timeline_error().empty()) return;
  std::fprintf(stderr, \"%s\\n\", controller.timeline_error().c_str());
  std::exit(3);
}

// Arguments: N, then N pairs VARIABLE VALUE (as Player prints them), then
// UNTIL (seconds, or - to play until no event runs or waits), POLICY (0 for
// each event's own, else 1 + the policy's position in WhenBusy's list) for
// the timed entries, then the entries: INDEX (sent when the events before it
// have ended) or INDEX@SECONDS.
int main(int argc, char** argv) {
"
   *driver-read-initial-state*
   "  if (next + 1 >= argc) {
    std::fprintf(stderr, \"missing UNTIL or POLICY\\n\");
    return 2;
  }
  const std::string until = argv[next++];
  const int policy = std::atoi(argv[next++]);
  TracePresenter presenter;
  ctl::Controller controller(presenter, state);
  for (; next < argc; ++next) {
    const std::string entry = argv[next];
    const std::size_t at = entry.find('@');
    const int index = std::atoi(entry.substr(0, at).c_str());
    if (index < 0 || index >= ctl::event_count) {
      std::fprintf(stderr, \"unknown event index %s\\n\", argv[next]);
      return 2;
    }
    const ctl::Event event = static_cast<ctl::Event>(index);
    if (at == std::string::npos) {
      controller.finish_events();
      check_timeline(controller);
      controller.send_timed(event, controller.now());
    } else {
      const double time = std::strtod(entry.c_str() + at + 1, nullptr);
      if (time < controller.now()) {
        std::fprintf(stderr, \"%s arrives at %s, before now (%s): a timed controller cannot go back\\n\",
                     ctl::event_name(event), number(time).c_str(), number(controller.now()).c_str());
        return 2;
      }
      controller.send_timed(event, time, static_cast<ctl::Controller::WhenBusy>(policy));
    }
    check_timeline(controller);
  }
  if (until == \"-\") {
    controller.finish_events();
  } else {
    const double time = std::strtod(until.c_str(), nullptr);
    if (time < controller.now()) {
      std::fprintf(stderr, \"until %s lies before now (%s): a timed controller cannot go back\\n\",
                   number(time).c_str(), number(controller.now()).c_str());
      return 2;
    }
    controller.advance(time);
  }
  check_timeline(controller);
  presenter.print_rest();
  return 0;
}
")
  "The timed driver's main(): plays a timed scenario as PLAY-EVENTS does.")

(defun driver-source (name namespace &key timed)
  "A main() printing Player's trace for the controller NAME in NAMESPACE; with
TIMED, playing a timed scenario on a controller emitted with the timed layer."
  (concatenate 'string
               (format nil "// ~A_main.cpp -- generated by Player: plays events and prints the trace.
#include \"~A.hpp\"

#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

namespace ctl = ~A;

" name name namespace)
               *driver-presenter*
               (if timed *timed-driver-presenter* "")
               *driver-presenter-end*
               (if timed *timed-driver-main* *driver-main*)))

(defun c++-cache-root ()
  "Where compiled drivers are kept: $XDG_CACHE_HOME/player/c++/ or ~/.cache/player/c++/."
  (let ((xdg (sb-ext:posix-getenv "XDG_CACHE_HOME")))
    (merge-pathnames "player/c++/"
                     (if (and xdg (plusp (length xdg)))
                         (directory-pathname xdg)
                         (merge-pathnames ".cache/" (user-homedir-pathname))))))

(defun content-key (&rest texts)
  "A hex digest of TEXTS, naming a cache entry."
  (let ((digest (sb-md5:md5sum-string (format nil "~{~A~^~%--~%~}" texts))))
    (format nil "~{~(~2,'0X~)~}" (coerce digest 'list))))

(defun run-program-capturing (program arguments &key directory)
  "Run PROGRAM (searched on PATH) with ARGUMENTS; (VALUES EXIT-CODE STDOUT STDERR),
or NIL when the program cannot be started."
  (let ((out (make-string-output-stream))
        (err (make-string-output-stream)))
    (handler-case
        (let ((process (sb-ext:run-program program arguments :search t :output out :error err
                                                             :directory directory)))
          (values (sb-ext:process-exit-code process)
                  (get-output-stream-string out) (get-output-stream-string err)))
      (error () nil))))

(defun write-build-files (directory name header source driver)
  "Write NAME.hpp, NAME.cpp and NAME_main.cpp into DIRECTORY; return the sources to compile."
  (let ((main (concatenate 'string name "_main")))
    (write-text-file (output-file directory name "hpp") header)
    (write-text-file (output-file directory name "cpp") source)
    (write-text-file (output-file directory main "cpp") driver)
    (list (file-namestring (output-file directory name "cpp"))
          (file-namestring (output-file directory main "cpp")))))

(defun build-c++-driver (machine &key timed)
  "Generate MACHINE's C++ (with TIMED, its timed layer too) with a driver and
compile it (once per content);
return the executable's pathname. Each build runs in a directory of its own and
only the finished executable is renamed into place, so processes sharing the
cache never run, or write into, another's half-written files."
  (let* ((name (c++-safe-identifier (spec-name (machine-spec machine))))
         ;; Prefixed, so no spec name can collide with the C library's globals.
         (namespace (concatenate 'string "player_" name)))
    (multiple-value-bind (header source) (c++-sources machine name namespace :timed timed)
      (let* ((driver (driver-source name namespace :timed timed))
             (directory (merge-pathnames (format nil "~A/" (content-key header source driver *c++-flags*))
                                         (c++-cache-root)))
             (executable (merge-pathnames "driver" directory)))
        (unless (probe-file executable)
          (let ((work (merge-pathnames (format nil "build-~36R/" (random (expt 2 64) (make-random-state t)))
                                       directory)))
            (ensure-directories-exist work)
            (unwind-protect
                 (handler-bind ((player-error
                                  (lambda (e)
                                    (declare (ignore e))
                                    ;; Keep the sources that failed where the message says.
                                    (write-build-files directory name header source driver))))
                   (compile-c++ work (write-build-files work name header source driver) "driver"
                                :shown-directory directory)
                   (rename-file (merge-pathnames "driver" work) executable))
              (sb-ext:delete-directory work :recursive t))))
        executable))))

(defun compile-c++ (directory sources output &key (shown-directory directory))
  "Compile SOURCES in DIRECTORY into OUTPUT with *C++-FLAGS*; clear errors if
not, naming SHOWN-DIRECTORY as where the sources are."
  (multiple-value-bind (code out err)
      (run-program-capturing *c++-compiler* (append *c++-flags* sources (list "-o" output))
                             :directory (namestring directory))
    (declare (ignore out))
    (cond ((null code)
           (error 'player-error-with-message
                  :message (format nil "~A is not installed; install the Debian package g++"
                                   *c++-compiler*)))
          ((/= code 0)
           (error 'player-error-with-message
                  :message (format nil "g++ failed on the generated code in ~A: ~A"
                                   (namestring shown-directory)
                                   (truncate-text (substitute #\Space #\Newline err) 600)))))))

(defun initial-state-arguments (spec overrides)
  "OVERRIDES as the driver's arguments: their count, then each variable and its
value as Player prints them, values checked and canonical."
  (let ((pairs (loop for (var . value) in (initial-assignments spec overrides)
                     when (assoc (name-key (var-name var)) overrides
                                 :key #'name-key :test #'string=)
                       do (when (and (eq (var-kind var) :number) (eq (var-type var) :integer))
                            (check-c++-int64 spec var value "initial value"))
                       and collect (list (lisp-text (var-name var))
                                         (if (plannable-p var)
                                             (value-text var value)
                                             (let ((*read-default-float-format* 'double-float))
                                               (prin1-to-string value)))))))
    (cons (princ-to-string (length pairs)) (reduce #'append pairs :initial-value '()))))

(defun event-index (spec event)
  "The position of EVENT (a symbol or a name string) in SPEC's events; UNKNOWN-EVENT if none."
  (let ((key (if (stringp event) (string-upcase event) (name-key event))))
    (or (position key (spec-events spec) :key (lambda (e) (name-key (event-name e))) :test #'string=)
        (error 'unknown-event :name event :known (mapcar #'event-name (spec-events spec))))))

(defun split-at-nul (text)
  "The NUL-terminated lines of TEXT."
  (loop for start = 0 then (1+ end)
        for end = (position (code-char 0) text :start start)
        while end
        collect (subseq text start end)))

(defun seconds-argument (seconds)
  "SECONDS as the driver reads it: the double, in digits that read back to it."
  (let ((*read-default-float-format* 'double-float))
    (prin1-to-string (to-double seconds))))

(defun check-timed-scenario (events until)
  "Signal an ARGUMENT-ERROR of RUN-C++-TRACE unless EVENTS are scenario entries
(NAME or (NAME . SECONDS)) none of which arrives after UNTIL."
  (unless (every #'event-entry-p events)
    (argument-fail 'run-c++-trace :events events
                   "a list of event names and (NAME . SECONDS) conses, seconds from 0"))
  (when until
    (check-seconds 'run-c++-trace :until until)
    (dolist (entry events)
      (when (and (consp entry) (> (cdr entry) until))
        (argument-fail 'run-c++-trace :until until
                       (format nil "a time no earlier than the events' (~A arrives at ~A)"
                               (lisp-text (car entry)) (format-number (cdr entry))))))))

(defun scenario-arguments (spec events until when-busy)
  "A timed scenario as the timed driver's arguments: UNTIL (or -), WHEN-BUSY's
number (0 for none), then each entry as INDEX or INDEX@SECONDS."
  (list* (if until (seconds-argument until) "-")
         (if when-busy (princ-to-string (policy-number when-busy)) "0")
         (mapcar (lambda (entry)
                  (if (consp entry)
                      (format nil "~D@~A" (event-index spec (car entry)) (seconds-argument (cdr entry)))
                      (princ-to-string (event-index spec entry))))
                events)))

(defun run-c++-trace (machine &key initial-state events until when-busy)
  "Build MACHINE's C++ driver and run EVENTS from INITIAL-STATE (an alist);
return the trace as a list of lines.  Events are names (symbols or strings),
sent one after another as whole events.  A timed scenario -- an entry
(NAME . SECONDS), or UNTIL given -- plays on the timed layer as PLAY-EVENTS
does on (MAKE-CONTROLLER MACHINE :TIMED T): each NAME when the events before
it have ended, each (NAME . SECONDS) at that time whatever runs; then the clock
advances to UNTIL, or until no event runs or waits.  WHEN-BUSY (a policy
keyword), if given, overrides the policy of every timed entry, as PLAY-EVENTS'
does."
  (check-argument 'run-c++-trace 'events events #'proper-form-list-p "a list of event names")
  (let ((timed (timed-scenario-p events until))
        (when-busy (and when-busy
                        (or (and (symbolp when-busy) (when-busy-policy when-busy))
                            (argument-fail 'run-c++-trace :when-busy when-busy
                                           (format nil "one of ~{~A~^, ~}"
                                                   (mapcar #'lisp-text *when-busy-policies*)))))))
    (when timed (check-timed-scenario events until))
    (let* ((machine (ensure-machine machine 'run-c++-trace))
           (spec (machine-spec machine))
           (arguments (append (initial-state-arguments spec initial-state)
                              (if timed
                                  (scenario-arguments spec events until when-busy)
                                  (mapcar (lambda (event) (princ-to-string (event-index spec event))) events))))
           (executable (build-c++-driver machine :timed timed)))
      (multiple-value-bind (code out err) (run-program-capturing (namestring executable) arguments)
        (unless (eql code 0)
          (error 'player-error-with-message
                 :message (format nil "the generated C++ controller failed (exit ~A): ~A" code err)))
        (split-at-nul out)))))

;;;# Several timed controllers in one driver
;;;
;;; g++ spends most of a build on the headers and on the driver's own code, so
;;; a test comparing many specs builds them into one program: their sources
;;; are included into one translation unit, each with a copy of both drivers
;;; in a namespace of its own; the first argument picks the spec, the second
;;; the driver (timed or whole).

(defun renamed-main (driver name)
  "The DRIVER's source (*TIMED-DRIVER-MAIN* or *DRIVER-MAIN*) with its main() named NAME."
  (let* ((main "int main(int argc, char** argv) {")
         (at (search main driver)))
    (concatenate 'string (subseq driver 0 at)
                 (format nil "int ~A(int argc, char** argv) {" name)
                 (subseq driver (+ at (length main))))))

(defun batch-driver-source (count)
  "The main() of a program holding COUNT timed controllers, b0.cpp ... (one
namespace each, player_bI): its first argument I picks controller I, its
second the driver: timed (the timed driver's arguments follow) or whole (the
whole-event driver's)."
  (with-output-to-string (out)
    (format out "// batch_main.cpp -- generated by Player: plays scenarios on ~D controllers.
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>
~{~%#include \"b~D.cpp\"~}~%" count (loop for i below count collect i))
    (dotimes (i count)
      (format out "~%namespace batch_~D {~%~%namespace ctl = player_b~D;~%~%" i i)
      (write-string *driver-presenter* out)
      (write-string *timed-driver-presenter* out)
      (write-string *driver-presenter-end* out)
      (write-string (renamed-main *timed-driver-main* "play") out)
      (write-string (renamed-main *driver-main* "play_whole") out)
      (format out "~%}  // namespace batch_~D~%" i))
    (format out "~%int main(int argc, char** argv) {
  const bool whole = argc > 2 && std::strcmp(argv[2], \"whole\") == 0;
  switch (argc > 2 ? std::atoi(argv[1]) : -1) {~{~%    case ~D:~%      return whole ? batch_~:*~D::play_whole(argc - 2, argv + 2) : batch_~:*~D::play(argc - 2, argv + 2);~}
    default:
      std::fprintf(stderr, \"unknown controller\\n\");
      return 2;
  }
}
" (loop for i below count collect i))))

(defun build-timed-c++-batch (machines)
  "Build one program holding the timed C++ controller of each of MACHINES (once
per content, cached as BUILD-C++-DRIVER's are); return the executable's
pathname, for RUN-TIMED-C++-BATCH."
  (let* ((sources (loop for machine in machines
                        for i from 0
                        collect (multiple-value-list
                                 (c++-sources (ensure-machine machine 'build-timed-c++-batch)
                                              (format nil "b~D" i) (format nil "player_b~D" i) :timed t))))
         (driver (batch-driver-source (length machines)))
         (directory (merge-pathnames (format nil "~A/" (apply #'content-key driver *c++-flags*
                                                              (reduce #'append sources)))
                                     (c++-cache-root)))
         (executable (merge-pathnames "driver" directory)))
    (flet ((write-files (where)
             (loop for (header source) in sources
                   for i from 0
                   do (write-text-file (output-file where (format nil "b~D" i) "hpp") header)
                      (write-text-file (output-file where (format nil "b~D" i) "cpp") source))
             (write-text-file (output-file where "batch_main" "cpp") driver)
             (list "batch_main.cpp")))
      (unless (probe-file executable)
        (let ((work (merge-pathnames (format nil "build-~36R/" (random (expt 2 64) (make-random-state t)))
                                     directory)))
          (ensure-directories-exist work)
          (unwind-protect
               (handler-bind ((player-error (lambda (e) (declare (ignore e)) (write-files directory))))
                 (compile-c++ work (write-files work) "driver" :shown-directory directory)
                 (rename-file (merge-pathnames "driver" work) executable))
            (sb-ext:delete-directory work :recursive t)))))
    executable))

(defun run-batch-driver (executable index driver arguments)
  "Run DRIVER (\"timed\" or \"whole\") of controller INDEX in the batch program
EXECUTABLE with ARGUMENTS; return the trace lines."
  (multiple-value-bind (code out err)
      (run-program-capturing (namestring executable)
                             (list* (princ-to-string index) driver arguments))
    (unless (eql code 0)
      (error 'player-error-with-message
             :message (format nil "the generated C++ controller failed (exit ~A): ~A" code err)))
    (split-at-nul out)))

(defun run-timed-c++-batch (executable index machine &key initial-state events until when-busy)
  "Play a timed scenario, as RUN-C++-TRACE does, on controller INDEX (MACHINE)
of the program EXECUTABLE from BUILD-TIMED-C++-BATCH; return the trace lines."
  (let ((when-busy (and when-busy
                        (or (and (symbolp when-busy) (when-busy-policy when-busy))
                            (argument-fail 'run-timed-c++-batch :when-busy when-busy
                                           (format nil "one of ~{~A~^, ~}"
                                                   (mapcar #'lisp-text *when-busy-policies*))))))
        (spec (machine-spec (ensure-machine machine 'run-timed-c++-batch))))
    (check-timed-scenario events until)
    (run-batch-driver executable index "timed"
                      (append (initial-state-arguments spec initial-state)
                              (scenario-arguments spec events until when-busy)))))

(defun run-whole-c++-batch (executable index machine &key initial-state events)
  "Send EVENTS (names) one after another as whole events, as RUN-C++-TRACE
does, to controller INDEX (MACHINE) of the program EXECUTABLE from
BUILD-TIMED-C++-BATCH; return the trace lines."
  (check-argument 'run-whole-c++-batch 'events events #'proper-form-list-p "a list of event names")
  (let ((spec (machine-spec (ensure-machine machine 'run-whole-c++-batch))))
    (run-batch-driver executable index "whole"
                      (append (initial-state-arguments spec initial-state)
                              (mapcar (lambda (event) (princ-to-string (event-index spec event))) events)))))
