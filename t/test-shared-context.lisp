;;;; test-shared-context.lisp -- state shared between modules and threads:
;;;; WITH-SPEC-CONTEXT binds the parts of the parsing context given and leaves
;;;; the others, the spec registry survives two threads defining, finding and
;;;; removing specs at once, and live output lines from two threads stay whole.

(in-package #:player-tests)

(def-suite* shared-context :in player-tests)

;;;# WITH-SPEC-CONTEXT

(test spec-context-binds-only-the-parts-given
  (player.spec:with-spec-context (:spec-name 'outer :form-label "op outer" :source-position nil)
    (player.spec:with-spec-context (:spec-name 'inner :source-position '(#p"/tmp/x.lisp" . 7))
      (is (eq 'inner player.base:*current-spec-name*))
      (is (equal '(#p"/tmp/x.lisp" . 7) player.base:*source-position*))
      (is (equal "op outer" player.base:*current-form-label*) "a part not given keeps its outer binding")
      ;; A spec error made here reads the context.
      (let ((condition (make-condition 'spec-error :message "m")))
        (is (eq 'inner (spec-error-spec condition)))
        (is (equal "op outer" (player.base:spec-error-label condition)))))
    (is (eq 'outer player.base:*current-spec-name*) "the binding ends with the form")
    (player.spec:with-spec-context (:spec-name nil)
      (is (null player.base:*current-spec-name*) "NIL given is bound, not ignored"))))

(test spec-context-evaluates-parts-before-binding
  (player.spec:with-spec-context (:spec-name 'outer)
    (player.spec:with-spec-context (:spec-name 'inner :form-label (format nil "in ~A" player.base:*current-spec-name*))
      (is (equal "in OUTER" player.base:*current-form-label*) "as in LET, not LET*"))))

;;;# The spec registry from two threads

(defun registry-worker (specs)
  "A function that registers SPECS, finds each, lists them all, removes each, and
returns a list of what went wrong (NIL when nothing did)."
  (lambda ()
    (let ((problems 0))
      (handler-case
          (progn
            (dolist (spec specs) (player.spec::register-spec spec))
            (list-specs)
            (dolist (spec specs)
              (unless (eq spec (find-spec (spec-name spec) nil)) (incf problems)))
            (dolist (spec specs)
              (unless (remove-spec (spec-name spec)) (incf problems)))
            (dolist (spec specs)
              (when (find-spec (spec-name spec) nil) (incf problems)))
            (and (plusp problems) (list problems :specs-lost-or-kept)))
        (error (e) (list (type-of e) (princ-to-string e)))))))

(defun join-within (thread seconds)
  "THREAD's value when it ends within SECONDS, else :TIMEOUT (the thread is destroyed)."
  (loop repeat (* seconds 20)
        while (bt:thread-alive-p thread)
        do (sleep 0.05))
  (cond ((bt:thread-alive-p thread) (bt:destroy-thread thread) :timeout)
        (t (bt:join-thread thread))))

(defun uninterned-specs (tag count)
  "COUNT empty specs named by uninterned symbols TAG-0, TAG-1, ..."
  (loop for i below count
        collect (player.spec::%make-spec :name (make-symbol (format nil "~A-~D" tag i)) :form-places nil)))

(test spec-registry-is-safe-from-two-threads
  ;; Each round starts from an empty table, so it grows -- is rehashed --
  ;; while both threads write: without the registry's lock, entries are lost.
  (let ((saved player.spec::*specs*)
        (left (uninterned-specs "LEFT" 20000))
        (right (uninterned-specs "RIGHT" 20000))
        (results '()))
    (unwind-protect
         (dotimes (round (sweep-count 20 4))
           (setf player.spec::*specs* (make-hash-table :test 'equal))
           (let ((threads (list (bt:make-thread (registry-worker left) :name "registry test left")
                                (bt:make-thread (registry-worker right) :name "registry test right"))))
             (push (mapcar (lambda (thread) (join-within thread 120)) threads) results))
           (push (list :left-over (hash-table-count player.spec::*specs*)) results))
      (setf player.spec::*specs* saved))
    (is (every (lambda (result) (if (eq (first result) :left-over)
                                    (zerop (second result))
                                    (every #'null result)))
               results)
        "problems: ~S" (remove-if (lambda (result) (member result '((nil nil) (:left-over 0)) :test #'equal))
                                  results))))

(test define-spec-from-two-threads
  (let* ((forms '((state-variable up boolean nil) (op rise :add up) (event ev-up :state up)))
         (threads (loop for tag in '("A" "B")
                        collect (let ((tag tag))
                                  (bt:make-thread
                                   (lambda ()
                                     (handler-case
                                         (loop for i below 30
                                               for name = (intern (format nil "DEFINED-~A-~D" tag i) '#:player-tests)
                                               do (define-spec name forms :package (find-package '#:player-tests))
                                                  (unless (find-spec name nil) (return (list name :missing)))
                                                  (remove-spec name))
                                       (error (e) (princ-to-string e))))))))
         (results (mapcar (lambda (thread) (join-within thread 120)) threads)))
    (is (every #'null results) "problems: ~S" results)))

;;;# Live output from two threads

(defun live-line-worker (stream tag rounds)
  "A function writing ROUNDS numbered lines tagged TAG to STREAM through WRITE-LIVE-LINE."
  (lambda ()
    (handler-case
        (dotimes (i rounds)
          ;; Many directives: FORMAT writes the line in many pieces.
          (player.render::write-live-line stream "~A~{ ~A~} ~D~%" tag '(1 2 3 4 5 6 7 8) i))
      (error (e) (princ-to-string e)))))

(test live-lines-from-two-threads-stay-whole
  (let* ((stream (make-string-output-stream))
         (threads (loop for tag in '("left" "right")
                        collect (bt:make-thread (live-line-worker stream tag 5000))))
         (results (mapcar (lambda (thread) (join-within thread 120)) threads))
         (lines (split-sequence-lines (get-output-stream-string stream))))
    (is (every #'null results) "problems: ~S" results)
    (is (= 10000 (length lines)))
    (dolist (tag '("left" "right"))
      (is (equal (loop for i below 5000 collect (format nil "~A 1 2 3 4 5 6 7 8 ~D" tag i))
                 (remove-if-not (lambda (line) (eql 0 (search (format nil "~A " tag) line))) lines))
          "~A's lines are whole and in order" tag))))

(defun split-sequence-lines (text)
  "TEXT's lines, without their newlines (none after the last)."
  (with-input-from-string (in text)
    (loop for line = (read-line in nil) while line collect line)))
