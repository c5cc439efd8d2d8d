# Cross build for big-endian s390x; tests run under qemu-s390x.
set(MOTIONBUS_CROSS_TRIPLE s390x-linux-gnu)
set(MOTIONBUS_CROSS_PROCESSOR s390x)
set(MOTIONBUS_CROSS_QEMU qemu-s390x)
include("${CMAKE_CURRENT_LIST_DIR}/qemu-linux-cross.cmake")
