;;;; classes.lisp -- the state class hierarchy.
;;;; A class is the conjunction of its elements with multiple inheritance, where a
;;;; later element overrides what earlier ones said about the same variables:
;;;; (state-class c (a posture.sit)) is A with posture set to sit, not A and sit.

(in-package #:player.spec)

(defun class-cubes (class spec)
  "The DNF of CLASS, computed once. Each element frees the variables it
constrains in what came before it, then is conjoined."
  (or (state-class-dnf class)
      (setf (state-class-dnf class)
            (let ((acc (list (top-cube spec))))
              (dolist (element (state-class-elements class) acc)
                (let* ((cubes (expression-cubes element spec))
                       (support (reduce #'logior cubes
                                        :key (lambda (c) (cube-support c spec))
                                        :initial-value 0)))
                  (setf acc (intersect-dnf (mapcar (lambda (a) (logior a support)) acc)
                                           cubes spec))))))))

(defun class-references (ast)
  "The classes state expression AST mentions directly."
  (case (first ast)
    (:class (list (second ast)))
    ((:not :and :or) (mapcan #'class-references (rest ast)))
    (t '())))

(defun check-class-cycles (spec)
  "Signal CLASS-CYCLE-ERROR when a class inherits from itself, naming the cycle."
  (let ((state (make-hash-table)))
    (labels ((visit (class path)
               (case (gethash class state)
                 (:done)
                 (:active
                  (let ((cycle (reverse (cons class (ldiff path (rest (member class path)))))))
                    (spec-fail 'class-cycle-error (state-class-form class)
                               "state classes inherit in a cycle: ~{~A~^ -> ~}"
                               (mapcar (lambda (c) (lisp-text (state-class-name c))) cycle))))
                 (t (setf (gethash class state) :active)
                    (dolist (parent (mapcan #'class-references (state-class-elements class)))
                      (visit parent (cons class path)))
                    (setf (gethash class state) :done)))))
      (loop for class being the hash-values of (spec-classes spec)
            do (visit class '())))))
