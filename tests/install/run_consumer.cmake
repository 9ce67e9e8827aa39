# install.find_package_consumer: the build installed into a fresh prefix, the consumer
# project (consumer/) configured and built against that prefix alone with the build's
# compilers and generator, then both programs run; each must print "ok".
#   cmake -DFG_BUILD_DIR=... -DFG_WORK_DIR=... -DFG_GENERATOR=... -DFG_MAKE_PROGRAM=...
#         -DFG_C_COMPILER=... -DFG_CXX_COMPILER=... -DFG_BUILD_TYPE=... [-DFG_LINK_FLAGS=...]
#         -P run_consumer.cmake
cmake_minimum_required(VERSION 3.22)
foreach(var FG_BUILD_DIR FG_WORK_DIR FG_GENERATOR FG_C_COMPILER FG_CXX_COMPILER)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "run_consumer.cmake: ${var} is not set")
  endif()
endforeach()
set(prefix ${FG_WORK_DIR}/prefix)
set(build ${FG_WORK_DIR}/build)
file(REMOVE_RECURSE ${FG_WORK_DIR})

function(run what)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${what} failed (${rc}):\n${out}\n${err}")
  endif()
  set(run_output "${out}" PARENT_SCOPE)
endfunction()

run("install" ${CMAKE_COMMAND} --install ${FG_BUILD_DIR} --prefix ${prefix})
message(STATUS "installed into ${prefix}")

# Only the prefix: no package registry, so nothing but this install can be found.
run("configure the consumer"
    ${CMAKE_COMMAND} -S ${CMAKE_CURRENT_LIST_DIR}/consumer -B ${build} -G ${FG_GENERATOR}
    -DCMAKE_MAKE_PROGRAM=${FG_MAKE_PROGRAM} -DCMAKE_C_COMPILER=${FG_C_COMPILER}
    -DCMAKE_CXX_COMPILER=${FG_CXX_COMPILER} -DCMAKE_BUILD_TYPE=${FG_BUILD_TYPE} -DCMAKE_PREFIX_PATH=${prefix}
    -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF -DCMAKE_EXE_LINKER_FLAGS=${FG_LINK_FLAGS})
string(REGEX MATCH "forcegrasp [^\n]*" found "${run_output}")
message(STATUS "${found}")
if(NOT found MATCHES " from ${prefix}/")
  message(FATAL_ERROR "the consumer found another forcegrasp: ${found}")
endif()
run("build the consumer" ${CMAKE_COMMAND} --build ${build})

foreach(program planner_consumer c_api_consumer)
  run("${program}" ${build}/${program})
  message(STATUS "${program}:\n${run_output}")
  if(NOT run_output MATCHES "(^|\n)ok\n")
    message(FATAL_ERROR "${program} did not print ok")
  endif()
endforeach()
