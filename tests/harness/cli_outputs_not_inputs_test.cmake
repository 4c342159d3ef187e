# No job's output may be, contain or lie inside one of its inputs (harness/run/job_inputs.h):
# every job that writes refuses such an output with exit 2 and one message naming its flag,
# before anything is written, and the input is left as it was. Links are followed: a link to the
# scenario's folder is that folder. (`evaluate` is checked in cli_evaluate_test.py.)
include("${CMAKE_CURRENT_LIST_DIR}/cli_support.cmake")

file(REMOVE_RECURSE "${WORK_DIR}")
set(in "${WORK_DIR}/in")
set(base "${WORK_DIR}/base")
file(WRITE "${base}/base.yaml"
     "include: ${SOURCE_DIR}/tests/data/scenarios/odometry_consistency.yaml\n")
file(WRITE "${in}/s.yaml" "include: ${base}/base.yaml\nduration_s: 1\n")
file(CREATE_LINK "${in}" "${WORK_DIR}/link_to_in" SYMBOLIC)
file(GLOB_RECURSE before RELATIVE "${WORK_DIR}" "${in}/*" "${base}/*")

# `run`, `world`, `snapshot`, `drive`, `dataset`, `study`, `test`: the scenario file, its include
# chain's files and the folders holding them.
foreach(job run world snapshot drive dataset study test)
  set(extra --force)  # refused all the same: --force never replaces an input
  if(job STREQUAL "run")
    set(extra --force --no-plots --no-viewer)
  elseif(job STREQUAL "snapshot")
    set(extra --force --pose 2,0,0)
  elseif(job STREQUAL "test")
    set(extra "")  # test has no --force
  endif()
  cli_run(EXIT 2 WHAT "${job} --out the scenario's folder" ARGS ${job} "${in}/s.yaml" --out "${in}"
          ${extra}
          STDERR "command line: --out: '[^']*/in' contains '[^']*/in/s.yaml', a scenario file")
  cli_run(EXIT 2 WHAT "${job} --out the include chain's folder" ARGS ${job} "${in}/s.yaml"
          --out "${base}" ${extra}
          STDERR "command line: --out: '[^']*/base' contains '[^']*/base/base.yaml', a scenario")
  cli_run(EXIT 2 WHAT "${job} --out a link to the scenario's folder" ARGS ${job} "${in}/s.yaml"
          --out "${WORK_DIR}/link_to_in" ${extra}
          STDERR "command line: --out: '[^']*/link_to_in' contains ")
  cli_run(EXIT 2 WHAT "${job} --out the scenario file" ARGS ${job} "${in}/s.yaml"
          --out "${in}/s.yaml" ${extra} STDERR "command line: --out: '[^']*/s.yaml' is ")
  cli_run(EXIT 2 WHAT "${job} --out inside the scenario file" ARGS ${job} "${in}/s.yaml"
          --out "${in}/s.yaml/x" ${extra} STDERR "command line: --out: .* lies inside ")
endforeach()
cli_run(EXIT 2 WHAT "run --export the scenario's folder" ARGS run "${in}/s.yaml"
        --out "${WORK_DIR}/o" --export "${in}" --force --no-plots --no-viewer
        STDERR "command line: --export: '[^']*/in' contains ")
cli_run(EXIT 2 WHAT "test --junit the scenario file" ARGS test "${in}/s.yaml"
        --out "${WORK_DIR}/t" --junit "${in}/s.yaml" STDERR "command line: --junit: .* is ")
cli_run(EXIT 2 WHAT "test --junit the include chain's file" ARGS test "${in}/s.yaml"
        --out "${WORK_DIR}/t" --junit "${base}/base.yaml"
        STDERR "command line: --junit: .* is ")

# `score`: the detections file and the dataset folder.
set(ds "${WORK_DIR}/ds")
file(WRITE "${ds}/dataset.json" "{\"format\": \"corridorsim dataset\", \"cameras\": [\"upward\"]}\n")
file(WRITE "${ds}/upward/annotations.json" [=[
{"images": [{"id": 1, "file_name": "images/w000_f0000.png", "width": 64, "height": 48}],
 "annotations": [{"id": 1, "image_id": 1, "category_id": 3, "bbox": [10, 10, 10, 10],
                  "circle": [15, 15, 5], "distance_m": 1.5, "viewing_angle_deg": 5}],
 "categories": []}
]=])
file(WRITE "${ds}/d.json" "[{\"image_id\": 1, \"category_id\": 3, \"circle\": [15, 15, 5], \"score\": 0.9}]\n")
cli_run(EXIT 2 WHAT "score --out inside the dataset" ARGS score "${ds}/d.json" --dataset "${ds}"
        --out "${ds}/report" STDERR "command line: --out: .* lies inside '[^']*/ds'")
cli_run(EXIT 2 WHAT "score --out the dataset" ARGS score "${ds}/d.json" --dataset "${ds}"
        --out "${ds}" --force STDERR "command line: --out: '[^']*/ds' contains '[^']*/d.json', the detections file")
cli_run(EXIT 0 WHAT "score beside the dataset" ARGS score "${ds}/d.json" --dataset "${ds}"
        --out "${WORK_DIR}/report")

# `study merge`: the folders merged (a study of one 1 s run, merged into itself and below it).
set(study "${WORK_DIR}/study")
cli_run(EXIT 0 WHAT "study" ARGS study "${in}/s.yaml" --runs 1 --jobs 1 --out "${study}"
        --no-plots)
cli_run(EXIT 2 WHAT "study merge into itself" ARGS study merge "${study}" --out "${study}"
        STDERR "command line: --out: '[^']*/study' is '[^']*/study', a folder to merge")
cli_run(EXIT 2 WHAT "study merge inside the folder merged" ARGS study merge "${study}"
        --out "${study}/merged" STDERR "command line: --out: .* lies inside ")
cli_run(EXIT 0 WHAT "study merge beside it" ARGS study merge "${study}" --out "${WORK_DIR}/merged"
        --no-plots)

# Nothing of the inputs changed.
file(GLOB_RECURSE after RELATIVE "${WORK_DIR}" "${in}/*" "${base}/*")
if(NOT before STREQUAL after)
  message(FATAL_ERROR "a refused output changed the inputs:\n${before}\n${after}")
endif()
