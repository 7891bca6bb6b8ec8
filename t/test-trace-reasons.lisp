;;;; test-trace-reasons.lisp -- traces that say why (issue 27, item 4): a
;;;; dropped event names what it met the running one on, a queued event's
;;;; arrival is a line, and a cut names where its op stopped -- in the Lisp
;;;; timed controller and, line for line, in the generated C++.

(in-package #:player-tests)

(def-suite* trace-reasons :in player-tests)

(defparameter *reason-forms*
  '((state-variable holding boolean false)
    (state-variable mood string calm (calm busy))
    (op grab :precond mood.calm :add holding :duration 3 :channels (wings head)
             :interrupt (:at 1))
    (op look :add mood.busy :duration 1 :channels (head))
    (op kick :duration 1 :channels (legs))
    (op shrug :duration 1)
    (event ev-grab :op grab)
    (event ev-look (:when-busy :override) :op look)
    (event ev-kick (:when-busy :override) :op kick)
    (event ev-shrug (:when-busy :override) :op shrug)
    (event ev-wait (:when-busy :queue) :op look)
    (event ev-stop (:when-busy :preempt) :op look))
  "A grab on the wings and head that needs a calm mood; a look of the head
that makes him busy; a kick on the legs alone; a shrug on no known channel;
events that drop, queue and preempt.")

(defun reason-trace (sends)
  "The trace of SENDS ((EVENT . TIME)...) on a spec of *REASON-FORMS*."
  (timed-trace-of-forms 'reasons *reason-forms* sends))

(test dropped-line-names-the-clash
  "A dropped event's line says what it met the running event on: the channels
both use, then the variables both mention; :all when one plays an op on no
known channel.  An event on other channels plays beside it, dropping nothing."
  (let ((lines (reason-trace '((ev-grab . 0) (ev-look . 0.5) (ev-shrug . 0.6) (ev-kick . 0.7)))))
    (is (member "(:dropped ev-look :time 0.5 :busy-with ev-grab :clash (\"head\" mood))" lines
                :test #'string=)
        "~S" lines)
    (is (member "(:dropped ev-shrug :time 0.6 :busy-with ev-grab :clash (:all))" lines :test #'string=)
        "~S" lines)
    (is (member "(:op kick :script kick :start 0.7 :end 1.7)" lines :test #'string=) "~S" lines)
    (is (notany (lambda (line) (search "(:dropped ev-kick" line)) lines))))

(test queued-arrival-is-a-line
  "An event queued on arrival shows when it arrived and whom it waits behind:
the running event it met, then the last one waiting before it."
  (let ((lines (reason-trace '((ev-grab . 0) (ev-wait . 0.5) (ev-wait . 1.25)))))
    (is (equal '("(:event ev-grab :time 0)"
                 "(:op grab :script grab :start 0 :end 3)"
                 "(:queued ev-wait :time 0.5 :behind ev-grab)"
                 "(:queued ev-wait :time 1.25 :behind ev-wait)"
                 "(:state (holding . t) (mood . calm))"
                 "(:event ev-wait :time 3)")
               (subseq lines 0 6))
        "~S" lines)))

(test cut-line-says-where-the-op-stopped
  "An op cut short: its :op line gave the end it was planned to have, the
:cut line after it the end it had, and nothing of its event plays past it."
  (let* ((lines (reason-trace '((ev-grab . 0) (ev-stop . 0.4))))
         (cut (find-if (lambda (line) (search "(:cut grab" line)) lines)))
    (is (equal "(:cut grab :time 1 :by ev-stop :end 1)" cut) "~S" lines)
    (is (member "(:event ev-stop :time 1)" lines :test #'string=) "~S" lines)))

(test trace-reasons-match-in-c++
  "The generated C++ prints the same :dropped, :queued and :cut lines."
  (let ((spec (define-spec 'reasons *reason-forms* :package (find-package '#:player-tests))))
    (unwind-protect
         (let ((machine (compile-spec spec)))
           (dolist (events '(((ev-grab . 0) (ev-look . 0.5) (ev-shrug . 0.6) (ev-kick . 0.7))
                             ((ev-grab . 0) (ev-wait . 0.5) (ev-wait . 1.25))
                             ((ev-grab . 0) (ev-stop . 0.4))))
             (let ((c (make-controller machine :timed t)))
               (play-events c events)
               (is (equal (trace-of c) (run-c++-trace machine :events events))
                   "events ~S" events))))
      (remove-spec 'reasons))))

(test recorded-traces-read-the-new-lines
  "A recording holding :queued, :dropped with its :clash and :cut with its
:end is written, read back and verifies; a changed clash is a difference."
  (let ((spec (define-spec 'reasons *reason-forms* :package (find-package '#:player-tests)))
        (path (temp-path "reasons.trace")))
    (unwind-protect
         (let ((recording (record-scenario spec :events '((ev-grab . 0) (ev-look . 0.5) (ev-wait . 0.7)
                                                           (ev-stop . 0.9))
                                                :out path)))
           (dolist (kind '("(:queued " "(:dropped " "(:cut "))
             (is (find kind (recording-lines recording) :test (lambda (k line) (search k line)))
                 "no ~A line in ~S" kind (recording-lines recording)))
           (let ((read (read-recording path)))
             (is (equal (recording-lines recording) (recording-lines read)))
             (is (verification-ok-p (verify-recording read :spec spec))))
           ;; The same file with the clash changed fails, naming the line.
           (let* ((text (alexandria:read-file-into-string path))
                  (clash ":clash (\"head\" mood)")
                  (at (search clash text)))
             (is (not (null at)) "~A" text)
             (alexandria:write-string-into-file
              (concatenate 'string (subseq text 0 at) ":clash (\"head\")" (subseq text (+ at (length clash))))
              path :if-exists :supersede)
             (is (not (verification-ok-p (verify-recording (read-recording path) :spec spec))))))
      (remove-spec 'reasons))))
