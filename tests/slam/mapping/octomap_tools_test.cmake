# A .bt file the mapper wrote (slam_mapping_tests "[.write_bt]") read by octomap-tools'
# bt2vrml, which parses the whole octree and writes its occupied voxels as VRML boxes.
# Passed: TESTS (the test binary), BT2VRML, WORK_DIR.
file(REMOVE_RECURSE "${WORK_DIR}")
file(MAKE_DIRECTORY "${WORK_DIR}")
set(bt "${WORK_DIR}/wall.bt")
execute_process(COMMAND ${CMAKE_COMMAND} -E env CORRIDORSIM_BT_OUT=${bt} ${TESTS} "[.write_bt]"
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0 OR NOT EXISTS "${bt}")
  message(FATAL_ERROR "writing ${bt} failed (${rc}):\n${out}\n${err}")
endif()
execute_process(COMMAND ${BT2VRML} "${bt}" WORKING_DIRECTORY "${WORK_DIR}"
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0 OR NOT EXISTS "${bt}.wrl" OR err MATCHES "ERROR|rror")
  message(FATAL_ERROR "bt2vrml could not read ${bt} (${rc}):\n${out}\n${err}")
endif()
file(READ "${bt}.wrl" vrml)
string(REGEX MATCHALL "Box" boxes "${vrml}")
list(LENGTH boxes n)
# The wall seen by an 80 x 60 camera at 3 m: more than a hundred 0.1 m voxels.
if(n LESS 100)
  message(FATAL_ERROR "bt2vrml found ${n} occupied voxels in ${bt}, expected at least 100")
endif()
# Every one of them on the wall's voxel layer [3.0, 3.1).
string(REGEX MATCHALL "translation 3\\.05 " on_wall "${vrml}")
list(LENGTH on_wall m)
if(NOT m EQUAL n)
  message(FATAL_ERROR "${m} of the ${n} occupied voxels lie on the wall (x = 3.05)")
endif()
message(STATUS "bt2vrml read ${bt}: ${n} occupied voxels")
