# Appearance randomisation through `corridorsim dataset` and `score`: each world's ground truth
# records what it drew, every image carries those values, two worlds draw differently, the same
# command gives the same bytes, and `score` bins recall by the values.
include("${CMAKE_CURRENT_LIST_DIR}/cli_support.cmake")

set(scenario "${SOURCE_DIR}/tests/data/scenarios/dataset_appearance.yaml")
set(args dataset "${scenario}" --worlds 2 --frames-per-world 2 --cameras upward)
cli_run(EXIT 0 WHAT "dataset" ARGS ${args} --out "${WORK_DIR}/a")
cli_run(EXIT 0 WHAT "dataset again" ARGS ${args} --out "${WORK_DIR}/b")
set(a "${WORK_DIR}/a")

foreach(w 000 001)
  file(READ "${a}/worlds/w${w}/ground_truth.json" truth)
  string(JSON blur_${w} GET "${truth}" appearance camera_blur_px)
  string(JSON kelvin_${w} GET "${truth}" appearance lamp_temperature_k)
  if(kelvin_${w} LESS 2700 OR kelvin_${w} GREATER 6500)
    message(FATAL_ERROR "world ${w}: lamp temperature ${kelvin_${w}} K outside [2700, 6500]")
  endif()
endforeach()
if(blur_000 STREQUAL blur_001)
  message(FATAL_ERROR "both worlds drew the same blur (${blur_000} px)")
endif()

file(READ "${a}/upward/annotations.json" coco)
string(JSON n_images LENGTH "${coco}" images)
math(EXPR last "${n_images} - 1")
foreach(i RANGE ${last})
  string(JSON world GET "${coco}" images ${i} world_index)
  string(JSON blur GET "${coco}" images ${i} appearance camera_blur_px)
  if(world EQUAL 0)
    set(expected "${blur_000}")
  else()
    set(expected "${blur_001}")
  endif()
  if(NOT blur STREQUAL expected)
    message(FATAL_ERROR "image ${i} (world ${world}) carries blur ${blur}, its world drew ${expected}")
  endif()
endforeach()

# Byte for byte the same dataset.
cli_expect_same_files("${a}" "${WORK_DIR}/b")

# `score` bins recall by every appearance key (an empty detection list: recall 0 everywhere).
file(WRITE "${WORK_DIR}/none.json" "[]")
cli_run(EXIT 0 WHAT "score" ARGS score "${WORK_DIR}/none.json" --dataset "${a}"
        --out "${WORK_DIR}/score")
file(READ "${WORK_DIR}/score/score.json" score)
foreach(key camera_blur_px lamp_temperature_k wall_brightness)
  string(JSON bins ERROR_VARIABLE missing LENGTH "${score}" classes lamp recall_by_appearance ${key})
  if(missing OR bins LESS 1)
    message(FATAL_ERROR "score.json has no recall of lamps binned by ${key}: ${missing}")
  endif()
endforeach()
