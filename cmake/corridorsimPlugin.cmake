# corridorsim_add_pipeline_plugin(NAME SOURCES ...): a pipeline plugin for corridorsim
# (docs/plugins.md). A MODULE library (loaded with dlopen, never linked) against corridorsim::slam,
# C++20 like the SDK, with hidden visibility so that only the entry points CORRIDORSIM_PLUGIN
# defines are exported, and no "lib" prefix: NAME.so. Link more with target_link_libraries.
function(corridorsim_add_pipeline_plugin name)
  cmake_parse_arguments(ARG "" "" "SOURCES" ${ARGN})
  if(NOT ARG_SOURCES)
    message(FATAL_ERROR "corridorsim_add_pipeline_plugin(${name}): no SOURCES")
  endif()
  add_library(${name} MODULE ${ARG_SOURCES})
  target_link_libraries(${name} PRIVATE corridorsim::slam)
  target_compile_features(${name} PRIVATE cxx_std_20)
  set_target_properties(${name} PROPERTIES
    PREFIX ""
    CXX_EXTENSIONS OFF
    CXX_VISIBILITY_PRESET hidden
    VISIBILITY_INLINES_HIDDEN ON
    POSITION_INDEPENDENT_CODE ON)
  # Undefined symbols are allowed at link time, as for any MODULE (a sanitized plugin takes its
  # runtime from the program); corridorsim loads with RTLD_NOW, so a symbol nothing provides is
  # refused at load with dlerror()'s text (exit 2), never a crash in the middle of a run.
endfunction()
