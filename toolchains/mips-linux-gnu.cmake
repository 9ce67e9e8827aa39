# 32-bit MIPS Linux, big-endian (MIPS32r2, hard float), with Debian's cross compiler
# (g++-mips-linux-gnu): the big-endian target, whose byte order many controllers
# share. ctest runs the target's programs under qemu-user: `cmake --preset mips &&
# cmake --build --preset mips && ctest --preset mips` (scripts/cross.sh).
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR mips)

set(CMAKE_C_COMPILER mips-linux-gnu-gcc)
set(CMAKE_CXX_COMPILER mips-linux-gnu-g++)

# The target's C library and loader (Debian's libc6-dev-mips-cross).
set(FG_MIPS_SYSROOT /usr/mips-linux-gnu)
set(CMAKE_CROSSCOMPILING_EMULATOR qemu-mips -L ${FG_MIPS_SYSROOT})

# As for aarch64: the target's libraries and headers, the host's programs, packages
# from both (the header-only ones install their CMake files under /usr/share).
set(CMAKE_FIND_ROOT_PATH ${FG_MIPS_SYSROOT})
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE BOTH)
