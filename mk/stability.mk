# stability (test/stability): the catalogue of stiff and extreme cases, one binary per board linked like the port
# tests; `make stability` runs it on host-sim and under qemu-aarch64 and writes $(STAB_O)/report.md and a CSV per
# board; `make test` runs it as a tier (stability-tier). FULL=1 adds the long variants.
STAB_SRCS := test/stability/main.c test/stability/stab_util.c test/stability/geometry.c test/stability/rays.c \
             test/stability/motion.c test/stability/transparency.c test/stability/recon.c \
             test/stability/timing.c test/stability/fixed.c test/stability/memory.c
STAB_SRCS += test/stability/blur.c test/stability/dither.c test/stability/adaptive.c
STAB_OBJS := $(STAB_SRCS:%.c=$(O)/%.o)
STAB := $(O)/test/stability/hzstab
STAB_O := $(BUILD_ROOT)/stability$(SAN_SUFFIX)
STAB_BOARDS := host-sim aarch64-generic
$(O)/test/stability/%.o: test/stability/%.c
	@mkdir -p $(dir $@)
	$(call msg,CC,$@)$(CC) $(TEST_CFLAGS) $(PORT_DEFS) -Iport/linux $(DEPFLAGS) -c $< -o $@
$(STAB): $(STAB_OBJS) $(PORT_LIB) $(LIB)
	@mkdir -p $(dir $@)
	$(call msg,LD,$@)$(CC) $(LDFLAGS_ALL) -o $@ $(STAB_OBJS) $(PORT_LIB) $(LIB) $(PORT_LIBS)
tests: $(STAB)
-include $(STAB_OBJS:.o=.d)

# One board's run (BOARD, O): CSV, notes and the .res line for test/summary.sh.
stability-board: $(STAB)
	@mkdir -p $(STAB_O)/test-results
	$(Q)$(BOARD_TEST_LAUNCHER) $(STAB) $(if $(filter 1,$(FULL)),--full) --label $(BOARD) \
		--csv $(STAB_O)/$(BOARD).csv --notes $(STAB_O)/$(BOARD).notes \
		--res $(STAB_O)/test-results/$(BOARD).res >$(STAB_O)/$(BOARD).log 2>&1; \
		rc=$$?; sed 's/^/  $(BOARD): /' $(STAB_O)/$(BOARD).log | grep -v '^  $(BOARD):   ok ' || true; \
		[ -s $(STAB_O)/test-results/$(BOARD).res ] || echo "$(BOARD)/stability 0 1 0" >$(STAB_O)/test-results/$(BOARD).res; \
		exit 0

stability-tier:
	$(Q)rm -rf $(STAB_O) && mkdir -p $(STAB_O)/test-results
	$(Q)for b in $(STAB_BOARDS); do \
		$(MAKE) --no-print-directory BOARD=$$b O=$(BUILD_ROOT)/$$b$(SAN_SUFFIX) stability-board || exit 1; \
	done
	$(Q)sh test/stability/report.sh $(STAB_O) $(STAB_BOARDS)
TEST_TIERS += stability-tier
TEST_TIER_RESULTS += $(STAB_O)/test-results

stability: deps ## stiff and extreme cases on host-sim and AArch64 (qemu): build/stability/report.md + CSVs; FULL=1 adds long variants
	$(Q)$(MAKE) --no-print-directory stability-tier
	$(Q)sh test/summary.sh $(STAB_O)/test-results
