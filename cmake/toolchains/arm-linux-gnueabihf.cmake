# Cross build for 32-bit ARM (armhf); tests run under qemu-arm.
set(MOTIONBUS_CROSS_TRIPLE arm-linux-gnueabihf)
set(MOTIONBUS_CROSS_PROCESSOR arm)
set(MOTIONBUS_CROSS_QEMU qemu-arm)
include("${CMAKE_CURRENT_LIST_DIR}/qemu-linux-cross.cmake")
