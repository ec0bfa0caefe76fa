# SPDX-License-Identifier: GPL-3.0-or-later
# Runs EXE FAMILY FILE (translucent_check_input). It must end cleanly with an error (exit status
# 1) or a warning (3): a crash is a signal, which execute_process reports as text, a hang is the
# timeout, and 0 means the input was accepted without a word. stderr must name the file (its
# name: scene errors about a referenced file name that one) and contain EXPECTED literally.
string(REPLACE "<semicolon>" ";" EXPECTED "${EXPECTED}")
execute_process(COMMAND ${EXE} ${FAMILY} ${FILE} RESULT_VARIABLE rc OUTPUT_VARIABLE out
                ERROR_VARIABLE err TIMEOUT 40)
if(NOT rc STREQUAL "1" AND NOT rc STREQUAL "3")
  message(FATAL_ERROR "expected a clean error (exit status 1) or a warning (3), got '${rc}':\n${out}\n${err}")
endif()
get_filename_component(name ${FILE} NAME)
string(FIND "${err}" "${name}" named)
if(named EQUAL -1)
  message(FATAL_ERROR "the message does not name the file '${name}':\n${err}")
endif()
string(FIND "${err}" "${EXPECTED}" found)
if(found EQUAL -1)
  message(FATAL_ERROR "the message does not contain '${EXPECTED}':\n${err}")
endif()
