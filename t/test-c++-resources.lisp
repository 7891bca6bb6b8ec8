;;;; test-c++-resources.lisp -- the fixed C++ the generator copies lives in
;;;; src/cpp/resources/: each file is read as it is (its final newline off),
;;;; and a missing one is a PLAYER-ERROR naming it, not a crash.

(in-package #:player-tests)

(def-suite* c++-resources :in player-tests)

(test c++-resource-is-the-file-without-its-final-newline
  (let ((text (player.cpp::c++-resource "timed-constants.cpp")))
    (is (eql 0 (search "// The timed layer" text)))
    (is (char/= #\Newline (char text (1- (length text)))))
    (is (string= (concatenate 'string text (string #\Newline))
                 (alexandria:read-file-into-string
                  (merge-pathnames "timed-constants.cpp" player.cpp::*c++-resources-directory*))))))

(test missing-c++-resource-is-a-player-error
  (let ((player.cpp::*c++-resources-directory* #p"/nonexistent-player-resources/"))
    (let ((condition (handler-case (progn (player.cpp::c++-resource "timeline-clock.cpp") nil)
                       (player-error (e) e))))
      (is (typep condition 'player-error))
      (is (search "timeline-clock.cpp" (princ-to-string condition)))
      (is (search "src/cpp/resources/" (princ-to-string condition))))))
