# Fails if a layer includes a header from a layer above it (docs/architecture.md):
# common <- common/io <- worlds <- render <- sim, slam on common only (not common/io), harness on
# top, and inside it its rooms.
# common/ (the robot-facing types) never includes its I/O part common/io/.
set(forbidden_common "common/io|worlds|render|sim|slam|harness|scenarios")
set(forbidden_common/io "worlds|render|sim|slam|harness|scenarios")
set(forbidden_worlds "render|sim|slam|harness|scenarios")
set(forbidden_render "sim|slam|harness|scenarios")
set(forbidden_sim "slam|harness|scenarios")
set(forbidden_slam "common/io|worlds|render|sim|harness|scenarios")
# The harness's rooms (docs/architecture.md): metrics <- scenario <- run <- study, workbench;
# the command line (cli/) on top of them all.
set(forbidden_harness/metrics "harness/scenario|harness/run|harness/study|harness/workbench|harness/cli")
set(forbidden_harness/scenario "harness/run|harness/study|harness/workbench|harness/cli")
set(forbidden_harness/run "harness/study|harness/workbench|harness/cli")
set(forbidden_harness/study "harness/workbench|harness/cli")
set(forbidden_harness/workbench "harness/study|harness/cli")
set(failures "")
foreach(layer common common/io worlds render sim slam harness/metrics harness/scenario harness/run
              harness/study harness/workbench)
  if(NOT IS_DIRECTORY "${SOURCE_DIR}/${layer}")
    continue()
  endif()
  if(layer STREQUAL "common")
    file(GLOB files "${SOURCE_DIR}/common/*.h" "${SOURCE_DIR}/common/*.cpp")
  else()
    file(GLOB_RECURSE files "${SOURCE_DIR}/${layer}/*.h" "${SOURCE_DIR}/${layer}/*.cpp")
  endif()
  foreach(f ${files})
    file(STRINGS "${f}" lines REGEX "^[ \t]*#[ \t]*include[ \t]*[<\"](corridorsim/)?(${forbidden_${layer}})/")
    foreach(line ${lines})
      string(APPEND failures "\n  ${f}: ${line}")
    endforeach()
  endforeach()
endforeach()
# scenarios/ is data: the scenario library, no code.
file(GLOB_RECURSE code "${SOURCE_DIR}/scenarios/*.h" "${SOURCE_DIR}/scenarios/*.cpp")
foreach(f ${code})
  string(APPEND failures "\n  ${f}: code in scenarios/ (it holds scenario data only)")
endforeach()
if(failures)
  message(FATAL_ERROR "upward includes across layers:${failures}")
endif()
message(STATUS "layering ok")
