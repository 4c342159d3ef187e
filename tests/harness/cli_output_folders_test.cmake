# Output folders and exit codes as a user meets them: no shell ever sees a path (plots are
# started with an argument vector), a folder holding files is refused without --force and
# replaced whole with it, a killed run leaves the previous folder as it was, and a run whose
# results are written exits 4 (not 1) when an extra such as plots/ fails.
include("${CMAKE_CURRENT_LIST_DIR}/cli_support.cmake")

file(WRITE "${WORK_DIR}/short.yaml"
     "include: ${SOURCE_DIR}/tests/data/scenarios/odometry_consistency.yaml\nduration_s: 4\n")
execute_process(COMMAND python3 -c "import matplotlib, numpy" RESULT_VARIABLE no_matplotlib
                OUTPUT_QUIET ERROR_QUIET)
if(no_matplotlib)
  execute_process(COMMAND /usr/bin/python3 -c "import matplotlib, numpy"
                  RESULT_VARIABLE no_matplotlib OUTPUT_QUIET ERROR_QUIET)
endif()

# 1. A folder name that a shell would run: quote, semicolons, $(...), redirection, spaces.
string(ASCII 59 semicolon)
set(evil "${WORK_DIR}/o/q'${semicolon} echo INJECTED > ${WORK_DIR}/injected.txt${semicolon} echo ' $(touch ${WORK_DIR}/dollar.txt) `touch ${WORK_DIR}/tick.txt` end")
set(plots_arg "")
if(no_matplotlib)
  set(plots_arg "--no-plots")
  message(STATUS "no python3 with matplotlib: the plots of the quoted folder are not checked")
endif()
execute_process(COMMAND "${CORRIDORSIM}" run "${WORK_DIR}/short.yaml" --out "${evil}" ${plots_arg}
                WORKING_DIRECTORY "${WORK_DIR}" RESULT_VARIABLE rc OUTPUT_VARIABLE stdout
                ERROR_VARIABLE stderr)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "run into a quoted folder: exit ${rc}\n${stdout}\n${stderr}")
endif()
foreach(injected injected.txt dollar.txt tick.txt)
  if(EXISTS "${WORK_DIR}/${injected}")
    message(FATAL_ERROR "a shell ran part of the folder name: ${injected} was created")
  endif()
endforeach()
cli_expect_files("${evil}" metrics.json timing.json events.json scenario.yaml)
if(NOT no_matplotlib)
  cli_expect_files("${evil}" plots/trajectories.png plots/summary.png)
endif()

# 2. A folder holding a previous run is refused (exit 2, naming --force) and left as it was.
set(run "${WORK_DIR}/run")
cli_run(EXIT 0 WHAT "first run" ARGS run "${WORK_DIR}/short.yaml" --out "${run}" --no-plots
        --no-viewer)
file(WRITE "${run}/from_an_older_run.txt" "x")
file(SHA256 "${run}/metrics.json" first_metrics)
cli_run(EXIT 2 WHAT "rerun without --force" NOT_STDOUT "real-time factor"
        STDERR "command line: --out: '[^']*/run' is not empty .*pass --force"
        ARGS run "${WORK_DIR}/short.yaml" --out "${run}" --no-plots --no-viewer --seed 5)
file(SHA256 "${run}/metrics.json" kept_metrics)
if(NOT kept_metrics STREQUAL first_metrics OR NOT EXISTS "${run}/from_an_older_run.txt")
  message(FATAL_ERROR "a refused run changed the previous folder")
endif()

# 3. --force replaces it whole: nothing of the previous folder is left, no staging folder stays.
cli_run(EXIT 0 WHAT "rerun with --force" ARGS run "${WORK_DIR}/short.yaml" --out "${run}" --no-plots
        --no-viewer --seed 5 --force)
if(EXISTS "${run}/from_an_older_run.txt")
  message(FATAL_ERROR "--force mixed the previous folder's files into the new run")
endif()
file(SHA256 "${run}/metrics.json" forced_metrics)
if(forced_metrics STREQUAL first_metrics)
  message(FATAL_ERROR "--force did not write the new run (seed 5)")
endif()
file(GLOB staging LIST_DIRECTORIES true "${WORK_DIR}/.run.partial-*")
if(staging)
  message(FATAL_ERROR "staging folders left: ${staging}")
endif()

