# libgpiod 2 (Debian 13's libgpiod-dev 2.x; tools/gpiod2/fetch.sh fetches it into the build folder, nothing is
# installed): the v2 path of port/linux/gpio.c compiled for BOARD and linked with that package's static library
# into test_gpiod2 (every tested board) and, for aarch64, test_vm_gpiod2 (the VM's GPIO edge test). Debian 12's
# libgpiod 1.6 stays the default build. `make test` records a failed check when the package cannot be fetched.
GPIOD2_DIR := $(BUILD_ROOT)/gpiod2
GPIOD2_DEB_ARCH := $(if $(filter aarch64,$(BOARD_ARCH)),arm64,amd64)
GPIOD2_TREE := $(GPIOD2_DIR)/$(GPIOD2_DEB_ARCH)
GPIOD2_LIB := $(GPIOD2_TREE)/usr/lib/$(BOARD_ARCH)-linux-gnu/libgpiod.a
GPIOD2_OBJ := $(O)/gpiod2/gpio.o
GPIOD2_TEST := $(O)/test/unit/test_gpiod2
VM_GPIOD2_TEST := $(O)/test/vm/test_vm_gpiod2
GPIOD2_LIBS := $(filter-out -lgpiod,$(PORT_LIBS)) $(GPIOD2_LIB)

$(GPIOD2_TREE)/.ok:
	$(call msg,FETCH,libgpiod-dev:$(GPIOD2_DEB_ARCH) (Debian trixie) into $(GPIOD2_TREE))sh tools/gpiod2/fetch.sh \
		$(GPIOD2_DIR) $(GPIOD2_DEB_ARCH)

$(GPIOD2_OBJ): port/linux/gpio.c $(GPIOD2_TREE)/.ok
	@mkdir -p $(dir $@)
	$(call msg,CC,$@ (libgpiod $(shell cat $(GPIOD2_TREE)/.ok 2>/dev/null)))$(CC) $(HOSTED_CFLAGS) $(PORT_DEFS) \
		-DHZ_PORT_GPIO=1 -Iport/linux -I$(GPIOD2_TREE)/usr/include -DHZ_LIBGPIOD_MAJOR=2 \
		-DHZ_LIBGPIOD_VERSION='"$(shell sed -n 's/^Version: *//p' $(GPIOD2_TREE)/usr/lib/$(BOARD_ARCH)-linux-gnu/pkgconfig/libgpiod.pc 2>/dev/null)"' \
		-c $< -o $@

# gpio.o v2 comes before the port library, so the archive's v1 gpio.o (if any) is never pulled in.
$(GPIOD2_TEST): test/unit/test_gpiod2.c $(GPIOD2_OBJ) $(PORT_LIB) $(LIB)
	@mkdir -p $(dir $@)
	$(call msg,CCLD,$@)$(CC) $(TEST_CFLAGS) $(PORT_DEFS) -DHZ_PORT_GPIO=1 -Iport/linux $(LDFLAGS_ALL) -o $@ $< \
		$(GPIOD2_OBJ) $(PORT_LIB) $(LIB) $(TEST_LIBS) $(GPIOD2_LIBS) -ldl

$(VM_GPIOD2_TEST): test/vm/test_vm_devices.c $(GPIOD2_OBJ) $(PORT_LIB) $(LIB)
	@mkdir -p $(dir $@)
	$(call msg,CCLD,$@)$(CC) $(TEST_CFLAGS) $(PORT_DEFS) -DHZ_PORT_GPIO=1 -DHZ_VM_GPIO_ONLY=1 -Iport/linux \
		$(LDFLAGS_ALL) -o $@ $< $(GPIOD2_OBJ) $(PORT_LIB) $(LIB) $(TEST_LIBS) $(GPIOD2_LIBS)

# Builds and runs test_gpiod2 into $(O)/test-results; a failed fetch or build is one recorded failure.
test-gpiod2:
	$(Q)if $(MAKE) --no-print-directory $(GPIOD2_TEST) >$(O)/test-results/gpiod2-build.log 2>&1; then \
		sh test/run-tests.sh $(O)/test-results "$(BOARD)" "$(BOARD_TEST_LAUNCHER)" $(GPIOD2_TEST); \
	else \
		echo "  FAIL  $(BOARD) test_gpiod2: the libgpiod 2 path could not be fetched or built (see $(O)/test-results/gpiod2-build.log)"; \
		grep -m 3 -iE 'error|fail' $(O)/test-results/gpiod2-build.log | sed 's/^/        /'; \
		echo "$(BOARD)/test_gpiod2 0 1 0" >$(O)/test-results/test_gpiod2.res; \
	fi
.PHONY: test-gpiod2
