# install.consumer_projects: the build installed into a fresh prefix, the consumer
# project (consumer/) configured and built against that prefix alone with the build's
# compilers and generator, then both programs run; each must print "ok". Then the same
# two programs built by the compilers alone with pkg-config's flags for forcegrasp.pc.
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

# pkg-config: the flags of the installed forcegrasp.pc alone (its prefix from its place).
find_program(PKG_CONFIG pkg-config REQUIRED)
set(ENV{PKG_CONFIG_PATH} "")
file(GLOB pc_files ${prefix}/lib*/pkgconfig/forcegrasp.pc ${prefix}/lib/*/pkgconfig/forcegrasp.pc)
list(LENGTH pc_files n_pc)
if(NOT n_pc EQUAL 1)
  message(FATAL_ERROR "expected one installed forcegrasp.pc, found: ${pc_files}")
endif()
get_filename_component(pc_dir ${pc_files} DIRECTORY)
set(ENV{PKG_CONFIG_PATH} ${pc_dir})
run("pkg-config --cflags" ${PKG_CONFIG} --cflags forcegrasp)
string(STRIP "${run_output}" pc_cflags)
separate_arguments(pc_cflags UNIX_COMMAND "${pc_cflags}")
run("pkg-config --libs" ${PKG_CONFIG} --libs forcegrasp)
string(STRIP "${run_output}" pc_libs)
separate_arguments(pc_libs UNIX_COMMAND "${pc_libs}")
message(STATUS "pkg-config forcegrasp: ${pc_cflags} ${pc_libs}")
set(link_flags "")
if(FG_LINK_FLAGS)
  separate_arguments(link_flags UNIX_COMMAND "${FG_LINK_FLAGS}")
endif()
set(src ${CMAKE_CURRENT_LIST_DIR}/consumer)
run("cc the C consumer" ${FG_C_COMPILER} -std=c99 ${pc_cflags} ${src}/c_api_consumer.c -o ${build}/c_api_pc ${pc_libs}
    ${link_flags})
run("c++ the C++ consumer" ${FG_CXX_COMPILER} -std=c++17 ${pc_cflags} ${src}/planner_consumer.cpp -o
    ${build}/planner_pc ${pc_libs} ${link_flags})
foreach(program planner_pc c_api_pc)
  run("${program}" ${build}/${program})
  if(NOT run_output MATCHES "(^|\n)ok\n")
    message(FATAL_ERROR "${program} did not print ok:\n${run_output}")
  endif()
endforeach()
message(STATUS "the consumers built with pkg-config's flags run: ok")
