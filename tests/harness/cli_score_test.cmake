# `corridorsim score` as a user runs it, on a hand-written dataset (no rendering): the report
# files, the table, --expect's exit codes 0 and 3, and exit code 2 naming the file and field for
# bad input.
include("${CMAKE_CURRENT_LIST_DIR}/cli_support.cmake")

set(ds "${WORK_DIR}/ds")
file(WRITE "${ds}/dataset.json" "{\"format\": \"corridorsim dataset\", \"cameras\": [\"upward\"]}\n")
# Two lamps in image 1, one plate in image 2.
file(WRITE "${ds}/upward/annotations.json" [=[
{"images": [{"id": 1, "file_name": "images/w000_f0000.png", "width": 64, "height": 48},
            {"id": 2, "file_name": "images/w000_f0001.png", "width": 64, "height": 48}],
 "annotations": [
  {"id": 1, "image_id": 1, "category_id": 3, "bbox": [10, 10, 10, 10], "circle": [15, 15, 5],
   "distance_m": 1.5, "viewing_angle_deg": 5},
  {"id": 2, "image_id": 1, "category_id": 3, "bbox": [40, 10, 10, 10], "circle": [45, 15, 5],
   "distance_m": 5, "viewing_angle_deg": 50},
  {"id": 3, "image_id": 2, "category_id": 1, "bbox": [5, 5, 20, 10], "room_number": "101",
   "distance_m": 3, "viewing_angle_deg": 20}],
 "categories": []}
]=])
# One lamp found (a circle), one false lamp, the plate found and read.
file(WRITE "${WORK_DIR}/d.json" [=[
[{"image_id": 1, "category_id": 3, "circle": [15, 15, 5], "score": 0.9},
 {"image_id": 1, "category_id": 3, "bbox": [30, 30, 4, 4], "score": 0.4},
 {"image_id": 2, "category_id": 1, "bbox": [5, 5, 20, 10], "score": 0.8, "room_number": "101"}]
]=])

cli_run(EXIT 0 WHAT "score" ARGS score "${WORK_DIR}/d.json" --dataset "${ds}" --out "${WORK_DIR}/r"
        --expect lamp.recall>=0.5 --expect door_plate.reading_accuracy>=1
        STDOUT "lamp +2 +2 +1\\.000 +0\\.500 +0\\.505 +0\\.505")
cli_expect_files("${WORK_DIR}/r" score.json score.png)
file(READ "${WORK_DIR}/r/score.json" report)
string(JSON ap50 GET "${report}" classes lamp ap50)
string(JSON plate_ap GET "${report}" classes door_plate ap)
string(JSON passed GET "${report}" expectations 1 passed)
# AP50 of the lamps: recall 0.5 at precision 1, nothing beyond: 51 of 101 recall points.
if(NOT ap50 MATCHES "^0\\.50495" OR NOT plate_ap EQUAL 1 OR NOT passed STREQUAL "ON")
  message(FATAL_ERROR "score.json: lamp ap50 ${ap50}, plate ap ${plate_ap}, passed ${passed}")
endif()

# A failed expectation: exit 3, named; the report is still written.
cli_run(EXIT 3 WHAT "failed expectation" ARGS score "${WORK_DIR}/d.json" --dataset "${ds}"
        --out "${WORK_DIR}/r3" --expect lamp.ap50>=0.8 --expect lamp.recall>=0.5
        STDERR "expectation failed: lamp.ap50>=0.8" STDOUT "lamp.ap50>=0.8 +0.505  FAILED")
cli_expect_files("${WORK_DIR}/r3" score.json score.png)
# Undefined values fail: there are no doors.
cli_run(EXIT 3 WHAT "undefined metric" ARGS score "${WORK_DIR}/d.json" --dataset "${ds}"
        --expect door.ap50>=0 STDERR "expectation failed: door.ap50>=0")
# The report folder follows the output-folder rules.
cli_run(EXIT 2 WHAT "report folder with files" ARGS score "${WORK_DIR}/d.json" --dataset "${ds}"
        --out "${WORK_DIR}/r" STDERR "--force")
cli_run(EXIT 0 WHAT "report folder with --force" ARGS score "${WORK_DIR}/d.json" --dataset "${ds}"
        --out "${WORK_DIR}/r" --force)

# Bad input: exit 2, one message naming the file and field, no report.
function(expect_bad name detections pattern)
  file(WRITE "${WORK_DIR}/${name}.json" "${detections}")
  cli_run(EXIT 2 WHAT "${name}" STDERR "${pattern}" NOT_EXISTS "${WORK_DIR}/bad"
          ARGS score "${WORK_DIR}/${name}.json" --dataset "${ds}" --out "${WORK_DIR}/bad")
