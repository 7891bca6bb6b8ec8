;;;; caption-font.lisp -- a 5x7 dot-matrix font for captions drawn into a frame.
;;;; The glyphs follow the upper-case, digit and punctuation cells of the
;;;; classic 5x7 character generators of dot-matrix LCD controllers (the
;;;; Hitachi HD44780's ROM A00 is the best known), redrawn here by hand as
;;;; strings: a caption is an op's name, so letters, digits and - . _ ? ! are
;;;; enough, and a built-in table needs no font file and no new dependency.
;;;; Lower case is drawn as upper case; any other character as ?.

(in-package #:player.render)

(defparameter *caption-glyphs*
  '((#\A ".###." "#...#" "#...#" "#####" "#...#" "#...#" "#...#")
    (#\B "####." "#...#" "#...#" "####." "#...#" "#...#" "####.")
    (#\C ".###." "#...#" "#...." "#...." "#...." "#...#" ".###.")
    (#\D "###.." "#..#." "#...#" "#...#" "#...#" "#..#." "###..")
    (#\E "#####" "#...." "#...." "####." "#...." "#...." "#####")
    (#\F "#####" "#...." "#...." "####." "#...." "#...." "#....")
    (#\G ".###." "#...#" "#...." "#.###" "#...#" "#...#" ".####")
    (#\H "#...#" "#...#" "#...#" "#####" "#...#" "#...#" "#...#")
    (#\I ".###." "..#.." "..#.." "..#.." "..#.." "..#.." ".###.")
    (#\J "..###" "...#." "...#." "...#." "...#." "#..#." ".##..")
    (#\K "#...#" "#..#." "#.#.." "##..." "#.#.." "#..#." "#...#")
    (#\L "#...." "#...." "#...." "#...." "#...." "#...." "#####")
    (#\M "#...#" "##.##" "#.#.#" "#.#.#" "#...#" "#...#" "#...#")
    (#\N "#...#" "#...#" "##..#" "#.#.#" "#..##" "#...#" "#...#")
    (#\O ".###." "#...#" "#...#" "#...#" "#...#" "#...#" ".###.")
    (#\P "####." "#...#" "#...#" "####." "#...." "#...." "#....")
    (#\Q ".###." "#...#" "#...#" "#...#" "#.#.#" "#..#." ".##.#")
    (#\R "####." "#...#" "#...#" "####." "#.#.." "#..#." "#...#")
    (#\S ".####" "#...." "#...." ".###." "....#" "....#" "####.")
    (#\T "#####" "..#.." "..#.." "..#.." "..#.." "..#.." "..#..")
    (#\U "#...#" "#...#" "#...#" "#...#" "#...#" "#...#" ".###.")
    (#\V "#...#" "#...#" "#...#" "#...#" "#...#" ".#.#." "..#..")
    (#\W "#...#" "#...#" "#...#" "#.#.#" "#.#.#" "#.#.#" ".#.#.")
    (#\X "#...#" "#...#" ".#.#." "..#.." ".#.#." "#...#" "#...#")
    (#\Y "#...#" "#...#" "#...#" ".#.#." "..#.." "..#.." "..#..")
    (#\Z "#####" "....#" "...#." "..#.." ".#..." "#...." "#####")
    (#\0 ".###." "#...#" "#..##" "#.#.#" "##..#" "#...#" ".###.")
    (#\1 "..#.." ".##.." "..#.." "..#.." "..#.." "..#.." ".###.")
    (#\2 ".###." "#...#" "....#" "...#." "..#.." ".#..." "#####")
    (#\3 "#####" "...#." "..#.." "...#." "....#" "#...#" ".###.")
    (#\4 "...#." "..##." ".#.#." "#..#." "#####" "...#." "...#.")
    (#\5 "#####" "#...." "####." "....#" "....#" "#...#" ".###.")
    (#\6 "..##." ".#..." "#...." "####." "#...#" "#...#" ".###.")
    (#\7 "#####" "....#" "...#." "..#.." ".#..." ".#..." ".#...")
    (#\8 ".###." "#...#" "#...#" ".###." "#...#" "#...#" ".###.")
    (#\9 ".###." "#...#" "#...#" ".####" "....#" "...#." ".##..")
    (#\- "....." "....." "....." "#####" "....." "....." ".....")
    (#\. "....." "....." "....." "....." "....." ".##.." ".##..")
    (#\_ "....." "....." "....." "....." "....." "....." "#####")
    (#\? ".###." "#...#" "....#" "...#." "..#.." "....." "..#..")
    (#\! "..#.." "..#.." "..#.." "..#.." "..#.." "....." "..#..")
    (#\Space "....." "....." "....." "....." "....." "....." "....."))
  "The caption font: per character, seven rows of five dots (# lit, . dark), top row first.")

(defconstant +glyph-columns+ 5 "Dots across a caption glyph.")
(defconstant +glyph-rows+ 7 "Dots down a caption glyph.")
(defconstant +glyph-advance+ 6 "Dots from one glyph's left edge to the next's: a dot of space between.")

(defun caption-glyph (char)
  "The seven row strings of CHAR in the caption font (lower case as upper, unknown characters as ?)."
  (rest (or (assoc (char-upcase char) *caption-glyphs*)
            (assoc #\? *caption-glyphs*))))

(defun caption-text-runs (text)
  "The lit dots of TEXT in the caption font as horizontal runs (COLUMN ROW
LENGTH) in dot units, row 0 at the top; merging a row's neighbouring dots into
one run keeps the number of rectangles to draw small."
  (loop for char across text
        for left from 0 by +glyph-advance+
        nconc (loop for row in (caption-glyph char)
                    for y from 0
                    nconc (loop with runs = '() and start = nil
                                for x from 0 to +glyph-columns+
                                for lit = (and (< x +glyph-columns+) (char= (char row x) #\#))
                                do (cond ((and lit (null start)) (setf start x))
                                         ((and (not lit) start)
                                          (push (list (+ left start) y (- x start)) runs)
                                          (setf start nil)))
                                finally (return (nreverse runs))))))

(defun caption-text-width (text)
  "TEXT's width in dots of the caption font (no trailing space)."
  (if (zerop (length text)) 0 (- (* +glyph-advance+ (length text)) 1)))
