# `corridorsim dataset` as a user runs it: the layout of docs/datasets.md, valid COCO files,
# byte-identical reruns, resuming a folder with missing frames, refusing another dataset's folder,
# and exit code 2 naming the option for bad input.
include("${CMAKE_CURRENT_LIST_DIR}/cli_support.cmake")

set(scenario "${SOURCE_DIR}/tests/data/scenarios/dataset_small.yaml")
set(args dataset "${scenario}" --worlds 2 --frames-per-world 2)

cli_run(EXIT 0 WHAT "dataset" ARGS ${args} --out "${WORK_DIR}/a"
        STDERR "dataset: world 2/2 frame 2/2")
set(a "${WORK_DIR}/a")
cli_expect_files("${a}" dataset.json worlds/w000/ground_truth.json worlds/w001/ground_truth.json)
foreach(camera front lateral upward)
  cli_expect_files("${a}" ${camera}/annotations.json ${camera}/intrinsics.json)
  foreach(stem w000_f0000 w000_f0001 w001_f0000 w001_f0001)
    cli_expect_files("${a}" ${camera}/images/${stem}.png ${camera}/labels/${stem}.png
                     ${camera}/truth/${stem}.json)
  endforeach()
endforeach()
cli_expect_files("${a}" front/depth/w001_f0001.png)
if(EXISTS "${a}/upward/depth")
  message(FATAL_ERROR "the upward camera has no depth, yet upward/depth/ was written")
endif()

# COCO: every annotation's image exists and its box lies inside that image; the categories are the
# fixed table.
foreach(camera front lateral upward)
  file(READ "${a}/${camera}/annotations.json" coco)
  string(JSON n_images LENGTH "${coco}" images)
  if(NOT n_images EQUAL 4)
    message(FATAL_ERROR "${camera}: ${n_images} images, expected 4")
  endif()
  math(EXPR last_image "${n_images} - 1")
  foreach(i RANGE ${last_image})
    string(JSON id GET "${coco}" images ${i} id)
    string(JSON width GET "${coco}" images ${i} width)
    string(JSON height GET "${coco}" images ${i} height)
    string(JSON file_name GET "${coco}" images ${i} file_name)
    cli_expect_files("${a}/${camera}" "${file_name}")
    set(size_${id} "${width};${height}")
  endforeach()
  foreach(k RANGE 3)
    math(EXPR id "${k} + 1")
    string(JSON category_id GET "${coco}" categories ${k} id)
    string(JSON name GET "${coco}" categories ${k} name)
    set(names door_plate door lamp ceiling_corner)
    list(GET names ${k} expected)
    if(NOT category_id EQUAL id OR NOT name STREQUAL expected)
      message(FATAL_ERROR "${camera}: category ${k} is ${category_id} ${name}")
    endif()
  endforeach()
  string(JSON n_annotations LENGTH "${coco}" annotations)
  if(n_annotations EQUAL 0)
    message(FATAL_ERROR "${camera}: no annotations")
  endif()
  math(EXPR last "${n_annotations} - 1")
  foreach(i RANGE ${last})
    string(JSON annotation GET "${coco}" annotations ${i})
    string(JSON image_id GET "${annotation}" image_id)
    string(JSON category_id GET "${annotation}" category_id)
    if(NOT DEFINED size_${image_id})
      message(FATAL_ERROR "${camera}: annotation ${i} refers to image ${image_id}, not in images")
    endif()
    if(category_id LESS 1 OR category_id GREATER 4)
      message(FATAL_ERROR "${camera}: annotation ${i} has category ${category_id}")
    endif()
    list(GET size_${image_id} 0 width)
    list(GET size_${image_id} 1 height)
    foreach(k 0 1 2 3)
      string(JSON b${k} GET "${annotation}" bbox ${k})
    endforeach()
    # CMake's math is integer: compare in 1e-4 px steps (values truncated to them).
    foreach(v b0 b1 b2 b3)
      string(REGEX REPLACE "^([0-9]+)$" "\\1.0" ${v} "${${v}}")
      string(REGEX MATCH "^([0-9]+)\\.([0-9]*)$" ok "${${v}}")
      if(NOT ok)
        message(FATAL_ERROR "${camera}: annotation ${i}: bbox value ${${v}} is not >= 0")
      endif()
      string(SUBSTRING "${CMAKE_MATCH_2}0000" 0 4 frac)
      math(EXPR ${v}_q "${CMAKE_MATCH_1} * 10000 + 1${frac} - 10000")
    endforeach()
    math(EXPR right "${b0_q} + ${b2_q}")
    math(EXPR bottom "${b1_q} + ${b3_q}")
    math(EXPR width_q "${width} * 10000")
    math(EXPR height_q "${height} * 10000")
    if(right GREATER width_q OR bottom GREATER height_q OR b2_q EQUAL 0 OR b3_q EQUAL 0)
      message(FATAL_ERROR "${camera}: annotation ${i}: bbox ${b0} ${b1} ${b2} ${b3} is not inside "
                          "the ${width}x${height} image")
    endif()
  endforeach()
