# `corridorsim world` as a user runs it: files, byte-identical reruns, exit code 2 on bad input.
file(REMOVE_RECURSE "${WORK_DIR}")
file(MAKE_DIRECTORY "${WORK_DIR}")

function(run_ok out)
  execute_process(COMMAND "${CORRIDORSIM}" world --seed 7 --out "${out}"
                  WORKING_DIRECTORY "${SOURCE_DIR}" RESULT_VARIABLE rc OUTPUT_VARIABLE stdout
                  ERROR_VARIABLE stderr)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "corridorsim world --seed 7 exited ${rc}: ${stderr}")
  endif()
  if(NOT stdout MATCHES "door plates 14")
    message(FATAL_ERROR "summary does not report 14 door plates:\n${stdout}")
  endif()
endfunction()

run_ok("${WORK_DIR}/a")
run_ok("${WORK_DIR}/b")
foreach(f world.obj world.mtl ground_truth.json map.png textures/wall.png textures/ceiling.png)
  if(NOT EXISTS "${WORK_DIR}/a/${f}")
    message(FATAL_ERROR "missing output ${f}")
  endif()
endforeach()
file(GLOB_RECURSE files RELATIVE "${WORK_DIR}/a" "${WORK_DIR}/a/*")
foreach(f ${files})
  file(SHA256 "${WORK_DIR}/a/${f}" ha)
  file(SHA256 "${WORK_DIR}/b/${f}" hb)
  if(NOT ha STREQUAL hb)
    message(FATAL_ERROR "${f} differs between two runs with the same seed")
  endif()
endforeach()

# Bad input: exit code 2 and one message naming file:line:column: key.
file(WRITE "${WORK_DIR}/bad.yaml" "seed: 3\nworld:\n  width_m: -1\n")
execute_process(COMMAND "${CORRIDORSIM}" world "${WORK_DIR}/bad.yaml" --out "${WORK_DIR}/c"
                RESULT_VARIABLE rc ERROR_VARIABLE stderr OUTPUT_QUIET)
if(NOT rc EQUAL 2)
  message(FATAL_ERROR "bad input exited ${rc}, expected 2")
endif()
if(NOT stderr MATCHES "bad.yaml:3:3: world.width_m: ")
  message(FATAL_ERROR "unexpected message for bad input: ${stderr}")
endif()

execute_process(COMMAND "${CORRIDORSIM}" world "${WORK_DIR}/missing.yaml" RESULT_VARIABLE rc
                ERROR_VARIABLE stderr OUTPUT_QUIET)
if(NOT rc EQUAL 2 OR NOT stderr MATCHES "missing.yaml: cannot open")
  message(FATAL_ERROR "missing scenario: exit ${rc}, ${stderr}")
endif()

execute_process(COMMAND "${CORRIDORSIM}" world --help RESULT_VARIABLE rc OUTPUT_VARIABLE stdout)
if(NOT rc EQUAL 0 OR NOT stdout MATCHES "--seed" OR NOT stdout MATCHES "--out")
  message(FATAL_ERROR "world --help: exit ${rc}, ${stdout}")
endif()

execute_process(COMMAND "${CORRIDORSIM}" world --bogus RESULT_VARIABLE rc OUTPUT_QUIET ERROR_QUIET)
if(NOT rc EQUAL 2)
  message(FATAL_ERROR "unknown option exited ${rc}, expected 2")
endif()
