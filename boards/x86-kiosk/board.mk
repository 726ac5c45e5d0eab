# x86-kiosk — an x86-64 kiosk PC driving a 1280x800 120 Hz panel through fbdev: AVX2, native backend only
# (the firmware-like build carries no Embree).
BOARD_ARCH := x86_64
BOARD_CROSS_COMPILE :=
BOARD_CFLAGS := -march=x86-64-v3 -mtune=generic
BOARD_LDFLAGS :=
BOARD_SIMD := avx2
BOARD_ACCEL := native
BOARD_PORTS := linux timing drm fbdev
BOARD_DEPS := gcc make libc6-dev binutils libdrm-dev
BOARD_TEST_LAUNCHER :=
BOARD_TEST_DEPS := libcmocka-dev
# Scenes `make test` checks this board with (test/boards/fit.sh): the default mode fits the display and the default
# command (`hzrt show`) runs it there.
BOARD_FIT_SCENES := builtin conference
