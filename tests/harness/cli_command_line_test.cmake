# The command line as a user types it: every number strict (no wrap-around, junk, hex, inf or
# nan), exit code 2 with `command line: --flag: ...` before anything is read or written, and the
# default scenario named when none is given.
include("${CMAKE_CURRENT_LIST_DIR}/cli_support.cmake")

set(out "${WORK_DIR}/out")
foreach(seed "-1" "18446744073709551616" "12abc" "0x10" "1e3" "+1" "nan")
  foreach(job world drive run)
    cli_run(EXIT 2 WHAT "${job} --seed '${seed}'" NOT_EXISTS "${out}"
            STDERR "command line: --seed: expected a decimal integer"
            ARGS ${job} --seed "${seed}" --out "${out}")
  endforeach()
endforeach()
foreach(pose "1,2,3,4" "inf,0,0" "0,nan,0" "0x10,0,0" "1,,3" "1e400,0,0" "200000,0,0" "0,0,720")
  cli_run(EXIT 2 WHAT "snapshot --pose '${pose}'" NOT_EXISTS "${out}"
          STDERR "command line: --pose: expected x,y,yaw"
          ARGS snapshot "--pose=${pose}" --out "${out}")
endforeach()
# A bad number is reported as the flag, even with a bad scenario: the command line comes first.
file(WRITE "${WORK_DIR}/bad.yaml" "world:\n  width_m: -1\n")
cli_run(EXIT 2 WHAT "bad seed before bad scenario" STDERR "^corridorsim: error: command line: --seed:"
        ARGS world "${WORK_DIR}/bad.yaml" --seed 12abc --out "${out}")
cli_run(EXIT 2 WHAT "no subcommand" STDERR "command line: " ARGS)
cli_run(EXIT 2 WHAT "empty --out" STDERR "command line: --out: "
        ARGS world --out=)

# No scenario given: the file used is named (one line on stderr, an absolute path).
cli_run(EXIT 0 WHAT "world without a scenario"
        STDERR "corridorsim: no scenario given; using /[^\n]*/scenarios/default\\.yaml\n"
        ARGS world --seed 7 --out "${WORK_DIR}/w")
cli_run(EXIT 0 WHAT "world with a scenario" ARGS world "${SOURCE_DIR}/scenarios/default.yaml"
        --seed 7 --out "${WORK_DIR}/w2")
if(CLI_STDERR MATCHES "no scenario given")
  message(FATAL_ERROR "a given scenario was reported as the default:\n${CLI_STDERR}")
endif()
