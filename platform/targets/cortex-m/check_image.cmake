# Post-link check of the bare-metal image (cmake -P, from platform/targets/cortex-m/CMakeLists.txt):
# fails, and deletes the ELF, if it holds any symbol of the heap, the exception runtime
# or RTTI; then prints the section sizes and the planner workspace.
# Inputs: NM, SIZE (arm-none-eabi-nm / -size), ELF.
execute_process(COMMAND ${NM} --defined-only ${ELF} OUTPUT_VARIABLE symbols RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "${NM} failed on ${ELF}")
endif()
# Mangled names: operator new/delete (_Znw*, _Zna*, _ZdlPv*, _Zda*), typeinfo (_ZTI*)
# and its names (_ZTS*); C names of the heap and of the exception and unwind runtime.
set(forbidden "^(_?malloc|_?free|_?calloc|_?realloc|_malloc_r|_free_r|_calloc_r|_realloc_r|_sbrk|_sbrk_r|_Znw.*|_Zna.*|_Zdl.*|_Zda.*|_ZTI.*|_ZTS.*|__cxa_throw|__cxa_rethrow|__cxa_allocate_exception|__cxa_begin_catch|__cxa_end_catch|__gxx_personality.*|_Unwind_.*|__aeabi_unwind_cpp_pr.*)$")
set(found "")
string(REPLACE "\n" ";" lines "${symbols}")
foreach(line IN LISTS lines)
  string(REGEX REPLACE "^[0-9a-fA-F]* *[A-Za-z] " "" name "${line}")
  if(name MATCHES "${forbidden}")
    list(APPEND found "${name}")
  endif()
endforeach()
if(found)
  file(REMOVE ${ELF})
  list(REMOVE_DUPLICATES found)
  list(JOIN found " " found)
  message(FATAL_ERROR "fg_m7_image: heap, exception or RTTI symbols linked in: ${found}\n"
                      "(see the .map file beside the image for the object that pulled each one in)")
endif()

execute_process(COMMAND ${SIZE} ${ELF} OUTPUT_VARIABLE size_report)
message(STATUS "fg_m7_image: no heap, exception or RTTI symbols\n${size_report}")
# The static planner's symbol size is sizeof(fg::Planner).
execute_process(COMMAND ${NM} -S -C ${ELF} OUTPUT_VARIABLE sized)
if(sized MATCHES "[0-9a-f]+ ([0-9a-f]+) [bBdD] [^\n]*g_planner")
  math(EXPR bytes "0x${CMAKE_MATCH_1}" OUTPUT_FORMAT DECIMAL)
  math(EXPR kib "${bytes} / 1024")
  message(STATUS "fg_m7_image: sizeof(fg::Planner) = ${bytes} bytes (${kib} KiB)")
endif()
