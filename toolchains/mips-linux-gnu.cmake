# 32-bit MIPS Linux, big-endian (MIPS32r2, hard float), with Debian's cross compiler
# (g++-mips-linux-gnu): the big-endian target, whose byte order many controllers
# share. ctest runs the target's programs under qemu-user: `cmake --preset mips &&
# cmake --build --preset mips && ctest --preset mips` (scripts/cross.sh).
set(CMAKE_SYSTEM_PROCESSOR mips)
set(FG_CROSS_TRIPLET mips-linux-gnu)
set(FG_CROSS_QEMU qemu-mips)
include(${CMAKE_CURRENT_LIST_DIR}/linux-qemu-user.cmake)
