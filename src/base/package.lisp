;;;; package.lisp -- player.base: Helpers every layer shares: the condition tree, the printer, argument checks, the limits on data.

(defpackage #:player.base
  (:use #:cl)
  (:import-from #:alexandria
                #:when-let #:if-let #:ensure-list #:hash-table-keys
                #:with-gensyms #:once-only #:appendf #:read-file-into-string)
  (:documentation "Helpers every layer shares: the condition tree, the printer, argument checks, the limits on data.")
  (:export
   #:*current-form-label* #:*current-spec-name* #:*form-places* #:*int64-range*
   #:*library-number-range* #:*max-form-depth* #:*max-seconds* #:*shortest-period* #:*path-phrase*
   #:*source-position* #:*sub-form-places* #:argument-error #:argument-error-argument #:control-character-p #:escaped-text
   #:argument-error-expected #:argument-error-function #:argument-error-value
   #:argument-fail #:argument-value-text #:bounded-form-p #:bounded-lisp-text
   #:check-argument #:check-form-structure #:check-real #:check-seconds #:check-spec-number
   #:class-cycle-error #:condition-line #:note-condition-place #:directory-pathname #:domain-error
   #:duplicate-definition #:effect-error #:find-executable #:finite-form-p
   #:finite-number-p #:finite-real-p #:form #:form-label #:format-number #:goal-error
   #:head #:inexact-macro-error #:int64-p #:label-error #:lisp-text
   #:load-first-foreign-library #:name-designator-p
   #:number-text #:out-of-range-number #:output-stream-designator-p #:pathname-designator-p
   #:plain-seconds-p #:player-error #:player-error-with-message #:position-line
   #:proper-form-list-p #:reachable-space-too-large #:report-spec-error-safely #:seconds-p
   #:seconds-phrase #:spec-error #:spec-error-form #:spec-error-label #:spec-error-message
   #:spec-error-position #:spec-error-spec #:spec-fail #:spec-reader-error #:spec-seconds
   #:spec-syntax-error #:split-list #:state-outside-planned-set #:state-space-too-large
   #:state-transfer-error #:string-designator-p #:tail #:to-double #:truncate-text
   #:type-error-in-spec #:unknown-event #:unknown-event-name #:unknown-name-error #:unquote
   #:untrusted-code-error #:code-error #:write-list-text
   ;; exact-times.lisp: a timed controller's times as integer microseconds
   #:micros #:+micros-per-second+ #:+never-micros+ #:seconds->micros #:exact-seconds->micros
   #:seconds-value->micros #:micros< #:micros<= #:micros+ #:micros->seconds #:micros->double #:format-micros #:micros-ratio-p #:parse-decimal-seconds
   ;; files.lisp, cleanup.lisp, outputs.lisp: files written whole, inputs checked, children killed
   #:io-error #:io-error-file #:io-error-reason #:io-error-action #:io-fail #:condition-reason
   #:errno-reason #:file-kind #:check-regular-file #:regular-file-or-nil #:open-input-file
   #:call-with-input-file #:with-input-file #:file-octets
   #:register-cleanup #:unregister-cleanup #:kill-child #:run-child #:run-child-output
   #:with-work-folder #:make-private-folder #:remove-folder #:interrupted #:interrupted-exit-code
   #:install-stop-handlers #:stop-at-once-from-start-up #:emergency-exit
   #:call-with-atomic-output-file #:with-atomic-output-file #:write-file-octets #:write-file-string
   #:stage-output-file #:write-files-together
   #:create-exclusive-file #:final-file-name #:output-target #:check-writable-directory #:call-with-output-set #:with-output-set))
