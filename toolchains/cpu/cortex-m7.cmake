# Cortex-M7 with the double-precision FPU (fpv5-d16), hard-float ABI. Included by
# toolchains/arm-none-eabi.cmake. Function and data sections let the linker drop
# what the image does not use (-Wl,--gc-sections).
set(FG_CPU_FLAGS "-mcpu=cortex-m7 -mthumb -mfpu=fpv5-d16 -mfloat-abi=hard")
set(CMAKE_C_FLAGS_INIT "${FG_CPU_FLAGS} -ffunction-sections -fdata-sections")
set(CMAKE_CXX_FLAGS_INIT "${FG_CPU_FLAGS} -ffunction-sections -fdata-sections")
