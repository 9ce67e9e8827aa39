# Bare-metal Arm (arm-none-eabi-gcc, newlib) for the Cortex-M images. CPU flags are
# not here: a cpu/<core>.cmake file adds them (FG_CPU, default cortex-m7), so one
# toolchain serves every core.
set(CMAKE_SYSTEM_NAME Generic)
set(CMAKE_SYSTEM_PROCESSOR arm)

set(CMAKE_C_COMPILER arm-none-eabi-gcc)
set(CMAKE_CXX_COMPILER arm-none-eabi-g++)
set(CMAKE_SIZE arm-none-eabi-size CACHE FILEPATH "")
set(CMAKE_NM arm-none-eabi-nm CACHE FILEPATH "")

# There is no OS to link a test program against: CMake's compiler checks build a
# static library instead of an executable.
set(CMAKE_TRY_COMPILE_TARGET_TYPE STATIC_LIBRARY)

set(FG_CPU "cortex-m7" CACHE STRING "Core of the bare-metal target: a file toolchains/cpu/<FG_CPU>.cmake")
list(APPEND CMAKE_TRY_COMPILE_PLATFORM_VARIABLES FG_CPU)  # the compiler checks see the same core
include(${CMAKE_CURRENT_LIST_DIR}/cpu/${FG_CPU}.cmake)

# The C++ runtime of the image: no exception, RTTI, thread-safe-static or atexit
# machinery (each pulls in code that allocates or unwinds).
set(CMAKE_CXX_FLAGS_INIT "${CMAKE_CXX_FLAGS_INIT} -fno-exceptions -fno-rtti -fno-threadsafe-statics -fno-use-cxa-atexit")
# newlib-nano; nosys.specs turns the system calls nothing uses into stubs instead of
# link errors; unused sections are dropped.
set(CMAKE_EXE_LINKER_FLAGS_INIT "--specs=nano.specs --specs=nosys.specs -Wl,--gc-sections")

# Target libraries and headers from the toolchain only; packages from the host too:
# Eigen is header-only and installs its CMake files under /usr/share.
set(CMAKE_FIND_ROOT_PATH /usr/lib/arm-none-eabi)
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE BOTH)
