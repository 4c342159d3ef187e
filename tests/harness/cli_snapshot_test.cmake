# `corridorsim snapshot` as a user runs it: the files, byte-identical reruns and across llvmpipe
# thread counts, and exit code 2 with a clear message for impossible cameras.
file(REMOVE_RECURSE "${WORK_DIR}")
file(MAKE_DIRECTORY "${WORK_DIR}")

# The default scenario with every camera on (default.yaml leaves P2/P3's upward camera off).
file(WRITE "${WORK_DIR}/all_cameras.yaml"
     "include: ${SOURCE_DIR}/scenarios/default.yaml\nsensors:\n  upward:\n    enabled: true\n")

function(snapshot out threads)
  execute_process(COMMAND ${CMAKE_COMMAND} -E env LP_NUM_THREADS=${threads}
                          "${CORRIDORSIM}" snapshot "${WORK_DIR}/all_cameras.yaml"
                          --pose 12,0.2,10 --out "${out}"
                  WORKING_DIRECTORY "${SOURCE_DIR}" RESULT_VARIABLE rc OUTPUT_VARIABLE stdout
                  ERROR_VARIABLE stderr)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "snapshot exited ${rc}: ${stderr}")
  endif()
endfunction()

snapshot("${WORK_DIR}/a" 0)
snapshot("${WORK_DIR}/b" 1)
snapshot("${WORK_DIR}/c" 2)
foreach(camera front lateral upward)
  foreach(kind rgb labels overlay)
    if(NOT EXISTS "${WORK_DIR}/a/${camera}_${kind}.png")
      message(FATAL_ERROR "missing ${camera}_${kind}.png")
    endif()
  endforeach()
endforeach()
foreach(f front_depth.png frame_ground_truth.json intrinsics.json)
  if(NOT EXISTS "${WORK_DIR}/a/${f}")
    message(FATAL_ERROR "missing ${f}")
  endif()
endforeach()
file(READ "${WORK_DIR}/a/intrinsics.json" intrinsics)
if(NOT intrinsics MATCHES "\"depth_scale\": 5000")
  message(FATAL_ERROR "intrinsics.json lacks depth_scale 5000")
endif()
file(GLOB files RELATIVE "${WORK_DIR}/a" "${WORK_DIR}/a/*")
foreach(f ${files})
  file(SHA256 "${WORK_DIR}/a/${f}" ha)
  foreach(other b c)
    file(SHA256 "${WORK_DIR}/${other}/${f}" hb)
    if(NOT ha STREQUAL hb)
      message(FATAL_ERROR "${f} differs between runs with LP_NUM_THREADS 0 and another count (${other})")
    endif()
  endforeach()
endforeach()

# Impossible cameras: exit code 2 and the key in the message.
function(expect_bad name yaml pattern)
  file(WRITE "${WORK_DIR}/${name}.yaml" "${yaml}")
  execute_process(COMMAND "${CORRIDORSIM}" snapshot "${WORK_DIR}/${name}.yaml" --pose 10,0,0
                          --out "${WORK_DIR}/bad"
                  RESULT_VARIABLE rc ERROR_VARIABLE stderr OUTPUT_QUIET)
  if(NOT rc EQUAL 2)
    message(FATAL_ERROR "${name}: exit ${rc}, expected 2 (${stderr})")
  endif()
  if(NOT stderr MATCHES "${pattern}")
    message(FATAL_ERROR "${name}: unexpected message: ${stderr}")
  endif()
endfunction()

expect_bad(fisheye_180 "sensors:\n  upward:\n    fov_deg: 180\n"
           "fisheye_180.yaml:3:5: sensors.upward.fov_deg: a fisheye must see less than 180")
expect_bad(pinhole_150 "sensors:\n  front:\n    fov_deg: 150\n"
           "pinhole_150.yaml:3:5: sensors.front.fov_deg: a pinhole camera must see less than 150")
expect_bad(zero_size "sensors:\n  lateral:\n    width: 0\n"
           "zero_size.yaml:3:5: sensors.lateral.width: the image size must be positive")
expect_bad(in_wall "sensors:\n  lateral:\n    mount: {y_m: 1.3}\n"
           "in_wall.yaml:3:5: sensors.lateral.mount: the camera at .* is (inside|outside)")
expect_bad(unknown_camera "sensors:\n  rear: {}\n" "unknown_camera.yaml:2:3: sensors.rear: unknown key")

execute_process(COMMAND "${CORRIDORSIM}" snapshot --pose 10,zero,0 RESULT_VARIABLE rc
                ERROR_VARIABLE stderr OUTPUT_QUIET)
if(NOT rc EQUAL 2 OR NOT stderr MATCHES "--pose: expected x,y,yaw")
  message(FATAL_ERROR "bad pose: exit ${rc}, ${stderr}")
endif()
