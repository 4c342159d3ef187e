# `corridorsim world` as a user runs it: files, byte-identical reruns, exit code 2 on bad input.
include("${CMAKE_CURRENT_LIST_DIR}/cli_support.cmake")

foreach(out a b)
  cli_run(EXIT 0 WHAT "world --seed 7" STDOUT "door plates 14"
          ARGS world --seed 7 --out "${WORK_DIR}/${out}")
endforeach()
cli_expect_files("${WORK_DIR}/a" world.obj world.mtl ground_truth.json map.png textures/wall.png
                 textures/ceiling.png)
cli_expect_same_files("${WORK_DIR}/a" "${WORK_DIR}/b")

# Bad input: exit code 2 and one message naming file:line:column: key.
cli_expect_bad(bad "seed: 3\nworld:\n  width_m: -1\n" "bad.yaml:3:3: world.width_m: " world
               --out "${WORK_DIR}/c")
cli_run(EXIT 2 WHAT "missing scenario" STDERR "missing.yaml: cannot open"
        ARGS world "${WORK_DIR}/missing.yaml")
cli_run(EXIT 0 WHAT "world --help" STDOUT "--seed" ARGS world --help)
if(NOT CLI_STDOUT MATCHES "--out")
  message(FATAL_ERROR "world --help does not name --out:\n${CLI_STDOUT}")
endif()
cli_run(EXIT 2 WHAT "unknown option" ARGS world --bogus)