endfunction()
expect_bad(malformed "[{\"image_id\": 1," "malformed.json: malformed JSON at byte 17: ")
expect_bad(not_object "[1]" "not_object.json: \\[0\\]: expected an object")
expect_bad(no_image "[{\"image_id\": 9, \"category_id\": 3, \"bbox\": [1,1,2,2], \"score\": 1}]"
           "no_image.json: \\[0\\].image_id: no image of the dataset's upward camera has id 9")
expect_bad(category "[{\"image_id\": 1, \"category_id\": 0, \"bbox\": [1,1,2,2], \"score\": 1}]"
           "category.json: \\[0\\].category_id: unknown category 0")
expect_bad(outside "[{\"image_id\": 1, \"category_id\": 3, \"bbox\": [70,1,2,2], \"score\": 1}]"
           "outside.json: \\[0\\].bbox: the box lies outside the image")
cli_run(EXIT 2 WHAT "missing detections" STDERR "missing.json: cannot be opened"
        ARGS score "${WORK_DIR}/missing.json" --dataset "${ds}")
cli_run(EXIT 2 WHAT "missing dataset" STDERR "nowhere/dataset.json: cannot be opened"
        ARGS score "${WORK_DIR}/d.json" --dataset "${WORK_DIR}/nowhere")
cli_run(EXIT 2 WHAT "unknown camera" STDERR "command line: --camera: 'front' is not a camera of the dataset"
        ARGS score "${WORK_DIR}/d.json" --dataset "${ds}" --camera front)
cli_run(EXIT 2 WHAT "bad expectation" STDERR "command line: --expect: unknown class 'lamps'"
        ARGS score "${WORK_DIR}/d.json" --dataset "${ds}" --expect lamps.ap50>=1)

# Hostile sizes are bounded before parsing (50 MB of `[` needed more than 3.5 GB and died of
# std::bad_alloc, exit 1): nesting at its line and column, in every JSON file score reads.
string(REPEAT "[" 1000000 deep)
file(WRITE "${WORK_DIR}/deep.json" "${deep}")
cli_run(EXIT 2 WHAT "deep detections" NOT_EXISTS "${WORK_DIR}/bad"
        STDERR "deep.json:1:65: more than 64 nested arrays and objects\n$"
        ARGS score "${WORK_DIR}/deep.json" --dataset "${ds}" --out "${WORK_DIR}/bad")
# expect_bad_dataset_file(<what> <file of the dataset> <text> <stderr regex>): with <text> in the
# file, score exits 2 with the message; the file is restored after.
function(expect_bad_dataset_file what file text pattern)
  file(COPY_FILE "${ds}/${file}" "${WORK_DIR}/saved")
  file(WRITE "${ds}/${file}" "${text}")
  cli_run(EXIT 2 WHAT "${what}" STDERR "${pattern}"
          ARGS score "${WORK_DIR}/d.json" --dataset "${ds}")
  file(COPY_FILE "${WORK_DIR}/saved" "${ds}/${file}")
endfunction()
expect_bad_dataset_file("deep annotations" upward/annotations.json "{\"images\": ${deep}"
                        "upward/annotations.json:1:75: more than 64 nested")
expect_bad_dataset_file("deep manifest" dataset.json "${deep}"
                        "ds/dataset.json:1:65: more than 64 nested")
# An image's width must fit: an int64 was cut to an int before.
expect_bad_dataset_file("huge width" upward/annotations.json
  "{\"images\": [{\"id\": 1, \"width\": 4294967360, \"height\": 48}], \"annotations\": []}"
  "annotations.json: images\\[0\\]\\.width: outside \\[1, 65536\\] px")
# A camera of dataset.json names a folder of the dataset, never a path out of it.
expect_bad_dataset_file("camera path" dataset.json
  "{\"format\": \"corridorsim dataset\", \"cameras\": [\"../ds/upward\"]}\n"
  "ds/dataset.json: \\.?cameras\\[0\\]: expected a camera name")
# A detections FIFO is refused without blocking.
execute_process(COMMAND mkfifo "${WORK_DIR}/fifo.json" RESULT_VARIABLE fifo_rc)
if(NOT fifo_rc EQUAL 0)
  message(FATAL_ERROR "mkfifo failed")
endif()
cli_run(EXIT 2 WHAT "FIFO detections" STDERR "fifo.json: not a regular file"
        ARGS score "${WORK_DIR}/fifo.json" --dataset "${ds}")
