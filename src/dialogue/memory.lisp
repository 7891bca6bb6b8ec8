;;;; memory.lisp -- episodic memory (Persona, "Episodic Memory"): a per-user
;;;; log of what was heard and said, kept across conversations.  It lets a
;;;; reaction depend on history (the second "Huh?" becomes "Sorry, could you
;;;; repeat that?"), limits how often a template is used, remembers earlier
;;;; requests, and holds a simple emotional state.  A memory file is data: one
;;;; (user NAME :mood M :conversations N :log (ENTRY...)) form per user, read
;;;; back as every Player data file is, so loading it runs nothing.

(in-package #:player.dialogue)

(defstruct (episodic-memory (:conc-name memory-) (:constructor %make-memory))
  "What Peedy remembers of USER (a string): his MOOD towards them (:neutral,
:happy, :sad or any keyword a dialogue sets), how many CONVERSATIONS have
begun, and the LOG, newest entry first.  An entry is a plist: :conversation N,
:kind :heard (with :event, :text, :slots, an alist of slot names and values)
or :said (with :category, :template, its index, and :text)."
  (user "user" :type string)
  (mood :neutral :type keyword)
  (conversations 0 :type (integer 0))
  (log '() :type list))

(defun make-memory (&key (user "user"))
  "A fresh memory of USER (a string)."
  (check-argument 'make-memory :user user #'stringp "a string")
  (%make-memory :user user))

(defun begin-conversation (memory)
  "Count a new conversation in MEMORY; per-conversation limits start afresh."
  (incf (memory-conversations memory)))

(defun remember (memory kind &rest properties)
  "Add an entry of KIND with PROPERTIES to MEMORY's log, in the current conversation."
  (push (list* :conversation (memory-conversations memory) :kind kind properties)
        (memory-log memory)))

(defun current-conversation-entries (memory kind)
  "MEMORY's entries of KIND in its current conversation, newest first."
  (loop for entry in (memory-log memory)
        while (eql (getf entry :conversation) (memory-conversations memory))
        when (eq (getf entry :kind) kind) collect entry))

(defun memory-streak (memory event)
  "How many of the latest inputs of this conversation in a row were EVENT."
  (loop for entry in (current-conversation-entries memory :heard)
        while (same-name-p (getf entry :event) event)
        count t))

(defun memory-count (memory event)
  "How often EVENT was heard in this conversation."
  (count-if (lambda (entry) (same-name-p (getf entry :event) event))
            (current-conversation-entries memory :heard)))

(defun memory-asked-before-p (memory slot value)
  "Did an input before the latest, in any conversation, carry VALUE in SLOT?"
  (loop for entry in (rest (remove :heard (memory-log memory) :key (lambda (e) (getf e :kind)) :test-not #'eq))
        thereis (let ((pair (assoc (dialogue-key slot) (getf entry :slots) :test #'string=)))
                  (and pair (dialogue-equal (cdr pair) value)))))

(defun memory-template-used-p (memory template span)
  "Has TEMPLATE been said within SPAN (:conversation, or :user: ever)?"
  (let ((category (template-category template)))
    (loop for entry in (memory-log memory)
          while (or (eq span :user) (eql (getf entry :conversation) (memory-conversations memory)))
          thereis (and (eq (getf entry :kind) :said)
                       (same-name-p (getf entry :category) category)
                       (eql (getf entry :template) (template-index template))))))

;;;# Files

(defun write-memory-form (memory stream)
  "Write MEMORY to STREAM as the data form a memory file holds, one log entry a line."
  (format stream "(user ~S :mood ~S :conversations ~D~%  :log (~{~S~^~%        ~}))~%"
          (memory-user memory) (memory-mood memory) (memory-conversations memory)
          (reverse (memory-log memory))))

(defun read-memory-file (file)
  "The memories in the memory FILE, as a list; a DIALOGUE-ERROR naming the file
and line of anything that is not a well-formed user form."
  (let ((truename (probe-file file)))
    (loop for (form position) in (read-data-file file :what "memory file"
                                                      :fail (lambda (position message &optional kind)
                                                              (declare (ignore kind))
                                                              (error 'dialogue-error :spec nil :form nil :message message
                                                                                     :position (and position (cons truename position)))))
          collect (let ((places (make-hash-table :test 'eq)))
                    (when (consp form) (setf (gethash form places) (cons truename position)))
                    (with-spec-context (:form-places places)
                      (parse-memory-form form))))))

(defun parse-memory-form (form)
  "The memory FORM, (user NAME :mood M :conversations N :log (ENTRY...)), describes."
  (unless (and (alexandria:proper-list-p form) (symbolp (first form)) (same-name-p (first form) "user")
               (stringp (second form)) (evenp (length (cddr form))))
    (dialogue-fail form "a memory file holds (user \"NAME\" :mood M :conversations N :log (ENTRY...)) forms"))
  (destructuring-bind (&key (mood :neutral) (conversations 0) log) (cddr form)
    (unless (and (keywordp mood) (typep conversations '(integer 0)) (alexandria:proper-list-p log)
                 (every (lambda (entry) (and (alexandria:proper-list-p entry) (evenp (length entry))
                                             (keywordp (getf entry :kind))
                                             (typep (getf entry :conversation) '(integer 0))
                                             (alexandria:proper-list-p (getf entry :slots))
                                             (every #'consp (getf entry :slots))))
                        log))
      (dialogue-fail form "malformed memory of user ~S: :mood must be a keyword, :conversations a count, :log a list of entries"
                     (second form)))
    (%make-memory :user (second form) :mood mood :conversations conversations :log (reverse log))))

(defun load-memory (file user)
  "USER's memory from the memory FILE, or a fresh one when FILE does not exist
or does not know USER."
  (check-argument 'load-memory :user user #'stringp "a string")
  (or (and (probe-file file)
           (find user (read-memory-file file) :key #'memory-user :test #'string=))
      (make-memory :user user)))

(defun save-memory (memory file)
  "Write MEMORY into the memory FILE, keeping the other users' memories there."
  (let ((others (and (probe-file file)
                     (remove (memory-user memory) (read-memory-file file) :key #'memory-user :test #'string=))))
    (with-atomic-output-file (out file :follow-links t)
      (format out ";;;; Peedy's episodic memory, one form per user (written by Player; data).~%")
      (with-standard-io-syntax
        (let ((*package* (find-package '#:player-user))
              (*print-readably* nil) (*print-case* :downcase))
          (dolist (each (append others (list memory)))
            (write-memory-form each out)))))
    file))
