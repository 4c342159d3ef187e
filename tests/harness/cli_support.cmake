# Steps the CLI tests (tests/harness/cli_*_test.cmake) share. CTest passes CORRIDORSIM,
# SOURCE_DIR and WORK_DIR (tests/CMakeLists.txt); each script includes this file first, which
# leaves it an empty WORK_DIR.
file(REMOVE_RECURSE "${WORK_DIR}")
file(MAKE_DIRECTORY "${WORK_DIR}")

# cli_run(EXIT <code> WHAT <name> ARGS <corridorsim arguments...> [ENV <VAR=value>]
#         [STDOUT <regex>] [STDERR <regex>] [NOT_STDOUT <regex>] [NOT_EXISTS <path>])
# Runs corridorsim in SOURCE_DIR; fails unless it exits <code>, its output matches, and
# NOT_EXISTS (e.g. an output folder bad input must not create) is absent. CLI_STDOUT gets stdout,
# CLI_STDERR stderr.
function(cli_run)
  cmake_parse_arguments(ARG "" "EXIT;WHAT;ENV;STDOUT;STDERR;NOT_STDOUT;NOT_EXISTS" "ARGS" ${ARGN})
  set(command "${CORRIDORSIM}" ${ARG_ARGS})
  if(ARG_ENV)
    set(command ${CMAKE_COMMAND} -E env ${ARG_ENV} ${command})
  endif()
  execute_process(COMMAND ${command} WORKING_DIRECTORY "${SOURCE_DIR}" RESULT_VARIABLE rc
                  OUTPUT_VARIABLE stdout ERROR_VARIABLE stderr)
  if(NOT rc EQUAL ARG_EXIT)
    message(FATAL_ERROR "${ARG_WHAT}: exit ${rc}, expected ${ARG_EXIT}\n${stderr}")
  endif()
  if(DEFINED ARG_STDOUT AND NOT stdout MATCHES "${ARG_STDOUT}")
    message(FATAL_ERROR "${ARG_WHAT}: output does not match '${ARG_STDOUT}':\n${stdout}")
  endif()
  if(DEFINED ARG_STDERR AND NOT stderr MATCHES "${ARG_STDERR}")
    message(FATAL_ERROR "${ARG_WHAT}: message does not match '${ARG_STDERR}':\n${stderr}")
  endif()
  if(DEFINED ARG_NOT_STDOUT AND stdout MATCHES "${ARG_NOT_STDOUT}")
    message(FATAL_ERROR "${ARG_WHAT}: output matches '${ARG_NOT_STDOUT}':\n${stdout}")
  endif()
  if(DEFINED ARG_NOT_EXISTS AND EXISTS "${ARG_NOT_EXISTS}")
    message(FATAL_ERROR "${ARG_WHAT}: ${ARG_NOT_EXISTS} was created")
  endif()
  set(CLI_STDOUT "${stdout}" PARENT_SCOPE)
  set(CLI_STDERR "${stderr}" PARENT_SCOPE)
endfunction()

# cli_expect_bad(<name> <yaml text> <stderr regex> <subcommand> [arguments...]): WORK_DIR/<name>.yaml
# holds the text; `corridorsim <subcommand> <that file> [arguments]` must exit 2 with one message
# matching the regex (file:line:column: key: ...).
function(cli_expect_bad name yaml pattern subcommand)
  file(WRITE "${WORK_DIR}/${name}.yaml" "${yaml}")
  cli_run(EXIT 2 WHAT "${name}" STDERR "${pattern}"
          ARGS ${subcommand} "${WORK_DIR}/${name}.yaml" ${ARGN})
endfunction()

# cli_expect_bad_run(<name> <yaml text> <stderr regex>): cli_expect_bad of `run`, whose
# --out WORK_DIR/out_<name> bad input must not create.
function(cli_expect_bad_run name yaml pattern)
  cli_expect_bad(${name} "${yaml}" "${pattern}" run --out "${WORK_DIR}/out_${name}")
  if(EXISTS "${WORK_DIR}/out_${name}")
    message(FATAL_ERROR "${name}: bad input still created the run folder")
  endif()
endfunction()

# cli_expect_files(<dir> <relative paths...>): each exists.
function(cli_expect_files dir)
  foreach(f ${ARGN})
    if(NOT EXISTS "${dir}/${f}")
      message(FATAL_ERROR "missing output ${dir}/${f}")
    endif()
  endforeach()
endfunction()

# cli_expect_same_files(<dir a> <dir b> [relative paths...]): the files (default: every file
# under <dir a>) exist in both with the same bytes.
function(cli_expect_same_files a b)
  set(files ${ARGN})
  if(NOT files)
    file(GLOB_RECURSE files RELATIVE "${a}" "${a}/*")
  endif()
  cli_expect_files("${a}" ${files})
  foreach(f ${files})
    file(SHA256 "${a}/${f}" ha)
    file(SHA256 "${b}/${f}" hb)
    if(NOT ha STREQUAL hb)
      message(FATAL_ERROR "${f} differs between ${a} and ${b} (same scenario and seed)")
    endif()
  endforeach()
endfunction()

# Writes `path`: the default scenario in a short corridor (`length` m with `doors` doors and
# `plates` plates, one poster and one fire extinguisher), then `extra` (more top-level YAML).
function(cli_write_short_scenario path length doors plates extra)
  file(WRITE "${path}" "include: ${SOURCE_DIR}/scenarios/default.yaml
world:
  length_m: ${length}
  doors: {count: ${doors}}
  plates: {count: ${plates}}
  distractors: {posters: 1, notice_boards: 0, bookshelves: 0, cabinets: 0, fire_extinguishers: 1}
${extra}")
endfunction()
