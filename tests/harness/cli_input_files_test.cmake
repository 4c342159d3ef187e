# `corridorsim run --check` on input files that are not regular files: exit 2 with one message,
# never a hang (CTest's TIMEOUT on this test fails it if opening a FIFO blocks).
include("${CMAKE_CURRENT_LIST_DIR}/cli_support.cmake")

find_program(MKFIFO mkfifo REQUIRED)
execute_process(COMMAND ${MKFIFO} "${WORK_DIR}/pipe.yaml" RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "mkfifo failed")
endif()

# An include naming a FIFO: refused at the include line, without waiting for a writer.
cli_expect_bad(fifo_include "seed: 2\ninclude: pipe.yaml\n"
               "^corridorsim: error: [^\n]*fifo_include.yaml:2:10: include: included file '[^']*pipe.yaml' is a FIFO \\(named pipe\\), not a regular file\n$"
               run --check)
# The FIFO itself as the scenario.
cli_run(EXIT 2 WHAT "fifo scenario" STDERR "pipe.yaml: cannot open the file: it is a FIFO"
        ARGS run "${WORK_DIR}/pipe.yaml" --check)
# A device: never read (reading /dev/zero would never end).
cli_expect_bad(device_include "include: /dev/zero\n"
               "device_include.yaml:1:10: include: included file '/dev/zero' is a character device"
               run --check)
# Two documents in one file.
cli_expect_bad(two_documents "seed: 2\n---\nseed: 3\n"
               "two_documents.yaml:2:1: a second YAML document starts here" run --check)

# A long expectation is quoted in the message only as a short excerpt (it was echoed whole, twice).
string(REPEAT "9" 5000 nines)
file(WRITE "${WORK_DIR}/long_expectation.yaml"
     "include: ${SOURCE_DIR}/scenarios/default.yaml\nexpectations:\n  - odometry.ate_${nines}_m < 1\n")
execute_process(COMMAND "${CORRIDORSIM}" run "${WORK_DIR}/long_expectation.yaml" --check
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
string(LENGTH "${err}" err_length)
string(REPEAT "9" 300 long_run)
if(NOT rc EQUAL 2 OR NOT err MATCHES "long_expectation.yaml:3:5: expectations: .*unknown metric"
   OR err MATCHES "${long_run}")
  message(FATAL_ERROR "long expectation: exit ${rc}, ${err_length} bytes of message:\n${err}")
endif()

# A file that is not a scenario (none of its keys is a scenario key), included or given: named by
# its position and kind only, never quoted (`include: /etc/shadow` quoted its first line).
file(WRITE "${WORK_DIR}/secrets.yaml" "zqxroot: s3cr3t-hash-1\nzqxdaemon: s3cr3t-hash-2\n")
file(WRITE "${WORK_DIR}/include_not_scenario.yaml" "seed: 2\ninclude: secrets.yaml\n")
cli_run(EXIT 2 WHAT "include of a file that is not a scenario"
        STDERR "^corridorsim: error: [^\n]*secrets.yaml: not a corridorsim scenario: a YAML map of 2 key\\(s\\), none of them a scenario key [^\n]*\n$"
        ARGS run "${WORK_DIR}/include_not_scenario.yaml" --check)
if(CLI_STDERR MATCHES "s3cr3t|zqx")
  message(FATAL_ERROR "the message quotes the file's content:\n${CLI_STDERR}")
endif()
cli_run(EXIT 2 WHAT "not a scenario given" STDERR "secrets.yaml: not a corridorsim scenario"
        ARGS run "${WORK_DIR}/secrets.yaml" --check)
if(CLI_STDERR MATCHES "s3cr3t|zqx")
  message(FATAL_ERROR "the message quotes the file's content:\n${CLI_STDERR}")
endif()
