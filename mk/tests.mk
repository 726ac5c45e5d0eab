# ---------------------------------------------------------------------------------------------------------
# Tests
tests: $(TEST_BINS) $(HZRT) ## build the test binaries of BOARD without running them

# Runs this board's tests and guards; results go to $(O)/test-results/ for the summary (failures are
# recorded there, so the run goes on to the summary line).
test-board: tests $(if $(BOARD_TEST_LAUNCHER),,$(BENCH))
	$(Q)rm -rf $(O)/test-results && mkdir -p $(O)/test-results
	$(Q)sh test/run-tests.sh $(O)/test-results "$(BOARD)" "$(BOARD_TEST_LAUNCHER)" $(TEST_BINS)
	$(Q)HZ_GUARD_LABEL=$(BOARD) sh test/guard/check-freestanding.sh --record $(O)/test-results "$(NM)" \
		$(CHECK_OBJS) || true
	$(Q)sh test/guard/check-integer.sh --record $(O)/test-results "$(CC)" "$(BOARD_ARCH)" $(INTEGER_SRCS) || true
	$(Q)sh test/guard/check-includes.sh --record $(O)/test-results || true
	$(Q)sh test/guard/check-layers.sh --record $(O)/test-results || true
	$(Q)$(if $(BOARD_TEST_LAUNCHER),true,sh test/cli/run.sh $(O)/test-results $(HZRT) $(BENCH))
	$(Q)$(MAKE) --no-print-directory test-gpiod2

# Fixed memory per board (test/boards/fit.sh, run by `make test` for every board): `hzrt info` of each scene in
# the board's BOARD_FIT_SCENES (board.mk; default builtin) says the default mode fits the display, and one frame
# of it renders (under the board's test launcher: qemu for AArch64).
BOARD_FIT_SCENES ?= builtin
BOARD_FIT_RES ?= $(O)/test-results/board-fit.res
board-fit: $(HZRT) $(foreach s,$(filter-out builtin,$(BOARD_FIT_SCENES)),$(SCENES_O)/$(s).hzb) ## check that the board's default mode fits its display with its reference scenes
	$(Q)mkdir -p $(dir $(BOARD_FIT_RES))
	$(Q)sh test/boards/fit.sh $(BOARD_FIT_RES) "$(BOARD)" "$(BOARD_TEST_LAUNCHER)" $(HZRT) \
		$(foreach s,$(BOARD_FIT_SCENES),$(if $(filter builtin,$(s)),builtin,$(SCENES_O)/$(s).hzb))

ifeq ($(SAN),1)
# Sanitizer objects reference the sanitizer runtime: check a plain build of the core instead.
CHECK_OBJS := $(LIB_SRCS:%.c=$(O)/check/%.o)
$(O)/check/src/%.o: src/%.c
	@mkdir -p $(dir $@)
	$(call msg,CC,$@)$(CC) $(LIB_CFLAGS_BASE) $(EXTRA_CFLAGS) -c $< -o $@
$(INTEGER_SRCS:%.c=$(O)/check/%.o): EXTRA_CFLAGS += $(INTEGER_FLAGS)
test-board: $(CHECK_OBJS)
else
CHECK_OBJS := $(LIB_OBJS)
endif

TEST_BOARDS := host-sim aarch64-generic
# Boards make test only builds (their tests are the same code on the same ISAs): x86-kiosk and rpi4 compile with
# HZ_FEATURE_STATS 0 and their own ISA flags, which the tested boards do not.
BUILD_CHECK_BOARDS := x86-kiosk rpi4
GUARDS_O := $(BUILD_ROOT)/guards$(SAN_SUFFIX)
board_o = $(BUILD_ROOT)/$(1)$(SAN_SUFFIX)
# make test in three steps: bake the scenes; build everything every tier runs, TEST_JOBS compilers at once;
# run the tiers in three lanes side by side — the native one (host tools and fuzz smoke, host-sim, its stability
# run, the design guards, the build-only boards, every board's fit), the emulated one (AArch64 under qemu-user,
# its stability run and fit) and the VM — each lane's tiers one after the other. The emulated lane is the
# longest; the others fill the cores it leaves idle (the VM's device checks and the simulated displays wait on
# their clocks much of the time).
TEST_JOBS ?= $(shell nproc)
# Test binaries run side by side in the emulated lane (qemu-user runs each on one core; the native lane is
# short, and the cores it leaves go to these).
TEST_EMULATED_JOBS ?= 2
test: deps ## build and run every test: scenes, host tools, host-sim, AArch64 under qemu, the VM, design guards
	$(Q)t0=$$(date +%s); \
	$(MAKE) --no-print-directory scenes || exit 1; \
	echo "  TEST     building every tier ($(TEST_JOBS) jobs)"; \
	$(MAKE) --no-print-directory -j$(TEST_JOBS) test-build || exit 1; \
	echo "  TEST     built in $$(( $$(date +%s) - t0 )) s; running the native, the emulated and the VM lane side by side"; \
	rm -rf $(GUARDS_O) $(STAB_O) && mkdir -p $(GUARDS_O) $(STAB_O)/test-results; \
	$(MAKE) --no-print-directory -j3 test-lane-native test-lane-emulated test-lane-vm || exit 1; \
	sh test/stability/report.sh $(STAB_O) $(STAB_BOARDS); \
	sh test/summary.sh $(HOST_O)/test-results $(foreach b,$(TEST_BOARDS),$(call board_o,$(b))/test-results) \
		$(TEST_TIER_RESULTS) $(GUARDS_O); rc=$$?; \
	echo "make test: $$(( $$(date +%s) - t0 )) s on $$(nproc) cores"; exit $$rc

