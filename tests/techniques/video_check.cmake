# SPDX-License-Identifier: GPL-3.0-or-later
# `render --frames N --video FILE` through Debian's ffmpeg (scripts/install-deps installs it):
# renders, then asks ffprobe what FILE holds: an H.264 stream of the frame size with exactly N
# decoded frames at the requested rate. EXE, ARGS, VIDEO, FRAMES, SIZE (WxH) and FPS come from
# tests/techniques/CMakeLists.txt.
find_program(FFPROBE ffprobe)
if(NOT FFPROBE)
  message(FATAL_ERROR "ffprobe is not on PATH: run scripts/install-deps (Debian's ffmpeg)")
endif()
separate_arguments(ARGS)
file(REMOVE ${VIDEO})
execute_process(COMMAND ${EXE} ${ARGS} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "exit ${rc}:\n${out}\n${err}")
endif()
if(NOT out MATCHES "wrote [^\n]*${FRAMES} frames at ${FPS} fps, ffmpeg")
  message(FATAL_ERROR "stdout does not report the video:\n${out}")
endif()
execute_process(COMMAND ${FFPROBE} -v error -count_frames -select_streams v:0
                        -show_entries stream=codec_name,width,height,nb_read_frames,r_frame_rate
                        -of default=noprint_wrappers=1 ${VIDEO}
                RESULT_VARIABLE prc OUTPUT_VARIABLE probe ERROR_VARIABLE perr)
if(NOT prc EQUAL 0)
  message(FATAL_ERROR "ffprobe cannot read ${VIDEO} (exit ${prc}): ${perr}")
endif()
string(REPLACE "x" ";" wh ${SIZE})
list(GET wh 0 w)
list(GET wh 1 h)
foreach(expected "codec_name=h264" "width=${w}" "height=${h}" "r_frame_rate=${FPS}/1"
                 "nb_read_frames=${FRAMES}")
  if(NOT probe MATCHES "(^|\n)${expected}(\n|$)")
    message(FATAL_ERROR "${VIDEO}: expected ${expected}; ffprobe says:\n${probe}")
  endif()
endforeach()
# The frames' temporary folder is gone.
file(GLOB left "${VIDEO}.frames-*")
if(left)
  message(FATAL_ERROR "temporary frames left behind: ${left}")
endif()
