# ---------------------------------------------------------------------------------------------------------
# Build rules
all: $(HZRT) ## build hzrt for BOARD (default host-sim) into O (default build/<board>)

# Every object depends on the configuration it was compiled with (compiler, flags, the ports found): `make deps`
# can install libdrm or libgpiod between two runs, and objects built before would keep the old answer (a port
# left out) while their sources look up to date. The stamp is rewritten only when the configuration changes.
BUILD_CONFIG := $(CC) $(HOSTCC) | $(LIB_CFLAGS) | $(HOSTED_CFLAGS) | $(PORT_DEFS) | ports $(BOARD_PORTS) | \
                gpiod $(LIBGPIOD_VERSION) | $(PORT_LIBS_drm) $(PORT_LIBS_gpio)
BUILD_STAMP := $(O)/.build-config
ifeq ($(filter clean help,$(MAKECMDGOALS)),)
$(shell mkdir -p $(O))
# (a name of its own per make process: make test runs several makes on one folder at once)
BUILD_STAMP_NEW := $(BUILD_STAMP).new.$(shell echo $$$$)
$(file >$(BUILD_STAMP_NEW),$(BUILD_CONFIG))
$(shell cmp -s $(BUILD_STAMP_NEW) $(BUILD_STAMP) || mv -f $(BUILD_STAMP_NEW) $(BUILD_STAMP); rm -f $(BUILD_STAMP_NEW))
endif

$(O)/src/%.o: src/%.c $(BUILD_STAMP)
	@mkdir -p $(dir $@)
	$(call msg,CC,$@)$(CC) $(LIB_CFLAGS) $(EXTRA_CFLAGS) $(DEPFLAGS) -c $< -o $@

$(INTEGER_SRCS:%.c=$(O)/%.o): EXTRA_CFLAGS += $(INTEGER_FLAGS)
# The upscaler's row loops in the vector unit: integer arithmetic, the same bytes on every ISA (test_rgb8).
$(O)/src/core/rgb8.o: EXTRA_CFLAGS += -ftree-vectorize -fvect-cost-model=dynamic
# The board's static pools may exceed 2 GiB: on x86-64 they go to .lbss (medium code model) so that the
# rest of the program keeps the fast small-model addressing.
$(O)/port/linux/pools.o: EXTRA_CFLAGS += $(if $(filter x86_64,$(BOARD_ARCH)),-mcmodel=medium)

# The refusal of a scene that needs a feature this build leaves out names the boards that have it.
feature_boards = $(subst $(space),$(comma)$(space),$(sort $(patsubst boards/%/board.h,%,$(shell grep -lE \
	'^[[:space:]]*\#[[:space:]]*define[[:space:]]+HZ_FEATURE_$(1)[[:space:]]+1' boards/*/board.h))))
comma := ,
$(O)/src/render/features.o: EXTRA_CFLAGS += $(foreach f,TEXTURES MIRRORS TRANSPARENCY MOTION, \
	-DHZ_FEATURE_BOARDS_$(f)='"$(or $(call feature_boards,$(f)),none)"')

$(O)/port/%.o: port/%.c $(BUILD_STAMP)
	@mkdir -p $(dir $@)
	$(call msg,CC,$@)$(CC) $(HOSTED_CFLAGS) $(PORT_DEFS) $(EXTRA_CFLAGS) $(DEPFLAGS) -c $< -o $@

$(O)/programs/%.o: programs/%.c $(BUILD_STAMP)
	@mkdir -p $(dir $@)
	$(call msg,CC,$@)$(CC) $(HOSTED_CFLAGS) $(PORT_DEFS) $(PROGRAM_CFLAGS) $(EXTRA_CFLAGS) $(DEPFLAGS) -c $< -o $@

$(LIB): $(LIB_OBJS)
	$(call msg,AR,$@)rm -f $@ && $(AR) rcs $@ $^

$(PORT_LIB): $(PORT_OBJS)
	$(call msg,AR,$@)rm -f $@ && $(AR) rcs $@ $^

$(OPT_LIB): $(OPT_OBJS)
	$(call msg,AR,$@)rm -f $@ && $(AR) rcs $@ $^

# What hzrt links (also the VM's static hzrt, mk/vm.mk).
HZRT_LINK := $(HZRT_OBJS) $(ERRTIME_LIB) $(OPT_LIB) $(PORT_LIB) $(LIB)
$(HZRT): $(HZRT_LINK)
	@mkdir -p $(dir $@)
	$(call msg,LD,$@)$(CC) $(LDFLAGS_ALL) -o $@ $(HZRT_LINK) $(PORT_LIBS)

$(BENCH): $(BENCH_OBJS) $(OPT_LIB) $(PORT_LIB) $(LIB)
	@mkdir -p $(dir $@)
	$(call msg,LD,$@)$(CC) $(LDFLAGS_ALL) -o $@ $(BENCH_OBJS) $(OPT_LIB) $(PORT_LIB) $(LIB) $(PORT_LIBS)

# The sigrok-cli demo traces (test/traces/README.md) as C arrays, for tests that also run in the VM.
TRACE_HDR := $(O)/test/gen/hz_traces.h
$(TRACE_HDR): test/traces/mkheader.sh test/traces/sigrok-demo-200k.vcd test/traces/sigrok-demo-1k.vcd
	@mkdir -p $(dir $@)
	$(call msg,GEN,$@)sh $< $(filter %.vcd,$^) >$@.tmp && mv $@.tmp $@

$(ERRTIME_LIB): $(ERRTIME_OBJS)
	$(call msg,AR,$@)rm -f $@ && $(AR) rcs $@ $^

$(ERRTIME): $(ERRTIME_MAIN_OBJS) $(ERRTIME_LIB) $(OPT_LIB) $(PORT_LIB) $(LIB)
	@mkdir -p $(dir $@)
	$(call msg,LD,$@)$(CC) $(LDFLAGS_ALL) -o $@ $(ERRTIME_MAIN_OBJS) $(ERRTIME_LIB) $(OPT_LIB) $(PORT_LIB) $(LIB) $(PORT_LIBS)

errtime: $(ERRTIME) ## build hzerrtime (error against run time; `hzerrtime --help`) into O/bin
tests: $(ERRTIME)

# Every unit test links the same libraries (archives: a test takes only what it calls). The commands' archive
# lets tests drive `hzrt render`, `show`, `latency` and `accel` through their entry points.
CMD_LIB := $(O)/libhzcmd.a
$(CMD_LIB): $(CMD_OBJS)
	$(call msg,AR,$@)rm -f $@ && $(AR) rcs $@ $^
TEST_DEP_LIBS := $(CMD_LIB) $(ERRTIME_LIB) $(OPT_LIB) $(PORT_LIB) $(LIB)
TEST_PROGRAM_CFLAGS := -Iprograms/hzrt -Iprograms/hzerrtime -Iprograms/opt -Iport/linux
$(TEST_BINS): $(O)/test/unit/%: $(TEST_UNIT_DIR)/%.c $(TEST_DEP_LIBS) $(TRACE_HDR) $(BUILD_STAMP)
	@mkdir -p $(dir $@)
	$(call msg,CCLD,$@)$(CC) $(TEST_CFLAGS) $(PORT_DEFS) $(TEST_PROGRAM_CFLAGS) -I$(O)/test/gen \
		-DHZ_HAVE_PNG=$(HAVE_PNG) $(DEPFLAGS) $(LDFLAGS_ALL) -o $@ $< $(TEST_DEP_LIBS) $(TEST_LIBS) $(PORT_LIBS) -ldl

-include $(ALL_OBJS:.o=.d) $(TEST_BINS:=.d)
