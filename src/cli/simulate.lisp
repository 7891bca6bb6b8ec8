;;;; simulate.lisp -- `player simulate`: a scenario played on the body, as BVH and frames.

(in-package #:player.cli)

(define-command "simulate" (file &key spec no-code initial events at when-busy fps seed scripts body bvh frames cast silent)
    (:summary "play the events on the spec's body in simulated time"
     :description "Prints the trace, what the drivers reported (a reach that fell short)
and the files written, as ; comment lines.  When the character speaks or
plays sounds, the audio track goes to speech.wav beside the --frames (or
--bvh) file."
     :arguments ("SPEC-FILE")
     :options ("--spec" "--no-code" "--initial" "--events" "--at" "--when-busy" "--fps" "--seed" "--scripts" "--body" "--cast" "--silent"
               ("--bvh" :string "FILE" "write the character's motion as BVH to FILE; for a scene, one file per body: DIR/MEMBER.bvh when FILE ends in /, else NAME-MEMBER.bvh")
               ("--frames" :string "FILE" "write one s-expression per frame to FILE; for a scene, one file per member, named as for --bvh"))
     :output "the trace on standard output; files only with --bvh and --frames (and
        speech.wav beside them)")
  (check-scenario-times events at)
  (check-frame-budget at fps)
  (when-let (scene (command-cast file spec cast (not no-code)))
    (let* ((simulation (simulate-scene scene :initial initial :events events :until at
                                             :when-busy (policy-keyword when-busy) :fps fps :seed seed
                                             :scripts scripts :body body))
           (written (progn (check-simulation-budget (simulation-frame-count simulation) fps)
                           (write-ensemble-trace (scene-simulation-ensemble simulation))
                           (write-scene-simulation simulation :bvh bvh :frames frames))))
      (print-scene-summary simulation (simulation-frame-count simulation) fps)
      (dolist (path written)
        (format t "; wrote ~A~%" (namestring path))))
    (return-from command-simulate))
  (let* ((simulation (simulate (choose-spec file spec :allow-code (not no-code))
                               :initial initial :events events :until at :when-busy (policy-keyword when-busy) :fps fps :seed seed
                               :scripts scripts :body body :stream *standard-output* :silent silent))
         (beside (progn (finish-trace (controller-presenter (simulation-controller simulation)))
                        (check-simulation-budget (simulation-frame-count simulation) fps)
                        (or frames bvh)))
         (written (write-simulation simulation :bvh bvh :frames frames
                                               :audio (and beside (merge-pathnames *audio-file-name* beside)))))
    (print-scenario-summary simulation (simulation-frame-count simulation) fps)
    (dolist (path written)
      (format t "; wrote ~A~%" (namestring path)))))
