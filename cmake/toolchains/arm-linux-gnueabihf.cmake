# Cross build for arm-linux-gnueabihf; the test suite runs under qemu-arm (qemu-user) through
# CMAKE_CROSSCOMPILING_EMULATOR. Binaries are linked statically so no target sysroot is needed.
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR arm)
set(CMAKE_CXX_COMPILER arm-linux-gnueabihf-g++)
set(CMAKE_FIND_ROOT_PATH /usr/arm-linux-gnueabihf)
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE ONLY)
set(CMAKE_EXE_LINKER_FLAGS_INIT "-static")
find_program(MOTIONBUS_QEMU qemu-arm REQUIRED)
set(CMAKE_CROSSCOMPILING_EMULATOR "${MOTIONBUS_QEMU}")
