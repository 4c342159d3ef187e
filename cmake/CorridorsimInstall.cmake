# What `cmake --install` puts where (docs/install.md), the CMake package that
# find_package(corridorsim) reads, and the Debian package `cpack -G DEB` makes from the build tree.
include(CMakePackageConfigHelpers)

# The program and the SDK's shared libraries (their SONAME carries the SDK ABI version).
install(TARGETS corridorsim RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT runtime)
install(TARGETS corridorsim_common corridorsim_slam
        EXPORT corridorsimTargets
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT runtime NAMELINK_COMPONENT dev
        INCLUDES DESTINATION ${CORRIDORSIM_INSTALL_INCLUDEDIR})

# The SDK's public headers: common/'s robot-facing types (not common/io/, the simulator's and the
# harness's I/O) and slam/ (the pipeline interface, the registry and plugin entry point, and the
# building blocks). What is installed is what a plugin may use: the harness, the simulator,
# worlds and rendering stay internal.
install(DIRECTORY ${PROJECT_SOURCE_DIR}/common/ DESTINATION ${CORRIDORSIM_INSTALL_INCLUDEDIR}/common
        COMPONENT dev FILES_MATCHING PATTERN "*.h" PATTERN "io" EXCLUDE)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/slam/ DESTINATION ${CORRIDORSIM_INSTALL_INCLUDEDIR}/slam
        COMPONENT dev FILES_MATCHING PATTERN "*.h")
install(FILES ${PROJECT_BINARY_DIR}/generated/sdk/slam/sdk_version.h
        DESTINATION ${CORRIDORSIM_INSTALL_INCLUDEDIR}/slam COMPONENT dev)

# What the program reads at run time: the shipped scenarios and studies, the trained detector
# models and the plot scripts (common/installation.h finds them from the libraries' folder).
install(DIRECTORY ${PROJECT_SOURCE_DIR}/scenarios ${PROJECT_SOURCE_DIR}/models
        DESTINATION ${CORRIDORSIM_INSTALL_DATADIR} COMPONENT runtime)
install(PROGRAMS ${PROJECT_SOURCE_DIR}/scripts/plot_run.py ${PROJECT_SOURCE_DIR}/scripts/plot_study.py
                 ${PROJECT_SOURCE_DIR}/scripts/plot_evaluation.py
                 ${PROJECT_SOURCE_DIR}/scripts/make_viewer.py
                 ${PROJECT_SOURCE_DIR}/scripts/make_report.py
        DESTINATION ${CORRIDORSIM_INSTALL_DATADIR}/scripts COMPONENT runtime)
# The modules those scripts import from their own folder.
install(FILES ${PROJECT_SOURCE_DIR}/scripts/system_python.py
              ${PROJECT_SOURCE_DIR}/scripts/plot_plan.py ${PROJECT_SOURCE_DIR}/scripts/plot_map.py
              ${PROJECT_SOURCE_DIR}/scripts/plot_detections.py
              ${PROJECT_SOURCE_DIR}/scripts/study_summary.py ${PROJECT_SOURCE_DIR}/scripts/pages.py
              ${PROJECT_SOURCE_DIR}/scripts/viewer_series.py
              ${PROJECT_SOURCE_DIR}/scripts/viewer_sensors.py
        DESTINATION ${CORRIDORSIM_INSTALL_DATADIR}/scripts COMPONENT runtime)
# The pages' sources (docs/viewer.md) and uPlot, which every viewer.html and report.html inlines
# (npm, pinned by viewer/package-lock.json; scripts/setup.sh installs it into viewer/node_modules).
install(FILES ${PROJECT_SOURCE_DIR}/viewer/viewer.html ${PROJECT_SOURCE_DIR}/viewer/viewer.js
              ${PROJECT_SOURCE_DIR}/viewer/viewer_plan.js ${PROJECT_SOURCE_DIR}/viewer/viewer_plots.js
              ${PROJECT_SOURCE_DIR}/viewer/viewer_frames.js
              ${PROJECT_SOURCE_DIR}/viewer/viewer_tables.js ${PROJECT_SOURCE_DIR}/viewer/page.js
              ${PROJECT_SOURCE_DIR}/viewer/viewer_sensors.js
              ${PROJECT_SOURCE_DIR}/viewer/page_head.html ${PROJECT_SOURCE_DIR}/viewer/page_header.html
              ${PROJECT_SOURCE_DIR}/viewer/page_tail.html
              ${PROJECT_SOURCE_DIR}/viewer/viewer.css ${PROJECT_SOURCE_DIR}/viewer/report.html
              ${PROJECT_SOURCE_DIR}/viewer/report.js
        DESTINATION ${CORRIDORSIM_INSTALL_DATADIR}/viewer COMPONENT runtime)
install(FILES ${CORRIDORSIM_UPLOT_DIR}/uPlot.iife.min.js ${CORRIDORSIM_UPLOT_DIR}/uPlot.min.css
              ${CORRIDORSIM_UPLOT_DIR}/../LICENSE
        DESTINATION ${CORRIDORSIM_INSTALL_DATADIR}/viewer/vendor/uplot COMPONENT runtime)

# The Python package (the protocol's reference client, docs/protocol.md) where Debian's python3
# finds it: <prefix>/lib/python3/dist-packages (corridorsim puts that folder on the PYTHONPATH of
# the programs it starts, whatever the prefix).
install(DIRECTORY ${PROJECT_SOURCE_DIR}/python/corridorsim DESTINATION ${CORRIDORSIM_INSTALL_PYTHONDIR}
        COMPONENT runtime PATTERN "__pycache__" EXCLUDE PATTERN "*.pyc" EXCLUDE)

