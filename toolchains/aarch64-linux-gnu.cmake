# aarch64 Linux (an onboard-controller class) with Debian's cross compiler
# (g++-aarch64-linux-gnu). ctest runs the target's programs under qemu-user, so the
# same tests run cross: `cmake --preset aarch64 && cmake --build --preset aarch64 &&
# ctest --preset aarch64`.
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR aarch64)

set(CMAKE_C_COMPILER aarch64-linux-gnu-gcc)
set(CMAKE_CXX_COMPILER aarch64-linux-gnu-g++)

# The target's C library and loader live here (Debian's libc6-dev-arm64-cross).
set(FG_AARCH64_SYSROOT /usr/aarch64-linux-gnu)
set(CMAKE_CROSSCOMPILING_EMULATOR qemu-aarch64 -L ${FG_AARCH64_SYSROOT})

# Libraries and headers of the target only; programs of the host; packages from both,
# because the header-only ones (Eigen, nlohmann-json, CLI11) install their CMake
# files under /usr/share, which serve every architecture.
set(CMAKE_FIND_ROOT_PATH ${FG_AARCH64_SYSROOT})
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE BOTH)
