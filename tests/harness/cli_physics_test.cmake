# `corridorsim run` and `drive` against the physics: the truth at every stamp whatever the physics
# rate (same ground_truth.tum rows and nearly the same ATE at 1000, 1001 and 333.3 Hz, a truth row
# at every estimate's stamp), ground_truth.tum meaning the same in both jobs, and the placement
# check along the whole path (a body or a camera that meets the world anywhere exits 2 naming
# its key; every shipped scenario passes).
include("${CMAKE_CURRENT_LIST_DIR}/cli_support.cmake")
cmake_policy(SET CMP0057 NEW)  # if(IN_LIST)

# A short default run: odometry errors on, so the ATE is millimetres, not zero.
cli_write_short_scenario("${WORK_DIR}/short.yaml" 6.0 2 2 "duration_s: 12
expectations: []
")

# The first column (stamps) of a TUM file's data lines.
function(tum_stamps file out)
  file(STRINGS "${file}" lines REGEX "^[^#]")
  set(stamps "")
  foreach(line ${lines})
    string(REGEX MATCH "^[^ ]+" t "${line}")
    list(APPEND stamps "${t}")
  endforeach()
  set(${out} "${stamps}" PARENT_SCOPE)
endfunction()

function(ate dir out)
  file(READ "${dir}/metrics.json" json)
  string(JSON value GET "${json}" pipelines odometry ate_rmse_m)
  set(${out} "${value}" PARENT_SCOPE)
endfunction()

# --- 1. Truth at every stamp whatever the physics rate ------------------------------------------
set(rates 1000 1001 333.3)
foreach(rate ${rates})
  string(REPLACE "." "_" tag "${rate}")
  file(WRITE "${WORK_DIR}/rate_${tag}.yaml"
       "include: ${WORK_DIR}/short.yaml\nrobot:\n  physics_rate_hz: ${rate}\n")
  cli_run(EXIT 0 WHAT "run at ${rate} Hz" STDOUT "real-time factor"
          ARGS run "${WORK_DIR}/rate_${tag}.yaml" --out "${WORK_DIR}/run_${tag}" --no-plots
               --no-viewer)
  tum_stamps("${WORK_DIR}/run_${tag}/ground_truth.tum" truth_${tag})
  tum_stamps("${WORK_DIR}/run_${tag}/odometry.tum" estimates_${tag})
  ate("${WORK_DIR}/run_${tag}" ate_${tag})
endforeach()
list(LENGTH truth_1000 rows_1000)
if(rows_1000 LESS 1201)  # 12 s at 100 Hz, and 0
  message(FATAL_ERROR "ground_truth.tum at 1000 Hz: only ${rows_1000} rows")
endif()
foreach(tag 1001 333_3)
  list(LENGTH truth_${tag} rows)
  if(NOT rows EQUAL rows_1000)
    message(FATAL_ERROR "ground_truth.tum at ${tag} Hz physics: ${rows} rows, ${rows_1000} at 1000 Hz")
  endif()
  # Every estimate is scored against the truth at its own stamp: the truth has a row there.
  foreach(t ${estimates_${tag}})
    if(NOT t IN_LIST truth_${tag})
      message(FATAL_ERROR "physics ${tag} Hz: no truth row at the estimate stamp ${t}")
    endif()
  endforeach()
  # The same drive scored the same: the ATE within 5 % + 1 mm of the 1000 Hz run. CMake has no
  # floating point: compare in micrometres.
  foreach(v 1000 ${tag})
    if(NOT ate_${v} MATCHES "^([0-9]+)\\.([0-9]+)$")
      message(FATAL_ERROR "ate_rmse_m at ${v} Hz is not a plain decimal: ${ate_${v}}")
    endif()
    string(SUBSTRING "${CMAKE_MATCH_2}000000" 0 6 frac)
    math(EXPR um_${v} "${CMAKE_MATCH_1} * 1000000 + 1${frac} - 1000000")
  endforeach()
  set(um_a ${um_1000})
  set(um_b ${um_${tag}})
  set(a ${ate_1000})
  set(b ${ate_${tag}})
  math(EXPR diff "${um_b} - ${um_a}")
  if(diff LESS 0)
    math(EXPR diff "-${diff}")
  endif()
  math(EXPR allowed "${um_a} / 20 + 1000")
  if(diff GREATER allowed)
    message(FATAL_ERROR "ATE at ${tag} Hz physics ${b} m, at 1000 Hz ${a} m: more than 5 % + 1 mm apart")
  endif()
endforeach()
foreach(t ${estimates_1000})
  if(NOT t IN_LIST truth_1000)
    message(FATAL_ERROR "physics 1000 Hz: no truth row at the estimate stamp ${t}")
  endif()
endforeach()

# --- 2. ground_truth.tum is the same thing in `drive` and `run` -----------------------------------
cli_run(EXIT 0 WHAT "drive" STDOUT "ground_truth_3d.tum"
        ARGS drive "${WORK_DIR}/short.yaml" --out "${WORK_DIR}/drive")
cli_run(EXIT 0 WHAT "run" STDOUT "real-time factor"
        ARGS run "${WORK_DIR}/short.yaml" --out "${WORK_DIR}/run" --no-plots --no-viewer)
cli_expect_same_files("${WORK_DIR}/drive" "${WORK_DIR}/run" ground_truth.tum)
file(STRINGS "${WORK_DIR}/drive/ground_truth.tum" header LIMIT_COUNT 1)
if(NOT header MATCHES "^# ground truth: planar world_from_robot")
  message(FATAL_ERROR "ground_truth.tum is not the planar truth: ${header}")
endif()
tum_stamps("${WORK_DIR}/drive/ground_truth.tum" planar)
tum_stamps("${WORK_DIR}/drive/ground_truth_3d.tum" full)
if(NOT planar STREQUAL full)
  message(FATAL_ERROR "ground_truth_3d.tum has other stamps than ground_truth.tum")
endif()
if(EXISTS "${WORK_DIR}/run/ground_truth_3d.tum")
  message(FATAL_ERROR "a run folder holds ground_truth_3d.tum (plot_run.py reads *.tum as estimates)")
endif()

# --- 3. Physical sanity along the whole path -----------------------------------------------------
function(expect_bad name yaml pattern)
  cli_expect_bad(${name} "include: ${WORK_DIR}/short.yaml\n${yaml}" "${pattern}" ${ARGN})
endfunction()

# A body wider than the corridor spawns in the walls; a 2 m wide one only meets the end wall while
# it turns.
expect_bad(wide_body "world:\n  width_m: 1.9\nrobot:\n  body_width_m: 2.0\n"
           "wide_body.yaml:5:3: robot.body_width_m: the robot body .* intersects a wall .*\\(got 2\\)"
           run --out "${WORK_DIR}/bad")
expect_bad(turning_body "robot:\n  body_width_m: 2.0\n"
           "turning_body.yaml:3:3: robot.body_width_m: the robot body .*, 4 m along the path, intersects a wall"
           drive --out "${WORK_DIR}/bad")
expect_bad(long_body "path:\n  end_margin_m: 1.5\nrobot:\n  body_length_m: 2.4\n"
           "long_body.yaml:5:3: robot.body_length_m: the robot body \\(2.4 x 0.381 x 0.237 m\\) .* intersects a (wall|door_frame)"
           run --check --out "${WORK_DIR}/bad")
# A camera above the ceiling.
expect_bad(high_camera "sensors:\n  front:\n    mount: {z_m: 3.0}\n"
           "high_camera.yaml:4:5: sensors.front.mount: the camera at .* is above the ceiling \\(2.7 m high\\)"
           run --out "${WORK_DIR}/bad")
# A camera 0.6 m to the side, fine at the start, inside the end wall during the first turn (the
# round trip turns counter-clockwise: the right side swings forward).
expect_bad(side_camera "path:\n  end_margin_m: 0.5\nsensors:\n  lateral:\n    mount: {y_m: -0.6}\n"
           "side_camera.yaml:6:5: sensors.lateral.mount: the camera at .*, 5 m along the path, is inside a wall"
           run --out "${WORK_DIR}/bad")
# A script into a wall.
expect_bad(script_into_wall "path:\n  kind: script\n  commands: [[20, 0.3, 0]]\n"
           "script_into_wall.yaml:4:3: path.commands: the robot body .* intersects a wall"
           drive --out "${WORK_DIR}/bad")

# Every shipped scenario passes the check.
file(GLOB shipped "${SOURCE_DIR}/scenarios/*.yaml")
foreach(scenario ${shipped})
  cli_run(EXIT 0 WHAT "run --check ${scenario}" STDOUT "^ok: "
          ARGS run "${scenario}" --check --out "${WORK_DIR}/check")
endforeach()
