# README's "Develop a detector", run as written on a tiny dataset (1 world, 2 frames):
# `corridorsim dataset`, examples/detect_lamps.py, `corridorsim score`; score.json must parse and
# the example detector must reach a lamp AP50 above 0.5. CTest passes PYTHON (one that imports cv2).
include("${CMAKE_CURRENT_LIST_DIR}/cli_support.cmake")

cli_run(EXIT 0 WHAT "dataset" ARGS dataset scenarios/p3_lamps.yaml --worlds 1 --frames-per-world 2
        --cameras upward --out "${WORK_DIR}/lamps")
execute_process(COMMAND "${PYTHON}" examples/detect_lamps.py "${WORK_DIR}/lamps"
                WORKING_DIRECTORY "${SOURCE_DIR}" RESULT_VARIABLE rc
                OUTPUT_FILE "${WORK_DIR}/lamps_detections.json" ERROR_VARIABLE stderr)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "detect_lamps.py: exit ${rc}\n${stderr}")
endif()
cli_run(EXIT 0 WHAT "score" ARGS score "${WORK_DIR}/lamps_detections.json"
        --dataset "${WORK_DIR}/lamps" --out "${WORK_DIR}/lamps_score" STDOUT "lamp ")
file(READ "${WORK_DIR}/lamps_score/score.json" report)
string(JSON ap50 ERROR_VARIABLE error GET "${report}" classes lamp ap50)
if(error)
  message(FATAL_ERROR "score.json: ${error}")
endif()
# CMake compares numbers as doubles here (LESS_EQUAL on decimal strings).
if(ap50 LESS_EQUAL 0.5)
  message(FATAL_ERROR "the example detector's lamp AP50 is ${ap50}, expected above 0.5")
endif()
# The same check through --expect: exit 0 when it holds.
cli_run(EXIT 0 WHAT "score --expect" ARGS score "${WORK_DIR}/lamps_detections.json"
        --dataset "${WORK_DIR}/lamps" --expect lamp.ap50>0.5)
