# `corridorsim snapshot` as a user runs it: the files, byte-identical reruns and across llvmpipe
# thread counts, and exit code 2 with a clear message for impossible cameras.
include("${CMAKE_CURRENT_LIST_DIR}/cli_support.cmake")

# The default scenario with every camera on (default.yaml leaves P2/P3's upward camera off).
file(WRITE "${WORK_DIR}/all_cameras.yaml"
     "include: ${SOURCE_DIR}/scenarios/default.yaml\nsensors:\n  upward:\n    enabled: true\n")

# Byte-identical across llvmpipe thread counts (LP_NUM_THREADS 0 draws on the calling thread).
foreach(threads 0 1 2)
  cli_run(EXIT 0 WHAT "snapshot with LP_NUM_THREADS=${threads}" ENV LP_NUM_THREADS=${threads}
          ARGS snapshot "${WORK_DIR}/all_cameras.yaml" --pose 12,0.2,10
               --out "${WORK_DIR}/threads_${threads}")
endforeach()
set(a "${WORK_DIR}/threads_0")
foreach(camera front lateral upward)
  cli_expect_files("${a}" ${camera}_rgb.png ${camera}_labels.png ${camera}_overlay.png)
endforeach()
cli_expect_files("${a}" front_depth.png frame_ground_truth.json intrinsics.json)
file(READ "${a}/intrinsics.json" intrinsics)
if(NOT intrinsics MATCHES "\"depth_scale\": 5000")
  message(FATAL_ERROR "intrinsics.json lacks depth_scale 5000")
endif()
cli_expect_same_files("${a}" "${WORK_DIR}/threads_1")
cli_expect_same_files("${a}" "${WORK_DIR}/threads_2")

# A named camera (docs/sensors.md: `type: camera`) gets the files of the three, its truth and its
# intrinsics under its name.
file(WRITE "${WORK_DIR}/named.yaml"
     "include: ${WORK_DIR}/all_cameras.yaml\nsensors:\n  rear_cam:\n    type: camera\n"
     "    width: 160\n    height: 120\n    depth: true\n    mount: {x_m: -0.1, z_m: 0.5, yaw_deg: 180}\n")
cli_run(EXIT 0 WHAT "snapshot with a named camera" STDOUT "4 cameras.*rear_cam +160x120 .*depth"
        ARGS snapshot "${WORK_DIR}/named.yaml" --pose 12,0.2,10 --out "${WORK_DIR}/named")
cli_expect_files("${WORK_DIR}/named" rear_cam_rgb.png rear_cam_labels.png rear_cam_overlay.png
                 rear_cam_depth.png)
file(READ "${WORK_DIR}/named/intrinsics.json" intrinsics)
string(JSON rear_width GET "${intrinsics}" rear_cam width)
file(READ "${WORK_DIR}/named/frame_ground_truth.json" truth)
string(JSON rear_id GET "${truth}" cameras rear_cam camera_id)
if(NOT rear_width EQUAL 160 OR NOT rear_id STREQUAL "rear_cam")
  message(FATAL_ERROR "named camera: intrinsics width ${rear_width}, truth camera_id ${rear_id}")
endif()
# The three cameras' files are those of the snapshot without it.
cli_expect_same_files("${a}" "${WORK_DIR}/named" front_rgb.png front_depth.png lateral_rgb.png
                      upward_rgb.png upward_labels.png)

# Impossible cameras: exit code 2 and the key in the message.
function(expect_bad name yaml pattern)
  cli_expect_bad(${name} "${yaml}" "${pattern}" snapshot --pose 10,0,0 --out "${WORK_DIR}/bad")
endfunction()

expect_bad(fisheye_180 "sensors:\n  upward:\n    fov_deg: 180\n"
           "fisheye_180.yaml:3:5: sensors.upward.fov_deg: a fisheye must see less than 180")
expect_bad(pinhole_150 "sensors:\n  front:\n    fov_deg: 150\n"
           "pinhole_150.yaml:3:5: sensors.front.fov_deg: a pinhole camera must see less than 150")
expect_bad(zero_size "sensors:\n  lateral:\n    width: 0\n"
           "zero_size.yaml:3:5: sensors.lateral.width: the image size must be positive")
expect_bad(in_wall "sensors:\n  lateral:\n    mount: {y_m: 1.3}\n"
           "in_wall.yaml:3:5: sensors.lateral.mount: the camera at .* is (inside|outside)")
expect_bad(unknown_camera "sensors:\n  rear: {}\n" "unknown_camera.yaml:2:3: sensors.rear: no sensor has this name")

cli_run(EXIT 2 WHAT "bad pose" STDERR "--pose: expected x,y,yaw" ARGS snapshot --pose 10,zero,0)
# A pose behind the corridor's wall is the command line's fault, not a camera mount's.
cli_run(EXIT 2 WHAT "pose behind a wall" STDERR "command line: --pose: the robot at \\(10.00, 5.00\\)"
        NOT_EXISTS "${WORK_DIR}/behind_wall" ARGS snapshot --pose 10,5,0 --out "${WORK_DIR}/behind_wall")