# The documentation and the plugin example (its README is the tutorial).
install(DIRECTORY ${PROJECT_SOURCE_DIR}/docs/ DESTINATION ${CMAKE_INSTALL_DOCDIR} COMPONENT runtime)
install(FILES ${PROJECT_SOURCE_DIR}/README.md DESTINATION ${CMAKE_INSTALL_DOCDIR}
        COMPONENT runtime)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/examples/cpp_plugin
        DESTINATION ${CMAKE_INSTALL_DOCDIR}/examples COMPONENT dev
        PATTERN "build" EXCLUDE PATTERN "out" EXCLUDE)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/examples/python_pipeline
        DESTINATION ${CMAKE_INSTALL_DOCDIR}/examples COMPONENT runtime
        PATTERN "out" EXCLUDE PATTERN "__pycache__" EXCLUDE)

# The CMake package: corridorsim::sdk, corridorsim::slam and corridorsim_add_pipeline_plugin.
install(EXPORT corridorsimTargets NAMESPACE corridorsim:: DESTINATION ${CORRIDORSIM_INSTALL_CMAKEDIR}
        COMPONENT dev)
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/corridorsimConfig.cmake.in
  ${PROJECT_BINARY_DIR}/cmake/corridorsimConfig.cmake
  INSTALL_DESTINATION ${CORRIDORSIM_INSTALL_CMAKEDIR})
# SameMinorVersion: a plugin that asks for 0.2 gets any 0.2.x; the SDK ABI version only changes
# with the minor version (CMakeLists.txt).
write_basic_package_version_file(${PROJECT_BINARY_DIR}/cmake/corridorsimConfigVersion.cmake
  VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/cmake/corridorsimConfig.cmake
              ${PROJECT_BINARY_DIR}/cmake/corridorsimConfigVersion.cmake
              ${PROJECT_SOURCE_DIR}/cmake/corridorsimPlugin.cmake
        DESTINATION ${CORRIDORSIM_INSTALL_CMAKEDIR} COMPONENT dev)

# The Debian packages: `cpack --config build/CPackConfig.cmake` (docs/install.md) makes two, from
# the components above:
#   corridorsim_<version>_amd64.deb       the program, its libraries, scenarios, models, plot
#                                         scripts and docs: what a CI image needs to run studies
#   corridorsim-dev_<version>_amd64.deb   the SDK: headers, the CMake package, the example plugin
# Depends: computed by dpkg-shlibdeps from the binaries (CPACK_DEBIAN_PACKAGE_SHLIBDEPS), plus
# what no binary links and the program or the SDK needs: python3 and matplotlib for the plots;
# for the SDK, the -dev packages of exactly the headers its installed headers include: Eigen,
# OpenCV's core and ml modules and OctoMap (not libopencv-dev, which pulls every OpenCV module
# with Qt, VTK and more; the CMake package finds OpenCV and OctoMap from their files,
# cmake/corridorsimConfig.cmake.in).
set(CPACK_PACKAGE_NAME corridorsim)
set(CPACK_PACKAGE_VENDOR "corridorsim")
set(CPACK_PACKAGE_CONTACT "corridorsim developers <corridorsim@localhost>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY
    "simulation harness for corridor SLAM: synthetic corridors, a Pioneer 3-DX, cameras, scoring")
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_COMPONENTS_ALL runtime dev)
set(CPACK_DEB_COMPONENT_INSTALL ON)
set(CPACK_DEBIAN_RUNTIME_PACKAGE_NAME corridorsim)
set(CPACK_DEBIAN_DEV_PACKAGE_NAME corridorsim-dev)
set(CPACK_DEBIAN_RUNTIME_FILE_NAME DEB-DEFAULT)  # corridorsim_<version>_amd64.deb
set(CPACK_DEBIAN_DEV_FILE_NAME DEB-DEFAULT)      # corridorsim-dev_<version>_amd64.deb
set(CPACK_DEBIAN_PACKAGE_SECTION science)
set(CPACK_DEBIAN_RUNTIME_PACKAGE_SHLIBDEPS ON)
# The SDK's own libraries are in the package: dpkg-shlibdeps must not look for another.
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS_PRIVATE_DIRS ${PROJECT_BINARY_DIR}/${CMAKE_INSTALL_LIBDIR})
set(CPACK_DEBIAN_RUNTIME_PACKAGE_DEPENDS "python3, python3-matplotlib, python3-numpy")
set(CPACK_DEBIAN_DEV_PACKAGE_DEPENDS
    "corridorsim (= ${PROJECT_VERSION}), cmake (>= 3.25), g++, libeigen3-dev (>= 3.4), libopencv-core-dev (>= 4), libopencv-ml-dev (>= 4), liboctomap-dev (>= 1.9)")
set(CPACK_DEBIAN_PACKAGE_DESCRIPTION
    "corridorsim drives a simulated differential-drive robot through procedurally generated\n corridors, renders its cameras off-screen and scores SLAM pipelines against exact ground\n truth.")
set(CPACK_COMPONENT_RUNTIME_DESCRIPTION
    "simulation harness for corridor SLAM: the program, scenarios, models, plot scripts, docs")
set(CPACK_COMPONENT_DEV_DESCRIPTION
    "corridorsim's C++ SDK for pipeline plugins: headers, CMake package, example plugin")
include(CPack)
