# aarch64 Linux (an onboard-controller class) with Debian's cross compiler
# (g++-aarch64-linux-gnu). ctest runs the target's programs under qemu-user, so the
# same tests run cross: `cmake --preset aarch64 && cmake --build --preset aarch64 &&
# ctest --preset aarch64`.
set(CMAKE_SYSTEM_PROCESSOR aarch64)
set(FG_CROSS_TRIPLET aarch64-linux-gnu)
set(FG_CROSS_QEMU qemu-aarch64)
include(${CMAKE_CURRENT_LIST_DIR}/linux-qemu-user.cmake)
