# The common part of the Linux cross toolchains: included by a toolchain file that sets
# FG_CROSS_TRIPLET (Debian's GNU triplet, e.g. aarch64-linux-gnu) and FG_CROSS_QEMU
# (the qemu-user emulator, e.g. qemu-aarch64).
set(CMAKE_SYSTEM_NAME Linux)

set(CMAKE_C_COMPILER ${FG_CROSS_TRIPLET}-gcc)
set(CMAKE_CXX_COMPILER ${FG_CROSS_TRIPLET}-g++)

# The target's C library and loader live here (Debian's libc6-dev-<arch>-cross); ctest
# (and GoogleTest's test discovery) runs the target's programs under the emulator.
set(FG_CROSS_SYSROOT /usr/${FG_CROSS_TRIPLET})
set(CMAKE_CROSSCOMPILING_EMULATOR ${FG_CROSS_QEMU} -L ${FG_CROSS_SYSROOT})

# Libraries and headers of the target only; programs of the host; packages from both,
# because the header-only ones (Eigen, nlohmann-json, CLI11) install their CMake
# files under /usr/share, which serve every architecture.
set(CMAKE_FIND_ROOT_PATH ${FG_CROSS_SYSROOT})
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE BOTH)
