;;;; export.lisp -- `player export`: a scenario played in simulated time and
;;;; written as one glTF file (skeletons, meshes, the performance as an
;;;; animation) that Blender, three.js or any glTF viewer plays.

(in-package #:player.cli)

(defun export-type (out)
  "OUT's container, checked before any work: a USAGE-ERROR unless --out is
given and names a .glb or .gltf file."
  (unless out (usage-fail "export needs --out FILE.glb or FILE.gltf"))
  (let ((type (pathname-type (pathname out))))
    (unless (member type '("glb" "gltf") :test #'equalp)
      (usage-fail "--out ~A: the file's type must be .glb (binary) or .gltf (JSON)" out))))

(define-command "export" (file &key spec no-code initial events at when-busy fps seed scripts body cast out)
    (:summary "play the events in simulated time and write the performance as glTF"
     :description "Writes one glTF 2.0 file: every body's skeleton (a node per joint), the
mesh it is drawn with, skinned to those joints, and the performance as one
animation named \"performance\", keying each joint's rotation (and the
root's position) at every frame, LINEAR; every prop is a node of its own,
prop/NAME, keyed with its place.  A scene exports all its members into one
file, their joints named MEMBER/JOINT.  Nothing sounds."
     :arguments ("SPEC-FILE")
     :options ("--spec" "--no-code" "--initial" "--events" "--at" "--when-busy" "--fps" "--seed" "--scripts" "--body" "--cast"
               ("--out" :string "FILE.glb|FILE.gltf" "the file to write: binary glTF (.glb) or JSON glTF with its buffer embedded (.gltf)"))
     :output "the --out file; the trace and the path written on standard output")
  (export-type out)
  (check-scenario-times events at)
  (check-frame-budget at fps)
  (let* ((scene (command-cast file spec cast (not no-code)))
         (simulation (if scene
                         (simulate-scene scene :initial initial :events events :until at
                                               :when-busy (policy-keyword when-busy) :fps fps :seed seed
                                               :scripts scripts :body body)
                         (simulate (choose-spec file spec :allow-code (not no-code))
                                   :initial initial :events events :until at :when-busy (policy-keyword when-busy)
                                   :fps fps :seed seed :scripts scripts :body body
                                   :stream *standard-output* :silent t))))
    (if scene
        (progn (write-ensemble-trace (scene-simulation-ensemble simulation))
               (print-scene-summary simulation (simulation-frame-count simulation) fps))
        (print-scenario-summary simulation (simulation-frame-count simulation) fps))
    (format t "; wrote ~A~%" (namestring (export-performance simulation out)))))
