# SPDX-License-Identifier: MIT
# `cmake --install BUILD [--prefix DIR]` (README "Installing"): the headers, the libraries, the
# `tumble` command, the scenes and a CMake package, so that another project writes
#   find_package(tumble REQUIRED)                        # COMPONENTS cuda for the CUDA pipeline
#   target_link_libraries(app PRIVATE tumble::tumble)   # and tumble::cuda: no CUDA without it
# The validation harness (brute force, comparisons, the study) is not installed: it is the
# `tumble validate` command's own library.
include(CMakePackageConfigHelpers)

# tumble::tumble: the library as one target (core, CPU pipeline, cuda-host, the factory); the CUDA
# module is tumble::cuda, linked on request (core/factory/CMakeLists.txt).
add_library(tumble_all INTERFACE)
target_link_libraries(tumble_all INTERFACE tumble_core tumble_cpu tumble_pipelines)
set_target_properties(tumble_all PROPERTIES EXPORT_NAME tumble)
# tumble::flags is the build's own (BUILD_INTERFACE); but a sanitized build's libraries need the
# sanitizer runtimes, so a program linking them from the install links those too.
if(TUMBLE_SANITIZE_LINK)
  target_link_options(tumble_all INTERFACE $<INSTALL_INTERFACE:${TUMBLE_SANITIZE_LINK}>)
endif()
set(_tumble_targets tumble_all tumble_core tumble_primitives tumble_cpu tumble_gpu_host tumble_pipelines)
set_target_properties(tumble_core PROPERTIES EXPORT_NAME core)
set_target_properties(tumble_primitives PROPERTIES EXPORT_NAME primitives)
set_target_properties(tumble_cpu PROPERTIES EXPORT_NAME cpu)
set_target_properties(tumble_gpu_host PROPERTIES EXPORT_NAME cuda_host)
set_target_properties(tumble_pipelines PROPERTIES EXPORT_NAME pipelines)
if(TARGET tumble_gpu)
  set_target_properties(tumble_gpu PROPERTIES EXPORT_NAME cuda)
  list(APPEND _tumble_targets tumble_gpu)
endif()
install(TARGETS ${_tumble_targets} EXPORT tumbleTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
        INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/core/include/ ${PROJECT_SOURCE_DIR}/core/factory/include/ ${PROJECT_SOURCE_DIR}/cpu/include/
                  ${PROJECT_SOURCE_DIR}/cpu/primitives/include/ ${PROJECT_BINARY_DIR}/generated/
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR} FILES_MATCHING PATTERN "*.hpp")
# The CUDA pipeline's headers: host_pipeline.hpp always (cuda-host), cuda_pipeline.hpp with the
# CUDA module only (it declares what only that module defines; the factory, compiled here, refers to it weakly).
if(TARGET tumble_gpu)
  set(_tumble_gpu_headers PATTERN "*.hpp")
else()
  set(_tumble_gpu_headers PATTERN "host_pipeline.hpp")
endif()
install(DIRECTORY ${PROJECT_SOURCE_DIR}/gpu/include/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}
        FILES_MATCHING ${_tumble_gpu_headers})
if(TARGET tumble)
  install(TARGETS tumble RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
endif()
# The scenes with the files they name (the meshes) and the scripts that wrote those.
install(DIRECTORY ${PROJECT_SOURCE_DIR}/scenes DESTINATION ${CMAKE_INSTALL_DATADIR}/tumble
        FILES_MATCHING PATTERN "*.toml" PATTERN "*.stl" PATTERN "*.obj" PATTERN "*.py")
install(FILES ${PROJECT_SOURCE_DIR}/examples/hello_spheres.cpp ${PROJECT_SOURCE_DIR}/examples/run_scene.cpp
        DESTINATION ${CMAKE_INSTALL_DOCDIR}/examples)

set(_cmake_dir ${CMAKE_INSTALL_LIBDIR}/cmake/tumble)
install(EXPORT tumbleTargets NAMESPACE tumble:: DESTINATION ${_cmake_dir})
set(TUMBLE_PACKAGE_HAS_CUDA ${TUMBLE_HAS_CUDA})
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/tumbleConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/tumbleConfig.cmake INSTALL_DESTINATION ${_cmake_dir})
write_basic_package_version_file(${PROJECT_BINARY_DIR}/tumbleConfigVersion.cmake COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/tumbleConfig.cmake ${PROJECT_BINARY_DIR}/tumbleConfigVersion.cmake
        DESTINATION ${_cmake_dir})

# The package test: install into the build folder, then configure, build and run
# examples/hello_spheres.cpp as another project would (examples/installed/).
if(TUMBLE_BUILD_TESTS AND TUMBLE_BUILD_EXAMPLES)
  add_test(NAME install_package
           COMMAND ${CMAKE_COMMAND} -DBUILD=${PROJECT_BINARY_DIR} -DSOURCE=${PROJECT_SOURCE_DIR}
                   -DGENERATOR=${CMAKE_GENERATOR} -DCXX=${CMAKE_CXX_COMPILER}
                   -DEXPECTED=$<TARGET_FILE:hello_spheres> -DHAS_CUDA=${TUMBLE_HAS_CUDA}
                   "-DPYTHON=$<$<TARGET_EXISTS:tumble_python>:${TUMBLE_PYTHON_FOR_TESTS}>"
                   -DPYTHON_DIR=${TUMBLE_PYTHON_INSTALL_DIR} -P ${PROJECT_SOURCE_DIR}/cmake/test_install.cmake)
  set_tests_properties(install_package PROPERTIES LABELS examples TIMEOUT 600)
endif()
