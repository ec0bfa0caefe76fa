# SPDX-License-Identifier: GPL-3.0-or-later
# Loads FILE with EXE (translucent_load_mesh); it must fail cleanly: exit status 1 (a crash is a
# signal, which execute_process reports as text), stderr naming the file and containing EXPECTED
# literally (not as a regular expression: messages hold brackets and dots).
execute_process(COMMAND ${EXE} ${FILE} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err
                TIMEOUT 20)
if(NOT rc STREQUAL "1")
  message(FATAL_ERROR "expected a clean error (exit status 1), got '${rc}':\n${out}\n${err}")
endif()
string(FIND "${err}" "mesh file '${FILE}'" named)
if(named EQUAL -1)
  message(FATAL_ERROR "the error does not name the file '${FILE}':\n${err}")
endif()
string(FIND "${err}" "${EXPECTED}" found)
if(found EQUAL -1)
  message(FATAL_ERROR "the error does not contain '${EXPECTED}':\n${err}")
endif()