# Step 2 (make -j): every binary the tiers run. The VM's build shares aarch64-generic's folder, so it waits for it.
test-build: test-build-host $(TEST_BOARDS:%=test-build-%) test-build-vm
test-build-host:
	$(Q)$(MAKE) --no-print-directory $(HOST_TEST_BINS) $(HOST_O)/bin/hzbake $(FUZZ) $(FUZZ_O)/seeds/.stamp
$(TEST_BOARDS:%=test-build-%): test-build-%:
	$(Q)$(MAKE) --no-print-directory BOARD=$* O=$(call board_o,$*) test-board-build
test-build-vm: test-build-aarch64-generic
	$(Q)$(MAKE) --no-print-directory BOARD=aarch64-generic O=$(call board_o,aarch64-generic) vmtest-build
test-board-build: tests $(STAB) $(if $(BOARD_TEST_LAUNCHER),,$(BENCH)) \
	$(foreach s,$(filter-out builtin,$(BOARD_FIT_SCENES)),$(SCENES_O)/$(s).hzb)

# Step 3: the lanes (make -j3 runs them side by side). A failing test is recorded for the summary, not fatal.
test-lane-native:
	$(Q)$(MAKE) --no-print-directory test-host || exit 1
	$(Q)$(MAKE) --no-print-directory BOARD=host-sim O=$(call board_o,host-sim) test-board stability-board || exit 1
	$(Q)sh test/guard/run-guards.sh --record $(GUARDS_O) || true
	$(Q)$(MAKE) --no-print-directory test-features-off || true
	$(Q)for b in $(BUILD_CHECK_BOARDS); do \
		if $(MAKE) --no-print-directory BOARD=$$b O=$(call board_o,$$b) all >$(GUARDS_O)/build-$$b.log 2>&1; \
		then echo "  ok    board $$b builds"; echo "board-build/$$b 1 0 0" >$(GUARDS_O)/build-$$b.res; \
		else echo "  FAIL  board $$b does not build: $(GUARDS_O)/build-$$b.log"; \
			grep -m 5 error $(GUARDS_O)/build-$$b.log | sed 's/^/        /'; \
			echo "board-build/$$b 0 1 0" >$(GUARDS_O)/build-$$b.res; fi; \
	done
	+$(Q)for b in host-sim $(BUILD_CHECK_BOARDS); do $(call board_fit,$$b); done
test-lane-emulated:
	$(Q)HZ_TEST_JOBS=$(TEST_EMULATED_JOBS) $(MAKE) --no-print-directory BOARD=aarch64-generic O=$(call board_o,aarch64-generic) test-board \
		stability-board || exit 1
	+$(Q)$(call board_fit,aarch64-generic)
test-lane-vm:
	$(Q)$(MAKE) --no-print-directory vmtest-tier
board_fit = r=$(GUARDS_O)/board-fit-$(1).res; \
	$(MAKE) --no-print-directory BOARD=$(1) O=$(call board_o,$(1)) BOARD_FIT_RES=$$r board-fit || \
	[ -f $$r ] || echo "board-fit/$(1) 0 1 0" >$$r
.PHONY: test-build test-build-host $(TEST_BOARDS:%=test-build-%) test-build-vm test-board-build test-lane-native \
        test-lane-emulated test-lane-vm

# Host-side tests (run by `make test`): the baker's tests and a bounded run of each fuzz target, results for the summary.
test-host: $(HOST_TEST_BINS) $(HOST_O)/bin/hzbake $(FUZZ) $(FUZZ_O)/seeds/.stamp scenes
	$(Q)rm -rf $(HOST_O)/test-results && mkdir -p $(HOST_O)/test-results
	$(Q)HZ_BAKE=$(abspath $(HOST_O)/bin/hzbake) HZ_SCENES_SRC=$(abspath $(SCENES_SRC)) \
		HZ_SCENES_UNPACK=$(abspath $(SCENES_UNPACK)) HZ_SCENES_GEN=$(abspath $(BUILD_ROOT)/scenes-gen) \
		sh test/run-tests.sh $(HOST_O)/test-results host "" $(HOST_TEST_BINS)
	$(Q)sh test/fuzz/run-fuzz.sh $(HOST_O)/test-results $(FUZZ_O) $(FUZZ_RUNS) $(FUZZ_TARGETS)
