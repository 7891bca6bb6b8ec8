;;;; play-expansion.lisp -- how much a script plays, its :play items expanded:
;;;; a chain of scripts each playing the next twice doubles at every link, so
;;;; a 3 KB library could ask for a billion drivers.  Counted once per script
;;;; when the library is loaded, and capped, naming the chain (issue 31).

(in-package #:player.performance)

(defparameter *max-played-items* 1000
  "The most items one script may play, the scripts it plays expanded.")

(defun played-item-count (library script counts)
  "How many items SCRIPT of LIBRARY plays: 1 per item, and a :play item 1 more
per item its script plays.  Remembered in COUNTS (a hash table), so each
script is counted once; nested cycles were ruled out before."
  (or (gethash script counts)
      (setf (gethash script counts)
            (loop for item in (script-items script)
                  sum (if (play-item-p item)
                          (1+ (played-item-count library (find-script library (play-item-script item)) counts))
                          1)))))

(defun largest-play-chain (library script counts)
  "The names of SCRIPT, the script it plays that plays the most, and so on down."
  (loop for s = script
          then (let ((plays (loop for item in (script-items s)
                                  when (play-item-p item) collect (find-script library (play-item-script item)))))
                 (and plays (reduce (lambda (a b)
                                      (if (>= (played-item-count library a counts)
                                              (played-item-count library b counts))
                                          a b))
                                    plays)))
        while s collect (lisp-text (script-name s))))

(defun check-play-expansion (library scripts)
  "Signal a SCRIPT-ERROR for the first of SCRIPTS (of LIBRARY) that plays more
than *MAX-PLAYED-ITEMS* items, its :play items expanded."
  (let ((counts (make-hash-table :test #'eq)))
    (dolist (script scripts)
      (let ((count (played-item-count library script counts)))
        (when (> count *max-played-items*)
          (with-script-context (script)
            (script-fail (script-form script) "plays ~:D items through ~{~A~^ -> ~}; at most ~:D"
                         count (largest-play-chain library script counts) *max-played-items*)))))))