endforeach()

# The same arguments give the same bytes.
cli_run(EXIT 0 WHAT "dataset again" ARGS ${args} --out "${WORK_DIR}/b")
cli_expect_same_files("${a}" "${WORK_DIR}/b")
file(GLOB_RECURSE files_b RELATIVE "${WORK_DIR}/b" "${WORK_DIR}/b/*")
cli_expect_same_files("${WORK_DIR}/b" "${a}" ${files_b})

# Resume: a folder that lost some frames (truth and image) and its COCO files is completed to the
# same bytes, re-rendering only the lost frames.
file(REMOVE "${WORK_DIR}/b/upward/truth/w001_f0001.json" "${WORK_DIR}/b/upward/images/w001_f0001.png"
     "${WORK_DIR}/b/front/truth/w000_f0000.json" "${WORK_DIR}/b/front/images/w000_f0000.png"
     "${WORK_DIR}/b/front/annotations.json" "${WORK_DIR}/b/upward/annotations.json")
cli_run(EXIT 0 WHAT "resume" ARGS ${args} --out "${WORK_DIR}/b" STDOUT "rendered 2 frames")
cli_expect_same_files("${a}" "${WORK_DIR}/b")
# A complete folder renders nothing.
cli_run(EXIT 0 WHAT "rerun of a complete dataset" ARGS ${args} --out "${WORK_DIR}/b"
        STDOUT "rendered 0 frames")
cli_expect_same_files("${a}" "${WORK_DIR}/b")

# Another dataset's folder is refused, and replaced only with --force.
cli_run(EXIT 2 WHAT "other arguments" ARGS dataset "${scenario}" --worlds 1 --frames-per-world 2
        --out "${WORK_DIR}/b"
        STDERR "command line: --out: .*dataset.json was written with other arguments \\(first difference: `worlds`\\); use --force")
cli_expect_same_files("${a}" "${WORK_DIR}/b")
cli_run(EXIT 0 WHAT "other arguments with --force" ARGS dataset "${scenario}" --worlds 1
        --frames-per-world 2 --cameras upward --out "${WORK_DIR}/b" --force)
if(EXISTS "${WORK_DIR}/b/front" OR EXISTS "${WORK_DIR}/b/worlds/w001")
  message(FATAL_ERROR "--force left files of the previous dataset")
endif()
# A folder with files but no dataset.json is never touched, even with --force.
file(WRITE "${WORK_DIR}/mine/notes.txt" "mine\n")
cli_run(EXIT 2 WHAT "a user's folder" ARGS ${args} --out "${WORK_DIR}/mine" --force
        STDERR "command line: --out: .*mine holds files that corridorsim did not write \\(it has no \\.corridorsim-output\\)")
cli_expect_files("${WORK_DIR}/mine" notes.txt)
# Nor is a user's folder that happens to hold a dataset.json: dataset resumes or replaces only a
# folder it proves it wrote (the marker .corridorsim-output), not one with a manifest of its shape,
# nor one holding a copy of this very dataset's manifest.
set(theirs "${WORK_DIR}/theirs")
file(WRITE "${theirs}/dataset.json" "{\"format\": \"corridorsim dataset\", \"cameras\": []}\n")
file(WRITE "${theirs}/notes.txt" "mine\n")
foreach(force "" --force)
  cli_run(EXIT 2 WHAT "a user's folder with a dataset.json ${force}" ARGS ${args} --out "${theirs}"
          ${force} STDERR "command line: --out: .*theirs holds files that corridorsim did not write")
  cli_expect_files("${theirs}" dataset.json notes.txt)
endforeach()
file(COPY_FILE "${a}/dataset.json" "${theirs}/dataset.json")
cli_run(EXIT 2 WHAT "a user's folder with this dataset's manifest" ARGS ${args} --out "${theirs}"
        STDERR "command line: --out: .*theirs holds files that corridorsim did not write")
cli_expect_files("${theirs}" dataset.json notes.txt)
if(EXISTS "${theirs}/front" OR EXISTS "${theirs}/.corridorsim-output")
  message(FATAL_ERROR "dataset wrote into a folder it did not write")
endif()
# The marker must be a file of its own, not a link to one.
file(CREATE_LINK "${a}/.corridorsim-output" "${theirs}/.corridorsim-output" SYMBOLIC)
cli_run(EXIT 2 WHAT "a linked marker" ARGS ${args} --out "${theirs}" --force
        STDERR "command line: --out: .*theirs holds files that corridorsim did not write")
