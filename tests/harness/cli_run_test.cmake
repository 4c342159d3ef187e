# `corridorsim run` as a user runs it: bad input gets exit code 2 and one message naming the
# file, line and key, before anything runs or any folder is written.
include("${CMAKE_CURRENT_LIST_DIR}/cli_support.cmake")

# default.yaml with the lines `yaml`.
function(expect_bad name yaml pattern)
  cli_expect_bad_run(${name} "include: ${SOURCE_DIR}/scenarios/default.yaml\n${yaml}" "${pattern}")
endfunction()

expect_bad(unknown_metric "expectations:\n  - odometry.speed_of_light < 3\n"
           "unknown_metric.yaml:3:5: expectations: .*unknown metric 'speed_of_light'")
expect_bad(bad_operator "expectations:\n  - odometry.ate_rmse_m ~ 3\n"
           "bad_operator.yaml:3:5: expectations:")
expect_bad(absent_pipeline "expectations:\n  - p3_upward.ate_rmse_m < 0.15\n"
           "absent_pipeline.yaml:3:5: expectations: .*the pipeline 'p3_upward' does not run")
expect_bad(unknown_pipeline "pipelines:\n  orb_slam9: {}\n"
           "unknown_pipeline.yaml:3:3: pipelines.orb_slam9: unknown pipeline")
expect_bad(bad_option "pipelines:\n  odometry: {k_m: -2}\n"
           "bad_option.yaml:3:.*pipelines.odometry.k_m: must lie in")
expect_bad(drop_one "sensors:\n  front: {drop_probability: 1.5}\n"
           "drop_one.yaml:3:.*sensors.front.drop_probability: must lie in")
expect_bad(missing_models "pipelines:\n  p1_vp_doorplate:\n    models_dir: ${WORK_DIR}/no_models\n"
           "missing_models.yaml:4:.*pipelines.p1_vp_doorplate.models_dir: model file .*door_plate_svm.yml: missing")

# An unwritable output folder is refused before the run starts.
file(WRITE "${WORK_DIR}/not_a_dir" "x")
cli_run(EXIT 2 WHAT "unwritable --out" STDERR "--out" NOT_STDOUT "real-time factor"
        ARGS run --out "${WORK_DIR}/not_a_dir/run")
cli_run(EXIT 2 WHAT "unwritable --export" STDERR "--export" NOT_STDOUT "real-time factor"
        ARGS run --out "${WORK_DIR}/ok" --export "${WORK_DIR}/not_a_dir/x")
