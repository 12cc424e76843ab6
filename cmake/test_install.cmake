# SPDX-License-Identifier: MIT
# The install_package test (cmake/tumble_install.cmake): install BUILD into BUILD/install-test,
# build examples/installed against it, and check that its hello_spheres prints what the build's
# own hello_spheres (EXPECTED) prints: the same library, the same bits.
set(prefix ${BUILD}/install-test/prefix)
set(out ${BUILD}/install-test/consumer)
file(REMOVE_RECURSE ${BUILD}/install-test)
execute_process(COMMAND ${CMAKE_COMMAND} --install ${BUILD} --prefix ${prefix} RESULT_VARIABLE rc OUTPUT_QUIET)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "cmake --install failed (${rc})")
endif()
foreach(f bin/tumble include/tumble/pipeline.hpp include/tumble/factory.hpp include/tumble/run.hpp include/tumble/config.hpp include/tumble/cpu/cpu_pipeline.hpp
          share/tumble/scenes/molecules.toml)
  if(NOT EXISTS ${prefix}/${f})
    message(FATAL_ERROR "not installed: ${f}")
  endif()
endforeach()
execute_process(COMMAND ${CMAKE_COMMAND} -S ${SOURCE}/examples/installed -B ${out} -G ${GENERATOR}
                        -DCMAKE_CXX_COMPILER=${CXX} -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH=${prefix}
                RESULT_VARIABLE rc OUTPUT_VARIABLE log ERROR_VARIABLE log)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "configuring examples/installed against the package failed:\n${log}")
endif()
execute_process(COMMAND ${CMAKE_COMMAND} --build ${out} RESULT_VARIABLE rc OUTPUT_VARIABLE log ERROR_VARIABLE log)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "building examples/installed against the package failed:\n${log}")
endif()
execute_process(COMMAND ${out}/hello_spheres OUTPUT_VARIABLE got RESULT_VARIABLE rc)
execute_process(COMMAND ${EXPECTED} OUTPUT_VARIABLE want)
if(NOT rc EQUAL 0 OR NOT got STREQUAL want)
  message(FATAL_ERROR "hello_spheres built against the package printed\n  ${got}the build's own printed\n  ${want}")
endif()
# A CPU program built against the package links no CUDA (issue 35, item 5): neither the CUDA
# runtime nor the module, and asking it for the cuda backend says how to get it.
file(STRINGS ${out}/hello_spheres cuda_strings REGEX "cudaGetDeviceCount|libcudart")  # (the weak reference is named, unresolved)
if(cuda_strings)
  message(FATAL_ERROR "hello_spheres, linked with tumble::tumble alone, holds CUDA: ${cuda_strings}")
endif()
execute_process(COMMAND ${out}/hello_spheres --backend=cuda RESULT_VARIABLE rc ERROR_VARIABLE why OUTPUT_QUIET)
if(HAS_CUDA)
  set(want "not linked with tumble's CUDA module \\(link tumble::cuda: find_package\\(tumble COMPONENTS cuda\\)")
else()
  set(want "this build of tumble has no CUDA pipeline")
endif()
if(rc EQUAL 0 OR NOT why MATCHES "${want}")
  message(FATAL_ERROR "hello_spheres --backend=cuda without tumble::cuda (status ${rc}) said: ${why}(expected: ${want})")
endif()
# With COMPONENTS cuda: the package built with CUDA gives tumble::cuda, whose program has the
# backend (here "no device" at most: it asks the CUDA runtime); one built without is not found.
execute_process(COMMAND ${CMAKE_COMMAND} -S ${SOURCE}/examples/installed -B ${out}-cuda -G ${GENERATOR}
                        -DCMAKE_CXX_COMPILER=${CXX} -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH=${prefix} -DWITH_CUDA=ON
                RESULT_VARIABLE rc OUTPUT_VARIABLE log ERROR_VARIABLE log)
if(HAS_CUDA)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "configuring examples/installed with COMPONENTS cuda failed:\n${log}")
  endif()
  execute_process(COMMAND ${CMAKE_COMMAND} --build ${out}-cuda --target hello_spheres RESULT_VARIABLE rc OUTPUT_VARIABLE log ERROR_VARIABLE log)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "building hello_spheres with tumble::cuda failed:\n${log}")
  endif()
  execute_process(COMMAND ${out}-cuda/hello_spheres --backend=cuda RESULT_VARIABLE rc ERROR_VARIABLE why OUTPUT_VARIABLE ran)
  if(why MATCHES "not linked with" OR NOT (rc EQUAL 0 OR why MATCHES "CUDA"))
    message(FATAL_ERROR "hello_spheres with tumble::cuda has no cuda backend (status ${rc}): ${ran}${why}")
  endif()
elseif(rc EQUAL 0 OR NOT log MATCHES "built without its CUDA module" OR log MATCHES ";[ \n]*rebuild it")
  message(FATAL_ERROR "COMPONENTS cuda of a package without CUDA (status ${rc}) said:\n${log}")
endif()
# run_scene (docs/cpp.md), built against the package, runs the installed scene of pours alone:
# its bodies enter (the run driver, tumble::Run).
execute_process(COMMAND ${out}/run_scene ${prefix}/share/tumble/scenes/pour.toml --steps 1000
                OUTPUT_VARIABLE ran RESULT_VARIABLE rc ERROR_VARIABLE log)
if(NOT rc EQUAL 0 OR NOT ran MATCHES "step 1000 .* ([1-9][0-9]*) bodies")
  message(FATAL_ERROR "run_scene built against the package failed (${rc}) on the installed pour.toml:\n${ran}${log}")
endif()
# The installed command runs every installed scene for a step (a mesh scene finds its mesh file).
# Not the two large benchmark lattices: bench-16k is the same generator at a size a test affords.
file(GLOB installed_scenes ${prefix}/share/tumble/scenes/*.toml)
list(FILTER installed_scenes EXCLUDE REGEX "bench-(128|960)k[.]toml$")
list(LENGTH installed_scenes n)
if(n LESS 10)
  message(FATAL_ERROR "only ${n} scenes installed in ${prefix}/share/tumble/scenes")
endif()
foreach(scene IN LISTS installed_scenes)
  execute_process(COMMAND ${prefix}/bin/tumble run ${scene} --steps 1 -q  # (molecules.toml records: here)
                  WORKING_DIRECTORY ${BUILD}/install-test RESULT_VARIABLE rc OUTPUT_QUIET ERROR_VARIABLE log)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "the installed tumble failed on the installed ${scene}:\n${log}")
  endif()
endforeach()
# The installed Python module imports and runs an installed scene (when it was built).
if(PYTHON)
  execute_process(COMMAND ${CMAKE_COMMAND} -E env PYTHONPATH=${prefix}/${PYTHON_DIR} ${PYTHON} -c
                          "import tumble; s = tumble.Simulation(tumble.Scene.load('${prefix}/share/tumble/scenes/spheres.toml')); s.step(5); print(tumble.__file__)"
                  RESULT_VARIABLE rc OUTPUT_VARIABLE where ERROR_VARIABLE log)
  if(NOT rc EQUAL 0 OR NOT where MATCHES "^${prefix}/")
    message(FATAL_ERROR "the installed Python module failed (${rc}): ${where}${log}")
  endif()
endif()
message(STATUS "installed, built against, same output: ${got}")
