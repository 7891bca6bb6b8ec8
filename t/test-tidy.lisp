;;;; test-tidy.lisp -- leftovers tidied: an undecodable `bin/player model
;;;; --texture` file is one error, and a character that root motion carried
;;;; rests where it arrived.

(in-package #:player-tests)

(def-suite* tidy :in player-tests)

;;; ---------------------------------------------------------------------------
;;; `player model --texture` with a file that is not a picture

(test model-command-refuses-an-undecodable-texture
  "A --texture file stb_image cannot decode is one `player: error:` line on
stderr naming the file and the reason, exit 1, and no summary."
  (with-stb
    (with-assimp-models
      (let ((gltf (assimp-model "glTF/BoxTextured-glTF/BoxTextured.gltf")))
        (with-image-file (path "png")
          (with-open-file (out path :direction :output :if-exists :supersede)
            (write-line "not a picture" out))
          (multiple-value-bind (out err code) (player-command "model" gltf "--texture" (namestring path))
            (let ((lines (remove "" (uiop:split-string err :separator '(#\Newline)) :test #'string=)))
              (is (= 1 code) "exit ~D: ~A" code err)
              (is (= 1 (length lines)) "~S" lines)
              (is (eql 0 (search "player: error: " (first lines))) "~A" err)
              (is (search (file-namestring path) err) "the texture file is not named: ~A" err)
              (is (search "stb_image cannot decode it" err) "no reason given: ~A" err)
              (is (not (search "textures:" out)) "a summary was printed: ~A" out))))))))
