# SPDX-License-Identifier: BSD-3-Clause
# Installs this build into a scratch prefix, moves that prefix elsewhere (the install tree is
# relocatable), then configures, builds and runs the downstream example against the moved package
# (find_package(SurfaceLOD)), and builds Examples/ standalone against it. Any failure fails the test.
foreach (var BUILD_DIR SOURCE_DIR WORK_DIR)
  if (NOT DEFINED ${var})
    message(FATAL_ERROR "${var} not set")
  endif ()
endforeach ()
file(REMOVE_RECURSE "${WORK_DIR}")
set(staged_prefix "${WORK_DIR}/install")
set(prefix "${WORK_DIR}/moved/install")
function (run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE result OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if (NOT result EQUAL 0)
    message(FATAL_ERROR "failed (${result}): ${ARGN}\n${out}\n${err}")
  endif ()
  message(STATUS "${out}")
endfunction ()
run(${CMAKE_COMMAND} --install "${BUILD_DIR}" --prefix "${staged_prefix}")
file(MAKE_DIRECTORY "${WORK_DIR}/moved")
file(RENAME "${staged_prefix}" "${prefix}")
if (NOT EXISTS "${prefix}/lib/cmake/SurfaceLOD/SurfaceLODConfig.cmake")
  message(FATAL_ERROR "no package config installed")
endif ()
if (NOT EXISTS "${prefix}/include/surfacelod/vtkSurfaceDeviation.h")
  message(FATAL_ERROR "headers not installed")
endif ()
run(${CMAKE_COMMAND} -S "${SOURCE_DIR}/Examples/Downstream" -B "${WORK_DIR}/build" -G Ninja
  -DCMAKE_BUILD_TYPE=Release "-DCMAKE_PREFIX_PATH=${prefix}")
run(${CMAKE_COMMAND} --build "${WORK_DIR}/build")
run("${WORK_DIR}/build/measure_decimation")
# (The installed CLI and Python package are run from a moved prefix by Install.RelocatedPrefix.)
# The examples build standalone against the moved package with the same CMakeLists as in the tree.
run(${CMAKE_COMMAND} -S "${SOURCE_DIR}/Examples" -B "${WORK_DIR}/examples" -G Ninja
  -DCMAKE_BUILD_TYPE=Release "-DCMAKE_PREFIX_PATH=${prefix}")
run(${CMAKE_COMMAND} --build "${WORK_DIR}/examples")