cli_expect_files("${theirs}" dataset.json notes.txt)
# Another corridorsim job's folder (the marker, no dataset.json) is replaced only with --force.
file(WRITE "${WORK_DIR}/none.json" "[]\n")
cli_run(EXIT 0 WHAT "a score report" ARGS score "${WORK_DIR}/none.json" --dataset "${a}"
        --camera upward --out "${WORK_DIR}/report")
cli_run(EXIT 2 WHAT "another job's folder" ARGS ${args} --cameras upward --out "${WORK_DIR}/report"
        STDERR "command line: --out: .*report holds another corridorsim job's output \\(no dataset.json\\); use --force")
cli_expect_files("${WORK_DIR}/report" score.json)
# A dataset.json that is not a regular file (a FIFO would block a plain read) is refused.
file(REMOVE "${WORK_DIR}/report/score.json" "${WORK_DIR}/report/score.png")
execute_process(COMMAND mkfifo "${WORK_DIR}/report/dataset.json" RESULT_VARIABLE fifo_rc)
if(NOT fifo_rc EQUAL 0)
  message(FATAL_ERROR "mkfifo failed")
endif()
cli_run(EXIT 2 WHAT "a FIFO manifest" ARGS ${args} --cameras upward --out "${WORK_DIR}/report"
        STDERR "report/dataset.json: not a regular file")

# Path poses: evenly spaced along the scenario's round trip, heading along each leg.
cli_run(EXIT 0 WHAT "path poses" ARGS dataset "${scenario}" --poses path --frames-per-world 2
        --cameras upward --out "${WORK_DIR}/path")
file(READ "${WORK_DIR}/path/upward/truth/w000_f0000.json" truth)
string(JSON x GET "${truth}" world_from_robot t 0)
string(JSON qz GET "${truth}" world_from_robot q 2)
if(NOT x EQUAL 5 OR NOT qz EQUAL 0)
  message(FATAL_ERROR "path pose 0: x ${x}, qz ${qz}; expected the middle of the outward leg")
endif()

# Plate poses: the lateral camera aimed at plates (and a quarter at printed distractors), the
# views train-detectors learns from; most frames show a plate, each within 0.4-3.5 m of the camera
# (the aimed-at one; others may lie farther).
cli_run(EXIT 0 WHAT "plate poses" ARGS dataset "${SOURCE_DIR}/scenarios/datasets/train_detectors.yaml"
        --poses plates --cameras lateral --frames-per-world 12 --out "${WORK_DIR}/plates")
set(with_plate 0)
foreach(f RANGE 0 11)
  string(LENGTH "${f}" digits)
  if(digits EQUAL 1)
    set(stem "w000_f000${f}")
  else()
    set(stem "w000_f00${f}")
  endif()
  file(READ "${WORK_DIR}/plates/lateral/truth/${stem}.json" truth)
  string(JSON plates LENGTH "${truth}" plates)
  set(near 0)
  if(plates GREATER 0)
    math(EXPR last "${plates} - 1")
    foreach(k RANGE 0 ${last})
      string(JSON d GET "${truth}" plates ${k} distance_m)
      if(d LESS_EQUAL 3.6)
        set(near 1)
      endif()
    endforeach()
  endif()
  math(EXPR with_plate "${with_plate} + ${near}")
endforeach()
if(with_plate LESS 6)
  message(FATAL_ERROR "plate poses: ${with_plate} of 12 frames show a plate within 3.6 m")
endif()
# train-detectors checks its models' folder before it reads or trains anything (a file in its
# place failed with exit 1 after the training).
file(WRITE "${WORK_DIR}/models_file" "")
cli_run(EXIT 2 WHAT "train-detectors --out a file"
        STDERR "command line: --out: .*models_file"
        ARGS train-detectors --dataset "${WORK_DIR}/plates" --eval-dataset "${WORK_DIR}/plates"
        --out "${WORK_DIR}/models_file")
cli_run(EXIT 2 WHAT "plate poses without the lateral camera"
        STDERR "command line: --poses: plates: aims the lateral camera"
        NOT_EXISTS "${WORK_DIR}/bad" ARGS dataset "${scenario}" --cameras upward --poses plates
        --out "${WORK_DIR}/bad")

# A named camera (docs/sensors.md: `type: camera`) is a camera like the three: its own folder with
# images, labels, depth and truth per frame, annotated, and named in dataset.json.
file(WRITE "${WORK_DIR}/named.yaml"
     "include: ${scenario}\nsensors:\n  high_cam:\n    type: camera\n    width: 96\n"
     "    height: 72\n    fov_deg: 70\n    depth: true\n    mount: {x_m: 0.1, z_m: 0.6, pitch_deg: 10}\n")
