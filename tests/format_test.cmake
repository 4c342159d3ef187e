# Fails if a C++ source of the project does not follow .clang-format.
file(GLOB_RECURSE files
  "${SOURCE_DIR}/common/*.h" "${SOURCE_DIR}/common/*.cpp"
  "${SOURCE_DIR}/worlds/*.h" "${SOURCE_DIR}/worlds/*.cpp"
  "${SOURCE_DIR}/render/*.h" "${SOURCE_DIR}/render/*.cpp"
  "${SOURCE_DIR}/sim/*.h" "${SOURCE_DIR}/sim/*.cpp"
  "${SOURCE_DIR}/slam/*.h" "${SOURCE_DIR}/slam/*.cpp"
  "${SOURCE_DIR}/harness/*.h" "${SOURCE_DIR}/harness/*.cpp"
  "${SOURCE_DIR}/tests/*.h" "${SOURCE_DIR}/tests/*.cpp"
  "${SOURCE_DIR}/bench/*.h" "${SOURCE_DIR}/bench/*.cpp"
  "${SOURCE_DIR}/examples/*.h" "${SOURCE_DIR}/examples/*.cpp")
execute_process(COMMAND "${CLANG_FORMAT}" --dry-run --Werror ${files}
                RESULT_VARIABLE rc ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "files not formatted with clang-format (run clang-format -i on them):\n${err}")
endif()
