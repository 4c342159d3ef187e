# `corridorsim run` scores something and records what its bytes depend on: an empty scenario and
# one without an enabled pipeline are bad input (exit 2, no run folder), an expectation on a
# wall-clock metric too; a run writes provenance.json with the SHA-256 of its scenario.yaml.
include("${CMAKE_CURRENT_LIST_DIR}/cli_support.cmake")

foreach(case IN ITEMS "zero_bytes;" "comments;# nothing here yet\n\n" "empty_map;{}\n")
  list(GET case 0 name)
  list(LENGTH case n)
  set(text "")
  if(n GREATER 1)
    list(GET case 1 text)
  endif()
  cli_expect_bad_run(${name} "${text}" "${name}.yaml: the scenario is empty")
endforeach()

# No enabled pipeline: `run` would score nothing; `drive` needs none, nor `run --export`.
set(no_pipeline "seed: 3\nduration_s: 1\nworld: {length_m: 12, doors: {count: 4}, plates: {count: 3}}\n")
cli_expect_bad(no_pipeline "${no_pipeline}"
               "no_pipeline.yaml: pipelines: no pipeline is enabled, so the run would score nothing"
               run --out "${WORK_DIR}/out_no_pipeline")
cli_expect_bad(disabled_pipeline "${no_pipeline}pipelines:\n  odometry: {enabled: false}\n"
               "disabled_pipeline.yaml:4:1: pipelines: no pipeline is enabled.*disabled: odometry"
               run --out "${WORK_DIR}/out_disabled")
cli_run(EXIT 0 WHAT "drive without a pipeline"
        ARGS drive "${WORK_DIR}/no_pipeline.yaml" --out "${WORK_DIR}/drive")
cli_expect_files("${WORK_DIR}/drive" provenance.json)
cli_run(EXIT 0 WHAT "run --export without a pipeline" STDOUT "^ok: "
        ARGS run "${WORK_DIR}/no_pipeline.yaml" --check --export "${WORK_DIR}/export")

# Wall-clock metrics cannot be expected.
cli_expect_bad(timing "include: ${SOURCE_DIR}/scenarios/default.yaml\nexpectations:\n  - odometry.timing.total_ms_per_step < 0.01\n"
               "timing.yaml:3:5: expectations: 'odometry.timing.total_ms_per_step < 0.01': timing metrics are machine-dependent; see timing.json"
               run --out "${WORK_DIR}/out_timing")

# A run records its provenance; the hash is that of the scenario.yaml it wrote.
file(WRITE "${WORK_DIR}/short.yaml" "${no_pipeline}pipelines:\n  odometry: {}\n")
cli_run(EXIT 0 WHAT "short run" ENV --unset=GALLIVM_PERF
        ARGS run "${WORK_DIR}/short.yaml" --out "${WORK_DIR}/run" --no-plots --no-viewer)
cli_expect_files("${WORK_DIR}/run" scenario.yaml provenance.json metrics.json)
file(SHA256 "${WORK_DIR}/run/scenario.yaml" expected)
file(READ "${WORK_DIR}/run/provenance.json" provenance)
string(JSON hash GET "${provenance}" scenario sha256)
string(JSON rendered GET "${provenance}" render rendered)
string(JSON version GET "${provenance}" project_version)
string(JSON compiler GET "${provenance}" compiler id)
string(JSON file GET "${provenance}" scenario file)
if(NOT hash STREQUAL expected)
  message(FATAL_ERROR "provenance.json's sha256 ${hash} is not scenario.yaml's ${expected}")
endif()
if(NOT rendered STREQUAL "OFF" OR version STREQUAL "" OR compiler STREQUAL "")
  message(FATAL_ERROR "provenance.json: rendered ${rendered}, version '${version}', compiler '${compiler}'")
endif()
if(NOT file STREQUAL "${WORK_DIR}/short.yaml")
  message(FATAL_ERROR "provenance.json names the scenario '${file}'")
endif()
# main() set GALLIVM_PERF for llvmpipe, but nothing was rendered and the user set none: null.
string(JSON gallivm_perf_type TYPE "${provenance}" environment GALLIVM_PERF)
if(NOT gallivm_perf_type STREQUAL "NULL")
  message(FATAL_ERROR "provenance.json: environment.GALLIVM_PERF is not null without a render")
endif()
# metrics.json holds no wall-clock value (timing.json does).
file(READ "${WORK_DIR}/run/metrics.json" metrics)
foreach(word IN ITEMS "\"timing\"" "wall_seconds" "wall_total_s" "real_time_factor" "ms_per")
  string(FIND "${metrics}" "${word}" at)
  if(NOT at EQUAL -1)
    message(FATAL_ERROR "metrics.json carries the wall-clock value ${word}")
  endif()
endforeach()
