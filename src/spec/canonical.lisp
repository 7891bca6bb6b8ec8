;;;; canonical.lisp -- state expressions as sets of cubes over the one-hot state.
;;;;
;;;; Each plannable variable owns a field of bits, one per value; a state has
;;;; exactly one bit set per field. A cube is an integer with, per field, the
;;;; bits of the values it allows, so "state S is in cube C" is the single test
;;;; (zerop (logandc2 S C)) and intersection is LOGAND. An expression becomes a
;;;; disjunction of cubes (DNF), simplified so equivalent goals usually merge.

(in-package #:player.spec)

(defun plannable-variables (spec)
  "SPEC's plannable variables, in declaration order."
  (remove-if-not #'plannable-p (spec-variables spec)))

(defun top-cube (spec)
  "The cube allowing every state of SPEC."
  (1- (ash 1 (spec-bit-count spec))))

(declaim (inline state-in-cube-p))
(defun state-in-cube-p (state cube)
  "True when one-hot STATE lies in CUBE."
  (zerop (logandc2 state cube)))

(defun cube-empty-p (cube spec)
  "True when some variable has no allowed value in CUBE."
  (loop for var in (plannable-variables spec)
          thereis (zerop (logand cube (var-field-mask var)))))

(declaim (inline cube-subset-p))
(defun cube-subset-p (inner outer)
  "True when every state of cube INNER lies in cube OUTER."
  (zerop (logandc2 inner outer)))

(defun cube-support (cube spec)
  "The fields of the variables CUBE constrains, as a mask."
  (loop for var in (plannable-variables spec)
        for mask = (var-field-mask var)
        unless (= (logand cube mask) mask) sum mask))

(defun literal-cube (var index spec)
  "The cube VAR = its INDEXth value."
  (logior (logandc2 (top-cube spec) (var-field-mask var)) (var-value-bit var index)))

(defun intersect-dnf (left right spec)
  "The conjunction of two cube lists."
  (simplify-cubes (loop for a in left
                        nconc (loop for b in right
                                    for c = (logand a b)
                                    unless (cube-empty-p c spec) collect c))
                  spec))

(defun negate-cube (cube spec)
  "The complement of CUBE: one cube per constrained variable, allowing the other values."
  (loop with top = (top-cube spec)
        for var in (plannable-variables spec)
        for mask = (var-field-mask var)
        for field = (logand cube mask)
        unless (= field mask)
          collect (logior (logandc2 top mask) (logandc2 mask field))))

(defun negate-dnf (cubes spec)
  "The complement of the disjunction CUBES."
  (reduce (lambda (acc cube) (intersect-dnf acc (negate-cube cube spec) spec))
          cubes :initial-value (list (top-cube spec))))

(defun expression-cubes (ast spec)
  "The simplified DNF (list of cubes) of state expression AST."
  (ecase (first ast)
    (:const (if (second ast) (list (top-cube spec)) '()))
    (:lit (list (literal-cube (second ast) (third ast) spec)))
    (:class (class-cubes (second ast) spec))
    (:and (reduce (lambda (acc e) (intersect-dnf acc (expression-cubes e spec) spec))
                  (rest ast) :initial-value (list (top-cube spec))))
    (:or (simplify-cubes (loop for e in (rest ast) append (expression-cubes e spec)) spec))
    (:not (negate-dnf (expression-cubes (second ast) spec) spec))))

(defun merge-adjacent (a b spec)
  "The single cube equal to A or B when they differ in one field only, else NIL."
  (let ((differing (loop for var in (plannable-variables spec)
                         for mask = (var-field-mask var)
                         unless (= (logand a mask) (logand b mask)) collect mask)))
    (when (and differing (null (rest differing)))
      (logior a b))))

(defun simplify-cubes (cubes spec)
  "CUBES without empty, duplicate or subsumed cubes, adjacent cubes merged,
sorted: the canonical form goals are compared in."
  (let ((cubes (remove-duplicates (remove-if (lambda (c) (cube-empty-p c spec)) cubes))))
    (loop
      (setf cubes (remove-if (lambda (c)
                               (some (lambda (d) (and (/= c d) (cube-subset-p c d))) cubes))
                             cubes))
      (let ((merge (loop for (a . rest) on cubes
                         thereis (loop for b in rest
                                       for m = (merge-adjacent a b spec)
                                       when m return (list a b m)))))
        (if merge
            (destructuring-bind (a b m) merge
              (setf cubes (cons m (remove b (remove a cubes)))))
            (return (sort cubes #'<)))))))

(defun value-symbol (var index spec)
  "The symbol VAR.VALUE for INDEX, interned in SPEC's package so it reads back."
  (intern (format nil "~A.~A" (symbol-name (var-name var))
                  (string-upcase (value-name (aref (var-domain var) index))))
          (spec-package spec)))

(defun field-expression (var field spec)
  "A readable expression for VAR's allowed-values FIELD (shifted to bit 0)."
  (let* ((allowed (loop for i below (var-domain-size var) when (logbitp i field) collect i))
         (excluded (loop for i below (var-domain-size var) unless (logbitp i field) collect i)))
    (cond ((eq (var-kind var) :boolean)
           (if (equal allowed '(1)) (var-name var) (list 'not (var-name var))))
          ((null (rest allowed)) (value-symbol var (first allowed) spec))
          ((null (rest excluded)) (list 'not (value-symbol var (first excluded) spec)))
          (t (cons 'or (mapcar (lambda (i) (value-symbol var i spec)) allowed))))))

(defun cube-expression (cube spec)
  "A readable state expression equal to CUBE."
  (let ((parts (loop for var in (plannable-variables spec)
                     for mask = (var-field-mask var)
                     for field = (logand cube mask)
                     unless (= field mask)
                       collect (field-expression var (ash field (- (var-bit-offset var))) spec))))
    (cond ((null parts) 'true)
          ((null (rest parts)) (first parts))
          (t (cons 'and parts)))))

(defun cubes-expression (cubes spec)
  "A readable state expression equal to the disjunction CUBES."
  (cond ((null cubes) 'false)
        ((null (rest cubes)) (cube-expression (first cubes) spec))
        (t (cons 'or (mapcar (lambda (c) (cube-expression c spec)) cubes)))))

(defun value-index-in-state (state var)
  "The index of the value plannable VAR has in the one-hot STATE."
  (1- (integer-length (ldb (byte (var-domain-size var) (var-bit-offset var)) state))))

(defun state-assignments (state spec)
  "The one-hot STATE as a list of (VARIABLE-DEF . VALUE-INDEX), one per
plannable variable of SPEC, in declaration order."
  (loop for var in (plannable-variables spec)
        collect (cons var (value-index-in-state state var))))
