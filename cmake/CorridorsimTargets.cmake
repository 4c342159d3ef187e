# Helpers that give every project target the same warnings and sanitizer flags.

function(corridorsim_target_flags target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow -Wnon-virtual-dtor
                                           -Wconversion -Wno-sign-conversion)
  # GCC 12 reports a false -Wrestrict inside std::string's operator+ (GCC bug 105329).
  if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU" AND CMAKE_CXX_COMPILER_VERSION VERSION_LESS 13)
    target_compile_options(${target} PRIVATE -Wno-restrict)
  endif()
  if(CORRIDORSIM_SANITIZE)
    # After the build type's flags, so these win: -O1 -g1 by default (docs/ci.md).
    target_compile_options(${target} PRIVATE -fsanitize=address,undefined -fno-omit-frame-pointer
                                             -fno-sanitize-recover=undefined
                                             ${CORRIDORSIM_SANITIZE_COMPILE_FLAGS})
    target_link_options(${target} PRIVATE -fsanitize=address,undefined)
  endif()
endfunction()

# corridorsim_add_library(NAME [SHARED] SOURCES ... PUBLIC_LINK ... PRIVATE_LINK ...)
# One library per layer; its link edges are the layering (COLMAP's colmap_add_library). SHARED:
# a library of the SDK (docs/plugins.md): one copy in the process, shared by the `corridorsim`
# program and the pipeline plugins it loads, installed with its headers; versioned by the SDK's
# ABI (slam/plugin.h). The others are static and internal.
function(corridorsim_add_library name)
  cmake_parse_arguments(ARG "SHARED" "" "SOURCES;PUBLIC_LINK;PRIVATE_LINK" ${ARGN})
  if(ARG_SHARED)
    add_library(${name} SHARED ${ARG_SOURCES})
    set_target_properties(${name} PROPERTIES
      VERSION ${PROJECT_VERSION}
      SOVERSION ${CORRIDORSIM_SDK_ABI_VERSION})
    # Calls inside the library bind inside it, as in a static build: no interposition, so GCC
    # inlines as before (and the numbers stay byte-identical to a static build's).
    target_compile_options(${name} PRIVATE -fno-semantic-interposition)
  else()
    add_library(${name} STATIC ${ARG_SOURCES})
  endif()
  target_include_directories(${name} PUBLIC $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}>
                                            $<INSTALL_INTERFACE:${CORRIDORSIM_INSTALL_INCLUDEDIR}>)
  target_link_libraries(${name} PUBLIC ${ARG_PUBLIC_LINK} PRIVATE ${ARG_PRIVATE_LINK})
  corridorsim_target_flags(${name})
endfunction()

function(corridorsim_add_executable name)
  cmake_parse_arguments(ARG "" "" "SOURCES;LINK" ${ARGN})
  add_executable(${name} ${ARG_SOURCES})
  target_link_libraries(${name} PRIVATE ${ARG_LINK})
  corridorsim_target_flags(${name})
endfunction()
