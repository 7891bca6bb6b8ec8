;;;; package.lisp -- player.speech: Sound files, espeak-ng synthesis with its phonemes as visemes, pocketsphinx recognition, playback.

(defpackage #:player.speech
  (:use #:cl #:player.base #:player.spec)
  (:import-from #:alexandria
                #:when-let #:if-let #:ensure-list #:hash-table-keys
                #:with-gensyms #:once-only #:appendf #:read-file-into-string)
  (:documentation "Sound files, espeak-ng synthesis with its phonemes as visemes, pocketsphinx recognition, playback.")
  (:export
   #:*default-speech-rate* #:*default-voice* #:audio-playback-problem #:clip #:clip-cut
   #:clip-sound #:clip-start #:ensure-espeak #:load-pocketsphinx-library #:make-clip
   #:make-sound #:mix-clips #:phoneme-viseme #:play-sound-now #:pocketsphinx-model-files
   #:*capture-device* #:open-capture #:close-capture #:read-capture #:listen-for-requests
   #:*rejection-margin* #:*longest-phone* #:*most-unexplained-speech* #:*longest-request* #:read-request-wav #:wav-header-duration
   #:read-wav #:recognize-sound #:recognize-wav #:samples #:sound #:sound-duration
   #:sound-p #:sound-rate #:sound-samples #:speech-error #:speech-unavailable
   #:synthesize-speech #:utterance #:utterance-duration #:utterance-phonemes
   #:utterance-sound #:utterance-text #:utterance-visemes #:utterance-word #:utterance-word-time #:utterance-words #:wav-fail #:write-wav
   #:track-tune #:title-tempo #:clip-kind #:clip-end #:clip-label #:play-clip-now #:stop-cut-clips))
