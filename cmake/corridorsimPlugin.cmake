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
  # A symbol the plugin uses and nothing provides is a link error now, not a load error later.
  target_link_options(${name} PRIVATE LINKER:--no-undefined)
endfunction()