cli_run(EXIT 0 WHAT "a named camera" ARGS dataset "${WORK_DIR}/named.yaml" --worlds 1
        --frames-per-world 2 --cameras high_cam,front --out "${WORK_DIR}/named"
        STDOUT "cameras front,high_cam: rendered 2 frames")
foreach(stem w000_f0000 w000_f0001)
  cli_expect_files("${WORK_DIR}/named/high_cam" images/${stem}.png labels/${stem}.png
                   depth/${stem}.png truth/${stem}.json)
endforeach()
file(READ "${WORK_DIR}/named/dataset.json" manifest)
string(JSON named_cameras GET "${manifest}" cameras)
string(REGEX REPLACE "[ \n]" "" named_cameras "${named_cameras}")
file(READ "${WORK_DIR}/named/high_cam/truth/w000_f0001.json" truth)
string(JSON truth_camera GET "${truth}" camera_id)
string(JSON width GET "${truth}" width)
file(READ "${WORK_DIR}/named/high_cam/annotations.json" coco)
string(JSON n_images LENGTH "${coco}" images)
string(JSON n_annotations LENGTH "${coco}" annotations)
if(NOT named_cameras STREQUAL "[\"front\",\"high_cam\"]" OR NOT truth_camera STREQUAL "high_cam"
   OR NOT width EQUAL 96 OR NOT n_images EQUAL 2 OR n_annotations EQUAL 0)
  message(FATAL_ERROR "named camera: dataset.json cameras ${named_cameras}, truth camera_id "
                      "${truth_camera} width ${width}, ${n_images} images, ${n_annotations} annotations")
endif()
cli_run(EXIT 0 WHAT "score on a named camera" ARGS score "${WORK_DIR}/none.json" --dataset
        "${WORK_DIR}/named" --camera high_cam --out "${WORK_DIR}/named_report")

# Bad input: exit 2 naming the option, nothing written.
cli_run(EXIT 2 WHAT "unknown camera" STDERR "command line: --cameras: 'rear' is not a camera the scenario enables"
        NOT_EXISTS "${WORK_DIR}/bad" ARGS dataset "${scenario}" --cameras upward,rear --out "${WORK_DIR}/bad")
file(WRITE "${WORK_DIR}/no_upward.yaml" "include: ${scenario}\nsensors:\n  upward: {enabled: false}\n")
cli_run(EXIT 2 WHAT "disabled camera" STDERR "command line: --cameras: 'upward' is not a camera"
        NOT_EXISTS "${WORK_DIR}/bad" ARGS dataset "${WORK_DIR}/no_upward.yaml" --cameras upward --out "${WORK_DIR}/bad")
cli_run(EXIT 2 WHAT "twice" STDERR "command line: --cameras: 'front' is named twice"
        NOT_EXISTS "${WORK_DIR}/bad" ARGS dataset "${scenario}" --cameras front,front --out "${WORK_DIR}/bad")
cli_run(EXIT 2 WHAT "missing scenario" STDERR "missing.yaml"
        NOT_EXISTS "${WORK_DIR}/bad" ARGS dataset "${WORK_DIR}/missing.yaml" --out "${WORK_DIR}/bad")
cli_run(EXIT 2 WHAT "worlds 0" STDERR "command line: --worlds: must be a whole number in \\[1, 100000\\]"
        NOT_EXISTS "${WORK_DIR}/bad" ARGS dataset "${scenario}" --worlds 0 --out "${WORK_DIR}/bad")
cli_run(EXIT 2 WHAT "worlds one past the most" STDERR "command line: --worlds: must be a whole number in \\[1, 100000\\] \\(got '100001'\\)"
        NOT_EXISTS "${WORK_DIR}/bad" ARGS dataset "${scenario}" --worlds 100001 --out "${WORK_DIR}/bad")
cli_run(EXIT 2 WHAT "frames 1e9" STDERR "command line: --frames-per-world: must be a whole number in \\[1, 100000\\] \\(got .1e9.\\)"
        NOT_EXISTS "${WORK_DIR}/bad" ARGS dataset "${scenario}" --frames-per-world 1e9 --out "${WORK_DIR}/bad")
cli_run(EXIT 2 WHAT "bad poses" STDERR "command line: --poses: expected path, random or plates"
        NOT_EXISTS "${WORK_DIR}/bad" ARGS dataset "${scenario}" --poses grid --out "${WORK_DIR}/bad")
file(WRITE "${WORK_DIR}/script.yaml"
     "include: ${scenario}\npath:\n  kind: script\n  commands: [[2, 0.2, 0]]\n")
cli_run(EXIT 2 WHAT "path poses on a script" STDERR "command line: --poses: path: the scenario's path is a script"
        NOT_EXISTS "${WORK_DIR}/bad" ARGS dataset "${WORK_DIR}/script.yaml" --poses path --out "${WORK_DIR}/bad")
