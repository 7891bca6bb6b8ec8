;;;; addresses.lisp -- events addressed to a scene's members.  An address is
;;;; MEMBER/EVENT (left/ev-search), MEMBER+MEMBER/EVENT (left+right/ev-search)
;;;; or all/EVENT (every member); a bare NAME is one of the scene's own
;;;; events, which sends several addresses at once.  Each member's controller
;;;; sees only the bare event name, so a member plays exactly as a lone
;;;; controller of its spec would.

(in-package #:player.cast)

(defun address-text (address)
  "ADDRESS (a symbol or string) as a string, as written (symbols downcased)."
  (if (stringp address) address (string-downcase (symbol-name address))))

(defun parse-event-address (address members)
  "The members (CAST-MEMBERs of MEMBERS) and the event name (a symbol of
PLAYER-USER when there is one, else an upcased string) ADDRESS, a symbol or string MEMBER/EVENT, MEMBER+.../EVENT or
all/EVENT, sends to: two values.  Signals an UNKNOWN-MEMBER-ERROR for an
address without a member part or naming a member not among MEMBERS."
  (unless (name-designator-p address)
    (scene-fail 'unknown-member-error address "an event address is MEMBER/EVENT (a symbol or string), not ~A"
                (bounded-lisp-text address 60)))
  (let* ((text (address-text address))
         (slash (position #\/ text))
         (names (lambda () (mapcar (lambda (m) (lisp-text (cast-member-name m))) members))))
    (unless (and slash (< 0 slash (1- (length text))))
      (scene-fail 'unknown-member-error (form-of address)
                  "event ~A names no member: in a scene, address it as MEMBER/EVENT, MEMBER+MEMBER/EVENT or all/EVENT (members: ~{~A~^, ~})"
                  text (funcall names)))
    (let ((member-part (subseq text 0 slash))
          (event (let ((name (string-upcase (subseq text (1+ slash)))))
                   ;; An event's symbol, when there is one, is looked up without consing.
                   (or (find-symbol name '#:player-user) name))))
      (values (if (string-equal member-part "all")
                  members
                  (loop for part in (split-sequence-simple #\+ member-part)
                        collect (or (find part members :key (lambda (m) (symbol-name (cast-member-name m)))
                                                       :test #'string-equal)
                                    (scene-fail 'unknown-member-error (form-of address)
                                                "event address ~A names member ~A, which the scene does not have (members: ~{~A~^, ~})"
                                                text part (funcall names)))))
              event))))

(defun form-of (address)
  "ADDRESS as the offending form of an error: a symbol as it is; a string,
which the message quotes already, as NIL."
  (and (symbolp address) address))

(defun split-sequence-simple (char text)
  "TEXT split at each CHAR, as a list of strings."
  (loop for start = 0 then (1+ end)
        for end = (position char text :start start)
        collect (subseq text start end)
        while end))

(defun scene-event-addresses (cast name)
  "The addresses the scene event NAME of CAST sends, or NIL when CAST has no such event."
  (and (name-designator-p name)
       (not (find #\/ (address-text name)))
       (cdr (assoc (address-text name) (cast-events cast) :test #'string-equal
                   :key #'symbol-name))))

(defun resolve-scene-entry (cast entry)
  "The scenario ENTRY (ADDRESS, or (ADDRESS . SECONDS), ADDRESS possibly a
scene event) of CAST as a list of (MEMBER-NAME . MEMBER-ENTRY), MEMBER-ENTRY
the bare event name (see PARSE-EVENT-ADDRESS), timed as ENTRY is; a scene
event's (ADDRESS :after OFFSET) arrives OFFSET seconds after ENTRY's time,
so such a scene event needs one (a SCENE-ERROR otherwise)."
  (let* ((address (event-entry-name entry))
         (addresses (or (scene-event-addresses cast address) (list address))))
    (loop for each in addresses
          for after = (and (consp each) (third each))
          do (when (and after (not (consp entry)))
               (scene-fail 'scene-error (form-of address)
                           "scene event ~A sends its events :after a time: send it at one, ~A@SECONDS"
                           (address-text address) (address-text address)))
          append (multiple-value-bind (members event)
                     (parse-event-address (if (consp each) (first each) each) (cast-members cast))
                   (loop for member in members
                         collect (cons (cast-member-name member)
                                       (if (consp entry)
                                           (cons event (+ (cdr entry) (or after 0)))
                                           event)))))))

(defun split-scene-events (cast events)
  "EVENTS, a scenario for CAST (see RESOLVE-SCENE-ENTRY), split per member: an
alist from each member's name, in CAST's order, to its own scenario, the
bare events it receives in order.  Signals an UNKNOWN-MEMBER-ERROR for an
address naming no member of CAST."
  (let ((entries (loop for entry in events append (resolve-scene-entry cast entry))))
    (loop for member in (cast-members cast)
          for name = (cast-member-name member)
          collect (cons name (loop for (owner . entry) in entries
                                   when (eq owner name) collect entry)))))
