;;;; record.lisp -- `player record`: play a scenario and keep its trace (and
;;;; frames) in a file, so that `player verify` can check it later.

(in-package #:player.cli)

(define-command "record" (file &key spec no-code initial events at when-busy frames fps seed scripts body out)
    (:summary "play a scenario and record its trace (and body frames) as a regression test"
     :description "The recording is data: a (:recording ...) header naming the spec, its
file (relative to the recording), the initial values, the events (EV@T
included), --at, --when-busy and whether frames follow; then the trace lines
exactly as `player run` prints them; with --frames, then the body frames as
`player simulate --frames` writes them (keep --fps low: a frame is about
2.5 KB).  `player verify SPEC-FILE FILE` replays it."
     :arguments ("SPEC-FILE")
     :options ("--spec" "--no-code" "--initial" "--events" "--at" "--when-busy"
               ("--frames" :flag "" "also record the body frames (needs a script library)")
               "--fps" "--seed" "--scripts" "--body"
               ("--out" :string "FILE" "the recording to write, e.g. t/golden/peedy.trace"))
     :output "the recording in the --out FILE; one ; line on standard output says what it holds")
  (unless out (usage-fail "record needs --out FILE, the recording to write"))
  (check-scenario-times events at)
  (when frames (check-frame-budget at fps))
  (let ((recording (record-scenario (choose-spec file spec :allow-code (not no-code))
                                    :initial initial :events events :at at
                                    :when-busy (policy-keyword when-busy)
                                    :frames frames :fps fps :seed seed :scripts scripts :body body
                                    :out out)))
    (format t "; recorded ~D trace line~:P~:[~;~:* and ~D frame~:P~] in ~A~%"
            (length (recording-lines recording))
            (and frames (length (recording-frames recording)))
            out)))
