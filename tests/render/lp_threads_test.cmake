# Fails if render_probe's hash of the rendered images changes with LP_NUM_THREADS (llvmpipe's
# rasterizer threads): the OSMesa backend must give byte-identical images for 0, 1 and 2 threads.
# EGL is checked the same way where an EGL context can be created (probe exit code 3: skipped).
#   cmake -DPROBE=<path to render_probe> -P lp_threads_test.cmake
if(NOT PROBE)
  message(FATAL_ERROR "pass -DPROBE=<path to render_probe>")
endif()

foreach(backend osmesa egl)
  set(reference "")
  foreach(threads 0 1 2)
    execute_process(
      COMMAND ${CMAKE_COMMAND} -E env LP_NUM_THREADS=${threads} ${PROBE} ${backend}
      RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err OUTPUT_STRIP_TRAILING_WHITESPACE)
    if(backend STREQUAL "egl" AND rc EQUAL 3)
      message(STATUS "egl backend not available here, skipped: ${err}")
      break()
    endif()
    if(NOT rc EQUAL 0)
      message(FATAL_ERROR "${backend} with LP_NUM_THREADS=${threads}: probe failed (${rc}):\n${err}")
    endif()
    message(STATUS "${backend} LP_NUM_THREADS=${threads}: ${out}")
    if(reference STREQUAL "")
      set(reference "${out}")
    elseif(NOT out STREQUAL reference)
      message(FATAL_ERROR
        "${backend}: images differ with LP_NUM_THREADS=${threads}: '${out}' vs '${reference}'")
    endif()
  endforeach()
endforeach()
message(STATUS "render output identical across LP_NUM_THREADS")
