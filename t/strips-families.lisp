;;;; strips-families.lisp -- classic STRIPS families written as Player specs,
;;;; for the planner at scale (issue 13): blocks world with N blocks and a
;;;; gripper-like transport domain.
;;;;
;;;; A family member is first plain data, a STRIPS-PROBLEM: facts, actions
;;;; (precondition, add and delete lists of facts), the facts true initially
;;;; and named goals (lists of facts). STRIPS-SPEC-FORMS renders it as a
;;;; DEFSPEC body: a boolean per fact, an op per action, an event per goal.
;;;; The tests (test-strips-families.lisp) search the plain data with their
;;;; own breadth-first search, never Player's; `make bench` (bench/strips.lisp)
;;;; loads this file too. It needs nothing but Common Lisp.

(defpackage #:player-strips
  (:use #:cl)
  (:export #:strips-problem #:make-strips-problem #:strips-problem-name #:strips-problem-facts
           #:strips-problem-actions #:strips-problem-initial #:strips-problem-goals
           #:strips-action #:strips-action-name #:strips-action-pre #:strips-action-add
           #:strips-action-del #:blocks-world #:gripper #:strips-spec-forms))

(in-package #:player-strips)

(defstruct strips-problem
  "A STRIPS problem: FACTS (symbols, in declaration order), ACTIONS, the
INITIAL facts (the others are false) and GOALS, ((EVENT-NAME FACT...) ...)."
  (name nil :type symbol)
  (facts '() :type list)
  (actions '() :type list)
  (initial '() :type list)
  (goals '() :type list))

(defstruct (strips-action (:constructor make-strips-action (name pre add del)))
  "An action: applicable when every fact of PRE holds; afterwards the facts
of DEL are false and those of ADD true."
  (name nil :type symbol)
  (pre '() :type list)
  (add '() :type list)
  (del '() :type list))

(defun fact (control &rest arguments)
  "The symbol, in PLAYER-USER, named by CONTROL and ARGUMENTS (upcased)."
  (intern (string-upcase (apply #'format nil control arguments)) '#:player-user))

;;; Blocks world

(defun block-names (n)
  "The names of N blocks: A, B, C..."
  (loop for i below n collect (string (code-char (+ (char-code #\A) i)))))

(defun blocks-world (n)
  "Blocks world with N blocks and one hand: a boolean per ON-X-Y (X /= Y),
ONTABLE-X, CLEAR-X, HOLDING-X and HANDEMPTY; PICKUP, PUTDOWN, STACK and UNSTACK.
Every block starts on the table. Goals: the tower A on B on C..., the reverse
tower, and holding the last block."
  (let* ((blocks (block-names n))
         (facts (append (loop for x in blocks
                              append (loop for y in blocks
                                           unless (equal x y) collect (fact "on-~A-~A" x y)))
                        (loop for x in blocks collect (fact "ontable-~A" x))
                        (loop for x in blocks collect (fact "clear-~A" x))
                        (loop for x in blocks collect (fact "holding-~A" x))
                        (list (fact "handempty"))))
         (actions
           (append
            (loop for x in blocks
                  collect (make-strips-action (fact "pickup-~A" x)
                                              (list (fact "clear-~A" x) (fact "ontable-~A" x) (fact "handempty"))
                                              (list (fact "holding-~A" x))
                                              (list (fact "clear-~A" x) (fact "ontable-~A" x) (fact "handempty")))
                  collect (make-strips-action (fact "putdown-~A" x)
                                              (list (fact "holding-~A" x))
                                              (list (fact "ontable-~A" x) (fact "clear-~A" x) (fact "handempty"))
                                              (list (fact "holding-~A" x))))
            (loop for x in blocks
                  append (loop for y in blocks
                               unless (equal x y)
                                 collect (make-strips-action (fact "stack-~A-~A" x y)
                                                             (list (fact "holding-~A" x) (fact "clear-~A" y))
                                                             (list (fact "on-~A-~A" x y) (fact "clear-~A" x) (fact "handempty"))
                                                             (list (fact "holding-~A" x) (fact "clear-~A" y)))
                                 and collect (make-strips-action (fact "unstack-~A-~A" x y)
                                                                 (list (fact "on-~A-~A" x y) (fact "clear-~A" x) (fact "handempty"))
                                                                 (list (fact "holding-~A" x) (fact "clear-~A" y))
                                                                 (list (fact "on-~A-~A" x y) (fact "clear-~A" x) (fact "handempty"))))))))
    (make-strips-problem
     :name (fact "blocks-~D" n) :facts facts :actions actions
     :initial (append (loop for x in blocks collect (fact "ontable-~A" x))
                      (loop for x in blocks collect (fact "clear-~A" x))
                      (list (fact "handempty")))
     :goals (list (cons (fact "tower") (tower-facts blocks))
                  (cons (fact "reverse-tower") (tower-facts (reverse blocks)))
                  (list (fact "hold-last") (fact "holding-~A" (first (last blocks))))))))

(defun tower-facts (blocks)
  "The facts of a tower of BLOCKS, the first on top, the last on the table."
  (append (loop for (x y) on blocks while y collect (fact "on-~A-~A" x y))
          (list (fact "ontable-~A" (first (last blocks))) (fact "clear-~A" (first blocks)))))

;;; Gripper

(defun gripper (balls &key (rooms 2))
  "A gripper-like transport domain: a robot with two grippers (left, right)
moves along a corridor of ROOMS rooms, picks up and drops BALLS balls. A
boolean per AT-ROBBY-R, AT-BALL-R, CARRY-BALL-G and FREE-G. Every ball starts
in the first room with the robot. Goals: every ball in the last room, and
ball 0 in the last room with the robot back in the first."
  (let* ((room-names (loop for r below rooms collect (format nil "r~D" r)))
         (ball-names (loop for b below balls collect (format nil "b~D" b)))
         (grippers '("left" "right"))
         (first-room (first room-names))
         (last-room (first (last room-names)))
         (facts (append (loop for r in room-names collect (fact "at-robby-~A" r))
                        (loop for b in ball-names
                              append (loop for r in room-names collect (fact "at-~A-~A" b r)))
                        (loop for b in ball-names
                              append (loop for g in grippers collect (fact "carry-~A-~A" b g)))
                        (loop for g in grippers collect (fact "free-~A" g))))
         (actions
           (append
            (loop for (from to) on room-names while to
                  collect (make-strips-action (fact "move-~A-~A" from to) (list (fact "at-robby-~A" from))
                                              (list (fact "at-robby-~A" to)) (list (fact "at-robby-~A" from)))
                  collect (make-strips-action (fact "move-~A-~A" to from) (list (fact "at-robby-~A" to))
                                              (list (fact "at-robby-~A" from)) (list (fact "at-robby-~A" to))))
            (loop for b in ball-names
                  append (loop for r in room-names
                               append (loop for g in grippers
                                            collect (make-strips-action
                                                     (fact "pick-~A-~A-~A" b r g)
                                                     (list (fact "at-~A-~A" b r) (fact "at-robby-~A" r) (fact "free-~A" g))
                                                     (list (fact "carry-~A-~A" b g))
                                                     (list (fact "at-~A-~A" b r) (fact "free-~A" g)))
                                            collect (make-strips-action
                                                     (fact "drop-~A-~A-~A" b r g)
                                                     (list (fact "carry-~A-~A" b g) (fact "at-robby-~A" r))
                                                     (list (fact "at-~A-~A" b r) (fact "free-~A" g))
                                                     (list (fact "carry-~A-~A" b g)))))))))
    (make-strips-problem
     :name (fact "gripper-~D-~D" balls rooms) :facts facts :actions actions
     :initial (append (list (fact "at-robby-~A" first-room))
                      (loop for b in ball-names collect (fact "at-~A-~A" b first-room))
                      (loop for g in grippers collect (fact "free-~A" g)))
     :goals (list (cons (fact "deliver-all") (loop for b in ball-names collect (fact "at-~A-~A" b last-room)))
                  (list (fact "deliver-one") (fact "at-~A-~A" (first ball-names) last-room)
                        (fact "at-robby-~A" first-room))))))

;;; As a spec

(defun conjunction (facts)
  "FACTS as a state expression: a lone fact, or (and FACT...)."
  (if (rest facts) (cons (fact "and") facts) (first facts)))

(defun strips-spec-forms (problem &key (state-space :reachable) (max-depth 40) optimize)
  "PROBLEM as a DEFSPEC body, its options first: (:state-space STATE-SPACE)
unless it is NIL, (:max-depth MAX-DEPTH), (:optimize OPTIMIZE) when given."
  (append (when state-space (list (list :state-space state-space)))
          (list (list :max-depth max-depth))
          (when optimize (list (list :optimize optimize)))
          (loop for f in (strips-problem-facts problem)
                collect (list (fact "state-variable") f (fact "boolean")
                              (fact (if (member f (strips-problem-initial problem)) "true" "false"))))
          (loop for action in (strips-problem-actions problem)
                collect (let ((del (set-difference (strips-action-del action) (strips-action-add action))))
                          ;; a fact both deleted and added stays true
                          (list* (fact "op") (strips-action-name action)
                                 :precond (conjunction (strips-action-pre action))
                                 :add (strips-action-add action)
                                 (when del (list :sub del)))))
          (loop for (name . facts) in (strips-problem-goals problem)
                collect (list (fact "event") name :state (conjunction facts)))))