# 4. A killed run leaves the previous folder untouched; the next run removes its staging folder.
file(WRITE "${WORK_DIR}/long.yaml"
     "include: ${SOURCE_DIR}/tests/data/scenarios/odometry_consistency.yaml
path: {kind: script, commands: [[100000, 0, 0]]}\n")
# Killed after 5 s, or, on a loaded machine (a sanitizer build beside other tests) where it had
# not yet made its staging folder by then, after 60 s: the kill must find it running.
foreach(timeout 5 60)
  execute_process(COMMAND "${CORRIDORSIM}" run "${WORK_DIR}/long.yaml" --out "${run}" --no-plots
                          --no-viewer --force
                  TIMEOUT ${timeout} RESULT_VARIABLE rc OUTPUT_QUIET ERROR_VARIABLE stderr)
  if(rc EQUAL 0 OR rc EQUAL 2)
    message(FATAL_ERROR "the long run was not killed (exit ${rc}):\n${stderr}")
  endif()
  file(SHA256 "${run}/metrics.json" after_kill)
  if(NOT after_kill STREQUAL forced_metrics)
    message(FATAL_ERROR "a killed run changed the previous folder")
  endif()
  file(GLOB staging LIST_DIRECTORIES true "${WORK_DIR}/.run.partial-*")
  if(staging)
    break()
  endif()
endforeach()
if(NOT staging)
  message(FATAL_ERROR "the killed run left no staging folder (was it killed while running?)")
endif()
cli_run(EXIT 0 WHAT "run after a killed one" ARGS run "${WORK_DIR}/short.yaml" --out "${run}"
        --no-plots --no-viewer --force)
file(GLOB staging LIST_DIRECTORIES true "${WORK_DIR}/.run.partial-*")
if(staging)
  message(FATAL_ERROR "a killed run's staging folder was not removed: ${staging}")
endif()

# 5. Results first: plots that cannot run (CORRIDORSIM_PYTHON names no program) exit 4 with the
#    results written; a failed expectation (3) takes precedence.
set(no_python "${WORK_DIR}/no_python")
cli_run(EXIT 4 WHAT "plots without python3" ENV CORRIDORSIM_PYTHON=/nonexistent/python3
        STDERR "corridorsim: error: plots/: /nonexistent/python3 .*could not be started"
        ARGS run "${WORK_DIR}/short.yaml" --out "${no_python}")
cli_expect_files("${no_python}" metrics.json timing.json events.json scenario.yaml
                 ground_truth.tum odometry.tum)
file(WRITE "${WORK_DIR}/failing.yaml"
     "include: ${WORK_DIR}/short.yaml\nexpectations:\n  - odometry.ate_rmse_m < 0.000000001\n")
cli_run(EXIT 3 WHAT "failed expectation and failed plots" ENV CORRIDORSIM_PYTHON=/nonexistent/python3
        ARGS run "${WORK_DIR}/failing.yaml" --out "${WORK_DIR}/failing")
cli_expect_files("${WORK_DIR}/failing" metrics.json)

# 6. The other jobs and --export: refused without --force, replaced whole with it.
set(world "${WORK_DIR}/world")
cli_run(EXIT 0 WHAT "world" ARGS world "${WORK_DIR}/short.yaml" --out "${world}")
file(WRITE "${world}/extra.txt" "x")
cli_run(EXIT 2 WHAT "world rerun" STDERR "--out: .*pass --force"
        ARGS world "${WORK_DIR}/short.yaml" --out "${world}")
cli_run(EXIT 0 WHAT "world --force" ARGS world "${WORK_DIR}/short.yaml" --out "${world}" --force)
if(EXISTS "${world}/extra.txt")
  message(FATAL_ERROR "world --force left a file of the previous folder")
endif()
cli_expect_files("${world}" world.obj ground_truth.json map.png)
cli_run(EXIT 2 WHAT "drive into a full folder" STDERR "--out: .*pass --force"
        ARGS drive "${WORK_DIR}/short.yaml" --out "${world}")
cli_run(EXIT 2 WHAT "snapshot into a full folder" STDERR "--out: .*pass --force"
        ARGS snapshot "${WORK_DIR}/short.yaml" --pose 1,0,0 --out "${world}")
cli_run(EXIT 2 WHAT "--export into a full folder" STDERR "--export: .*pass --force"
        NOT_EXISTS "${WORK_DIR}/new_run" ARGS run "${WORK_DIR}/short.yaml"
        --out "${WORK_DIR}/new_run" --export "${world}")
cli_run(EXIT 2 WHAT "--export inside --out" STDERR "--export: .*separate folders"
        ARGS run "${WORK_DIR}/short.yaml" --out "${run}" --export "${run}/dataset" --force)
cli_run(EXIT 2 WHAT "--out inside --export" STDERR "--export: .*separate folders"
        ARGS run "${WORK_DIR}/short.yaml" --out "${WORK_DIR}/d/run" --export "${WORK_DIR}/d")
# 7. --force replaces only a folder a corridorsim job wrote: a user's folder is never deleted.
set(mine "${WORK_DIR}/mine")
file(WRITE "${mine}/notes.txt" "keep me")
cli_run(EXIT 2 WHAT "--force over a user's folder" STDERR "--out: .*no corridorsim job wrote"
        ARGS world "${WORK_DIR}/short.yaml" --out "${mine}" --force)
file(READ "${mine}/notes.txt" kept)
if(NOT kept STREQUAL "keep me")
  message(FATAL_ERROR "--force touched a folder no corridorsim job wrote")
endif()
cli_run(EXIT 2 WHAT "--out the current folder" STDERR "--out: .*current folder"
        ARGS world "${WORK_DIR}/short.yaml" --out . --force)
