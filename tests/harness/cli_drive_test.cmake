# `corridorsim drive` as a user runs it: the files, TUM lines with 8 columns, byte-identical
# reruns, saved frames, and exit code 2 with a clear message for bad robot and path input.
include("${CMAKE_CURRENT_LIST_DIR}/cli_support.cmake")

# A short corridor with odometry errors and slips on, so determinism covers every stream.
cli_write_short_scenario("${WORK_DIR}/short.yaml" 9.0 4 3 "robot:
  odometry: {random_k_m: 0.0001, slip_rate_per_m: 0.3, diameter_ratio: 1.005}
sensors:
  front: {width: 80, height: 60, rate_hz: 3.3333333333}
  lateral: {enabled: false}
  upward: {enabled: true, width: 80, height: 60, rate_hz: 2}
")

function(drive out)
  cli_run(EXIT 0 WHAT "drive ${ARGN}" STDOUT "real-time factor"
          ARGS drive "${WORK_DIR}/short.yaml" --out "${out}" ${ARGN})
endfunction()

drive("${WORK_DIR}/a")
drive("${WORK_DIR}/b")
cli_expect_same_files("${WORK_DIR}/a" "${WORK_DIR}/b" ground_truth.tum odometry.tum odometry.csv
                      events.json)
foreach(f ground_truth.tum odometry.tum)
  file(STRINGS "${WORK_DIR}/a/${f}" lines REGEX "^[^#]")
  list(LENGTH lines n)
  if(n LESS 100)
    message(FATAL_ERROR "${f}: only ${n} poses")
  endif()
  foreach(line ${lines})
    string(REGEX MATCHALL "[^ ]+" columns "${line}")
    list(LENGTH columns c)
    if(NOT c EQUAL 8)
      message(FATAL_ERROR "${f}: a line without 8 columns: ${line}")
    endif()
  endforeach()
endforeach()
file(READ "${WORK_DIR}/a/events.json" events)
if(NOT events MATCHES "\"type\": \"path_done\"" OR NOT events MATCHES "\"type\": \"slip\"")
  message(FATAL_ERROR "events.json lacks path_done or slips: ${events}")
endif()

# Another seed, other odometry.
drive("${WORK_DIR}/c" --seed 9)
file(SHA256 "${WORK_DIR}/a/odometry.tum" ha)
file(SHA256 "${WORK_DIR}/c/odometry.tum" hc)
if(ha STREQUAL hc)
  message(FATAL_ERROR "--seed did not change the odometry")
endif()

# Saved frames: rgb, labels and depth per stamp, and the per-frame truth.
drive("${WORK_DIR}/frames" --save-frames)
file(GLOB front_rgb "${WORK_DIR}/frames/frames/front/rgb/*.png")
file(GLOB front_depth "${WORK_DIR}/frames/frames/front/depth/*.png")
file(GLOB upward_rgb "${WORK_DIR}/frames/frames/upward/rgb/*.png")
list(LENGTH front_rgb n_front)
list(LENGTH front_depth n_depth)
list(LENGTH upward_rgb n_upward)
if(n_front LESS 10 OR NOT n_front EQUAL n_depth OR n_upward EQUAL 0 OR NOT n_upward LESS n_front)
  message(FATAL_ERROR "frames: front ${n_front}, depth ${n_depth}, upward ${n_upward}")
endif()
if(NOT EXISTS "${WORK_DIR}/frames/frames/front/rgb/0.300000000.png")
  message(FATAL_ERROR "the front camera's second frame is not stamped 0.3 s")
endif()
cli_expect_files("${WORK_DIR}/frames" frames/front/frames.json frames/upward/frames.json
                 frames/intrinsics.json)
if(EXISTS "${WORK_DIR}/frames/frames/lateral")
  message(FATAL_ERROR "a disabled camera wrote frames")
endif()

# Bad input: exit code 2 and the key in the message.
function(expect_bad name yaml pattern)
  cli_expect_bad(${name} "include: ${WORK_DIR}/short.yaml\n${yaml}" "${pattern}" drive
                 --out "${WORK_DIR}/bad")
endfunction()

expect_bad(unknown_robot_key "robot:\n  wheels: 3\n" "unknown_robot_key.yaml:3:3: robot.wheels: unknown key")
expect_bad(bad_ratio "robot:\n  odometry:\n    diameter_ratio: 0\n"
           "bad_ratio.yaml:4:5: robot.odometry.diameter_ratio: must lie in")
expect_bad(bad_kind "path:\n  kind: zigzag\n" "bad_kind.yaml:3:3: path.kind: unknown value 'zigzag'")
expect_bad(negative_speed "path:\n  speed_mps: -1\n" "negative_speed.yaml:3:3: path.speed_mps:")
expect_bad(loop_on_straight "path:\n  kind: loop\n" "loop_on_straight.yaml:3:3: path.kind:")
expect_bad(offset_into_wall "path:\n  lateral_offset_m: 1.0\n"
           "offset_into_wall.yaml:3:3: path.lateral_offset_m:")
expect_bad(bad_duration "duration_s: -3\n" "bad_duration.yaml:2:1: duration_s: must lie in")
# Bounds on what becomes a time: a duration that would round to 0 ns, rates whose periods do not
# fit int64 nanoseconds (they rendered forever, or ran out of memory).
expect_bad(zero_ns_duration "duration_s: 1e-12\n" "zero_ns_duration.yaml:2:1: duration_s: must lie in .*got 1e-12")
cli_expect_bad(slow_camera "include: ${WORK_DIR}/short.yaml\nsensors:\n  front:\n    rate_hz: 1e-10\n"
               "slow_camera.yaml:4:5: sensors.front.rate_hz: must lie in .*got 1e-10" drive
               --out "${WORK_DIR}/bad" --save-frames)
expect_bad(slow_odometry "robot:\n  odometry:\n    rate_hz: 1e-10\n"
           "slow_odometry.yaml:4:5: robot.odometry.rate_hz: must lie in .*got 1e-10")

# An unwritable output folder is refused before the run.
file(WRITE "${WORK_DIR}/not_a_dir" "x")
cli_run(EXIT 2 WHAT "unwritable --out" STDERR "--out"
        ARGS drive "${WORK_DIR}/short.yaml" --out "${WORK_DIR}/not_a_dir/out")
