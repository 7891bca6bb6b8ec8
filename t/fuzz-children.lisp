;;;; fuzz-children.lisp -- running fuzz cases in forked child processes, so
;;;; that even an escape that kills SBCL is reported (see fuzz.lisp).

(in-package #:player-tests)

;;; ---------------------------------------------------------------------------
;;; Running cases in child processes

(defparameter *fz-result-slots*
  '(fzr-seed fzr-index fzr-target fzr-mode fzr-base fzr-kinds fzr-notes fzr-outcome fzr-condition-type
    fzr-message fzr-phase fzr-violations fzr-excerpt fzr-size fzr-seconds fzr-warnings)
  "The readers of the FZ-RESULT slots a child sends its parent.")

(defun fz-send-result (result stream)
  "Write RESULT to STREAM as one readable form."
  (with-standard-io-syntax
    (let ((*print-readably* nil) (*print-pretty* nil))
      (prin1 (cons :result (mapcar (lambda (reader) (funcall reader result)) *fz-result-slots*)) stream)
      (terpri stream)
      (finish-output stream))))

(defun fz-receive-result (form)
  "The FZ-RESULT a child sent as FORM."
  (let ((result (make-fz-result)))
    (loop for reader in *fz-result-slots*
          for value in (rest form)
          do (funcall (fdefinition (list 'setf reader)) value result))
    result))

(defun fz-child (run make-case from to in out log)
  "In a forked child: run the cases MAKE-CASE makes of FROM below TO, sending each result
through the pipe OUT, with standard input from /dev/null and both outputs to
the file LOG (emptied before each case, so it holds what the last case printed).
Never returns."
  (sb-posix:close in)
  (let ((null (sb-posix:open "/dev/null" sb-posix:o-rdonly))
        (log-fd (sb-posix:open (namestring log) (logior sb-posix:o-wronly sb-posix:o-creat sb-posix:o-append)
                               #o644)))
    (sb-posix:dup2 null 0)
    (sb-posix:dup2 log-fd 1)
    (sb-posix:dup2 log-fd 2))
  (let ((stream (sb-sys:make-fd-stream out :output t :external-format :utf-8 :buffering :full)))
    (loop for index from from below to
          do (sb-posix:ftruncate 2 0)
             (let ((case nil))
               (handler-case (progn (setf case (funcall make-case index))
                                    (fz-send-result (fz-execute case run) stream))
                 (serious-condition (condition)
                   ;; The harness itself failed around the case (the registry
                   ;; could not be listed, say): an escape of that case.
                   (let ((result (make-fz-result :seed (and case (fzc-seed case)) :index index
                                                 :outcome :escaped :phase :harness
                                                 :condition-type (type-of condition)
                                                 :message (fz-clip (ignore-errors (princ-to-string condition))
                                                                           300))))
                     (ignore-errors (fz-send-result result stream)))))))
    (ignore-errors (prin1 '(:done) stream) (finish-output stream))
    (sb-ext:exit :code 0 :abort t)))

(defun fz-read-from-child (stream fd seconds)
  "The next form from a child: :EOF when it has gone, :TIMEOUT after SECONDS of silence."
  (if (or (listen stream) (sb-sys:wait-until-fd-usable fd :input seconds))
      (handler-case (with-standard-io-syntax
                      (let ((*read-eval* nil)) (read stream nil :eof)))
        (error () :eof))
      :timeout))

(defun fz-crash-reason (log-text)
  "What the runtime said when a child died: the line after 'fatal error', else
a line about exhaustion; NIL if neither."
  (let* ((lines (remove "" (mapcar (lambda (line) (string-trim '(#\Space #\Tab #\Return) line))
                                   (fz-split-lines log-text))
                        :test #'string=))
         (fatal (position-if (lambda (line) (search "fatal error" line)) lines))
         (line (cond (fatal (or (nth (1+ fatal) lines) (nth fatal lines)))
                     (t (find-if (lambda (line) (search "exhausted" line)) lines)))))
    (and line (subseq line 0 (or (position #\, line) (min (length line) 80))))))

(defun fz-dead-child-result (run make-case index wait-status hung log)
  "The FZ-RESULT of case INDEX (made by MAKE-CASE), during which the child died
(WAIT-STATUS) or was killed for not answering (HUNG)."
  (let* ((result (handler-case (sb-ext:with-timeout 20 (fz-new-result (funcall make-case index) run))
                   (serious-condition (c)
                     (make-fz-result :index index
                                     :notes (list (format nil "the case cannot be made again here: ~A"
                                                          (type-of c)))))))
         (log-text (or (ignore-errors (let ((text (alexandria:read-file-into-string log :external-format :latin-1)))
                                        (subseq text 0 (min (length text) 4000))))
                       ""))
         (status (cond (hung "was killed after it stopped answering")
                       ((null wait-status) "vanished")
                       ((sb-posix:wifsignaled wait-status)
                        (format nil "was killed by signal ~D" (sb-posix:wtermsig wait-status)))
                       ((sb-posix:wifexited wait-status)
                        (format nil "exited with status ~D" (sb-posix:wexitstatus wait-status)))
                       (t (format nil "ended with status ~D" wait-status)))))
    (setf (fzr-outcome result) (if hung :hung :crashed)
          (fzr-phase result) :process
          (fzr-condition-type result) (or (fz-crash-reason log-text) status)
          (fzr-message result) (format nil "the process ~A; it printed: ~A" status
                                       (fz-visible (subseq log-text 0 (min (length log-text) 300)))))
    result))

(defun fz-run-forked (run make-case from to record)
  "Run the cases MAKE-CASE makes of FROM below TO in forked children, calling
RECORD with each FZ-RESULT in order. A child that dies or stops answering costs the case
it was running (recorded :CRASHED or :HUNG); a new child starts after it.
Where fork is refused (other threads running), the cases run in this process."
  (let ((next from)
        (log (merge-pathnames "child.log" (fzrun-directory run)))
        (patience (or (fzrun-patience run) (+ 20 (* 3 (fzrun-timeout run))))))
    (pushnew (namestring log) (fzrun-expected run) :test #'string=)
    (loop while (< next to)
          do (multiple-value-bind (in out) (sb-posix:pipe)
               (finish-output *standard-output*)
               (finish-output *error-output*)
               (let ((pid (handler-case (sb-posix:fork)
                            (error ()
                              (sb-posix:close in)
                              (sb-posix:close out)
                              (format *error-output* "~&; fuzz: fork refused (threads: ~{~A~^, ~}); ~
                                                      the cases run in this process, unprotected from crashes~%"
                                      (mapcar #'sb-thread:thread-name (sb-thread:list-all-threads)))
                              (loop for index from next below to
                                    do (funcall record (fz-execute (funcall make-case index) run)))
                              (return-from fz-run-forked)))))
                 (when (zerop pid)
                   (fz-child run make-case next to in out log))
                 (sb-posix:close out)
                 (let ((stream (sb-sys:make-fd-stream in :input t :external-format :utf-8 :buffering :full))
                       (last (1- next))
                       (hung nil))
                   (unwind-protect
                        (loop (let ((form (fz-read-from-child stream in patience)))
                                (cond ((eq form :timeout)
                                       (setf hung t)
                                       (ignore-errors (sb-posix:kill pid sb-posix:sigkill))
                                       (return))
                                      ((and (consp form) (eq (first form) :result))
                                       (let ((result (fz-receive-result form)))
                                         (setf last (fzr-index result))
                                         (funcall record result)))
                                      (t (return)))))
                     (close stream))
                   (let ((status (nth-value 1 (ignore-errors (sb-posix:waitpid pid 0)))))
                     (if (>= (1+ last) to)
                         (setf next to)
                         (progn (funcall record (fz-dead-child-result run make-case (1+ last) status hung log))
                                (setf next (+ 2 last)))))))))))

(defun fuzz-case-text (seed index)
  "The text case INDEX of SEED writes (the marker file named by placeholder
@MARKER@), or, for a memory case, its forms."
  (let ((case (progn (fz-bases) (fz-generate seed index))))
    (or (fzc-text case) (fzc-forms case))))

(defun fz-failure-groups (failures)
  "FAILURES grouped by what went wrong: ((LABEL COUNT PHASES EXAMPLE
MEMORY-EXAMPLE OTHERS) ...), largest groups first. EXAMPLE is the file case with
the shortest input (else the first memory case); MEMORY-EXAMPLE, when EXAMPLE
is a file case, the first memory case of the group; OTHERS the first case of
each other cause ((SIGNATURE . RESULT) ...), told apart by FZ-SIGNATURE."
  (let ((groups (make-hash-table :test 'equal)))
    (dolist (result failures)
      (let ((labels (append (when (member (fzr-outcome result) *fz-failing-outcomes*)
                              (list (fz-outcome-label result)))
                            (mapcar (lambda (v) (format nil "SIDE EFFECT ~A" (subseq v 0 (or (search ": " v) (length v)))))
                                    (fzr-violations result)))))
        (dolist (label (remove-duplicates labels :test #'string=))
          (let ((entry (or (gethash label groups) (setf (gethash label groups) (list 0 '() nil nil '())))))
            (incf (first entry))
            (pushnew (fzr-phase result) (second entry))
            (let ((signature (fz-signature result)))
              (unless (assoc signature (fifth entry) :test #'string=)
                (setf (fifth entry) (append (fifth entry) (list (cons signature result))))))
            (if (eq (fzr-mode result) :memory)
                (unless (fourth entry) (setf (fourth entry) result))
                (when (or (null (third entry))
                          (< (fzr-size result) (fzr-size (third entry)))
                          (and (= (fzr-size result) (fzr-size (third entry)))
                               (< (fzr-index result) (fzr-index (third entry)))))
                  (setf (third entry) result)))))))
    (sort (loop for label being the hash-keys of groups using (hash-value (count phases file memory kinds))
                for example = (or file memory)
                collect (list label count (reverse phases) example (and file memory)
                              (remove (fz-signature example) kinds :key #'car :test #'string=)))
          #'> :key #'second)))

(defun fz-signature (result)
  "What distinguishes one cause from another within a failure group: the phase
and the message, digits and long tails left out."
  (let ((text (format nil "~(~A~): ~A" (fzr-phase result) (or (fzr-message result) ""))))
    (with-output-to-string (out)
      (loop with previous-digit = nil
            for char across (subseq text 0 (min 120 (length text)))
            do (if (digit-char-p char)
                   (unless previous-digit (write-char #\N out))
                   (write-char char out))
               (setf previous-digit (digit-char-p char))))))

(defun fz-describe-example (result stream)
  "Write RESULT as a reproducer."
  (format stream "    seed ~D case ~D: ~(~A ~A, base ~A~); replay: (player-tests::fuzz-case ~D ~D)~%"
          (fzr-seed result) (fzr-index result) (fzr-mode result) (fzr-target result) (fzr-base result)
          (fzr-seed result) (fzr-index result))
  (format stream "    phase ~(~A~); mutations: ~{~A~^; ~}~%" (fzr-phase result) (fzr-notes result))
  (when (fzr-message result)
    (format stream "    message: ~A~%" (fzr-message result)))
  (when (fzr-violations result)
    (format stream "    side effects: ~{~A~^; ~}~%" (fzr-violations result)))
  (format stream "    input: ~A~%" (fzr-excerpt result)))

(defun fz-write-group (group stream)
  "Write one group of FZ-FAILURE-GROUPS: what, how often, where, a reproducer."
  (destructuring-bind (label count phases example memory-example others) group
    (format stream "~A: ~D case~:P (phase~P ~(~{~A~^, ~}~))~%" label count (length phases) phases)
    (fz-describe-example example stream)
    (when memory-example
      (format stream "    also in memory, without a file: (player-tests::fuzz-case ~D ~D): ~{~A~^; ~}~%"
              (fzr-seed memory-example) (fzr-index memory-example) (fzr-notes memory-example)))
    (when others
      (format stream "    other causes:~%")
      (loop for (signature . result) in others
            repeat 6
            do (format stream "      ~A ~~ (player-tests::fuzz-case ~D ~D), ~(~A~)~%"
                       signature (fzr-seed result) (fzr-index result) (fzr-mode result)))
      (when (> (length others) 6)
        (format stream "      ... and ~D more~%" (- (length others) 6))))))

(defun fz-failure-report (failures &optional (stream nil))
  "The failures, grouped, one reproducer each, as a string (or written to STREAM)."
  (flet ((write-report (out)
           (dolist (group (fz-failure-groups failures))
             (fz-write-group group out))))
    (if stream (write-report stream) (with-output-to-string (out) (write-report out)))))

(defun fz-report (summary &optional (stream *standard-output*))
  "Print SUMMARY: outcomes, mutation kinds, the slowest cases and the failures."
  (format stream "~&Fuzzing: seed ~D, ~:D cases in ~,1F s (~,1F ms a case)~%"
          (fzs-seed summary) (fzs-cases summary) (fzs-seconds summary)
          (if (plusp (fzs-cases summary)) (/ (* 1000 (fzs-seconds summary)) (fzs-cases summary)) 0))
  (format stream "~%  ~40A ~8@A~%" "outcome" "cases")
  (let ((rows (sort (alexandria:hash-table-alist (fzs-outcomes summary)) #'string< :key #'car)))
    (loop for (label . count) in rows do (format stream "  ~40A ~8:D~%" label count)))
  (format stream "~%  ~18A ~8@A ~9@A ~13@A ~7@A~%" "mutation kind" "cases" "accepted" "player-error" "failed")
  (let ((rows (sort (alexandria:hash-table-alist (fzs-kinds summary)) #'string< :key (lambda (r) (symbol-name (car r))))))
    (loop for (kind . row) in rows
          do (format stream "  ~18A ~8:D ~9:D ~13:D ~7:D~%" (string-downcase kind) (aref row 0) (aref row 1) (aref row 2) (aref row 3))))
  (format stream "~%  slowest cases:~{ ~A~^,~}~%"
          (mapcar (lambda (r) (format nil "~D (~,2F s)" (fzr-index r) (fzr-seconds r))) (fzs-slowest summary)))
  (if (fzs-failures summary)
      (progn (format stream "~%~D failing case~:P, by kind (one reproducer each):~%" (length (fzs-failures summary)))
             (fz-failure-report (reverse (fzs-failures summary)) stream))
      (format stream "~%No escapes, hangs or side effects.~%"))
  summary)
