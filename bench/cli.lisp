;;;; cli.lisp -- the command line's rows: how long bin/player takes to start,
;;;; warm (the saved core is up to date) and cold (it must be built first),
;;;; and a whole `run` of Peedy's first event.

(in-package #:player-bench)

(defparameter *player-program* (merge-pathnames "../bin/player" *bench-directory*))

(defun player-wall-seconds (&rest arguments)
  "Wall-clock seconds of one bin/player run with ARGUMENTS, its output discarded."
  (let ((start (now)))
    (sb-ext:run-program (namestring *player-program*) arguments :output nil :error nil :search nil)
    (- (now) start)))

(defun median-player-seconds (runs &rest arguments)
  "The median wall time of RUNS runs of bin/player ARGUMENTS, after one warm-up."
  (apply #'player-wall-seconds arguments)
  (median (loop repeat runs collect (apply #'player-wall-seconds arguments))))

(defun bench-command-line ()
  "Rows for bin/player's start-up: cold (core rebuilt), warm help, and run."
  (let ((core (merge-pathnames "../build/player" *bench-directory*)))
    (when (probe-file core) (delete-file core))
    (row "10. bin/player help, cold (builds the saved core; fasls compiled)"
         (format-seconds (player-wall-seconds "help")) "-" ""))
  (let ((warm (median-player-seconds 11 "help")))
    (row "    bin/player help, warm" (format-seconds warm) "< 0.3 s" (< warm 0.3)))
  (row "    bin/player run specs/peedy.lisp --events ev-search"
       (format-seconds (median-player-seconds 11 "run" (namestring *peedy-file*) "--events" "ev-search"))
       "-" ""))
