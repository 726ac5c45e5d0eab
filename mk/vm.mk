# ---------------------------------------------------------------------------------------------------------
# VM tier (test/vm): Debian's arm64 kernel under qemu-system-aarch64 (virt, software emulation) runs the
# AArch64 unit tests natively and the device checks (vivid V4L2 loop-back, vivid fbdev, PL061 GPIO pulsed
# from the monitor). Results land next to the boards' for test/summary.sh.
VM_ROOT := $(BUILD_ROOT)/vm
VM_RESULTS := $(BUILD_ROOT)/vmtest$(SAN_SUFFIX)/test-results
DEPS_VMTEST := qemu-system-arm cpio kmod ?libgpiod-dev:arm64 ?libdrm-dev:arm64
TEST_TIERS += vmtest-tier
TEST_TIER_RESULTS += $(VM_RESULTS)
VM_DEVICE_TEST := $(O)/test/vm/test_vm_devices
VM_DRM_TEST := $(O)/test/vm/test_vm_drm
# Variables the unit tests read (as exported to them on the host); directories among their values are shared
# into the guest read-only at the same paths.
VM_TEST_ENV := HZ_SCENES_DIR HZ_SCENES_UNPACK
# In the VM (software-emulated CPU, ~10x slower than qemu user mode) run the unit tests that need no scene files
# and take seconds; the heavy ones (BVH builds over 10^5..10^6 triangles, whole-image corruption sweeps,
# rendered sequences; tagged "hz-test: no-vm") already run on the same AArch64 binaries under qemu-aarch64 in
# the board stage.
VM_TEST_BINS := $(filter-out $(TESTS_NO_VM:%=$(O)/test/unit/%),$(TEST_BINS))

vmtest: deps ## boot Debian's arm64 kernel in qemu-system-aarch64: AArch64 unit tests, V4L2 loop-back, GPIO capture
	$(Q)$(MAKE) --no-print-directory vmtest-tier
	$(Q)sh test/summary.sh $(VM_RESULTS)

vmtest-tier:
	$(Q)$(MAKE) --no-print-directory BOARD=aarch64-generic O=$(BUILD_ROOT)/aarch64-generic$(SAN_SUFFIX) vmtest-board

# Runs with BOARD=aarch64-generic (see vmtest-tier): its test binaries, plus a static hzrt and init. The build
# step is apart so that make test builds it with every other tier before the lanes run.
VM_GPIOD2_LOG := $(VM_ROOT)/gpiod2-vm-build.log
VM_HZRT := $(VM_ROOT)/static/bin/hzrt
vmtest-build: tests $(VM_DEVICE_TEST) $(VM_DRM_TEST) $(VM_ROOT)/init $(VM_HZRT)
	$(Q)$(MAKE) --no-print-directory $(VM_GPIOD2_TEST) >$(VM_GPIOD2_LOG) 2>&1 || rm -f $(VM_GPIOD2_TEST)
vmtest-board: vmtest-build
	$(Q)VM_ENV="$(foreach v,$(VM_TEST_ENV),$(v)=$($(v)))" sh test/vm/run.sh $(VM_RESULTS) $(VM_ROOT)/kernel \
		$(VM_ROOT)/init $(VM_HZRT) $(VM_DEVICE_TEST) $(VM_TEST_BINS) \
		$(VM_DRM_TEST) $$([ -x $(VM_GPIOD2_TEST) ] && echo $(VM_GPIOD2_TEST))
	$(Q)[ -x $(VM_GPIOD2_TEST) ] || { echo "  FAIL  vm-aarch64 test_vm_gpiod2: libgpiod 2 could not be fetched or linked (see $(VM_GPIOD2_LOG))"; \
		echo "vm-aarch64/test_vm_gpiod2 0 1 0" >$(VM_RESULTS)/test_vm_gpiod2.res; }

include tools/gpiod2/gpiod2.mk

$(VM_DEVICE_TEST): test/vm/test_vm_devices.c $(PORT_LIB) $(LIB)
	@mkdir -p $(dir $@)
	$(call msg,CCLD,$@)$(CC) $(TEST_CFLAGS) $(PORT_DEFS) -Iport/linux $(DEPFLAGS) $(LDFLAGS_ALL) -o $@ $< \
		$(PORT_LIB) $(LIB) $(TEST_LIBS) $(PORT_LIBS)

# The DRM/KMS sink on virtio-gpu: flips, their events, a screendump compared byte for byte (test/vm/test_vm_drm.c).
$(VM_DRM_TEST): test/vm/test_vm_drm.c $(PORT_LIB) $(LIB)
	@mkdir -p $(dir $@)
	$(call msg,CCLD,$@)$(CC) $(TEST_CFLAGS) $(PORT_DEFS) -Iport/linux $(DEPFLAGS) $(LDFLAGS_ALL) -o $@ $< \
		$(PORT_LIB) $(LIB) $(TEST_LIBS) $(PORT_LIBS)

# The guest's hzrt is static (its initramfs has no arm64 libraries for it): aarch64-generic's own objects linked
# with -static, no second compile. A sanitizer build's objects need the sanitizer runtime, which does not link
# statically: with SAN=1 the static hzrt is a plain build of its own.
ifeq ($(abspath $(O)),$(abspath $(VM_ROOT)/static))
# (the SAN=1 sub-make below: there $(HZRT) is the static hzrt)
else ifeq ($(SAN),)
$(VM_HZRT): $(HZRT_LINK)
	@mkdir -p $(dir $@)
	$(call msg,LD,$@)$(CC) $(LDFLAGS_ALL) -static -o $@ $(HZRT_LINK) $(PORT_LIBS)
else
.PHONY: $(VM_HZRT)
$(VM_HZRT):
	$(Q)$(MAKE) --no-print-directory BOARD=aarch64-generic O=$(VM_ROOT)/static BOARD_LDFLAGS=-static SAN= all
endif

$(VM_ROOT)/init: test/vm/init.c
	@mkdir -p $(dir $@)
	$(call msg,CCLD,$@)aarch64-linux-gnu-gcc $(WARN) -O2 -static -o $@ $<
