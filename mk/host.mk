# ---------------------------------------------------------------------------------------------------------
# Host tools: the scene baker (programs/hzbake), its tests (test/host) and the loader fuzzer (test/fuzz). They are
# built for the build machine with HOSTCC whatever BOARD is, against a host-compiled copy of the core and
# scene sources (tools/host/board.h), into $(BUILD_ROOT)/host (host-san with SAN=1). `make scenes` always
# bakes with the plain build, so SAN=1 does not re-bake every scene.
HOSTAR ?= ar
HOST_CFLAGS := $(WARN) $(OPT) -D_POSIX_C_SOURCE=200809L -Iinclude -Itools/host -Iport/linux -Iprograms/opt
HOST_SAN_FLAGS := -fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer
HOST_LIB_SRCS := $(CORE_SRCS) $(SCENE_SRCS) port/linux/cli.c port/linux/fileio.c programs/opt/opttab.c
BAKE_LIB_SRCS := programs/hzbake/util.c programs/hzbake/sidecar.c programs/hzbake/scene.c programs/hzbake/texture.c \
                 programs/hzbake/import_assimp.c programs/hzbake/import_furball.c
BAKE_SRCS := programs/hzbake/main.c $(BAKE_LIB_SRCS)
BAKE_LIBS := -lassimp -lstb -lz -lm
HOST_TESTS := sidecar bake bake_cli

# $(1): output directory, $(2): extra compiler/linker flags
define HOST_TREE
$(1)/obj/src/%.o: src/%.c
	@mkdir -p $$(dir $$@)
	$$(call msg,HOSTCC,$$@)$$(HOSTCC) $$(HOST_CFLAGS) -ffreestanding $(2) $$(DEPFLAGS) -c $$< -o $$@
$(1)/obj/%.o: %.c
	@mkdir -p $$(dir $$@)
	$$(call msg,HOSTCC,$$@)$$(HOSTCC) $$(HOST_CFLAGS) $(2) $$(DEPFLAGS) -c $$< -o $$@
$(1)/libhz-host.a: $$(HOST_LIB_SRCS:%.c=$(1)/obj/%.o)
	$$(call msg,AR,$$@)rm -f $$@ && $$(HOSTAR) rcs $$@ $$^
$(1)/libbake.a: $$(BAKE_LIB_SRCS:%.c=$(1)/obj/%.o)
	$$(call msg,AR,$$@)rm -f $$@ && $$(HOSTAR) rcs $$@ $$^
$(1)/bin/hzbake: $(1)/obj/programs/hzbake/main.o $(1)/libbake.a $(1)/libhz-host.a
	@mkdir -p $$(dir $$@)
	$$(call msg,HOSTLD,$$@)$$(HOSTCC) $(2) -o $$@ $$^ $$(BAKE_LIBS)
$(1)/test/test_%: test/host/test_%.c $(1)/libbake.a $(1)/libhz-host.a
	@mkdir -p $$(dir $$@)
	$$(call msg,HOSTCC,$$@)$$(HOSTCC) $$(HOST_CFLAGS) -Itest -Iprograms/hzbake $(2) $$(DEPFLAGS) -o $$@ $$< \
		$(1)/libbake.a $(1)/libhz-host.a $$(BAKE_LIBS) -lcmocka
-include $$(patsubst %.c,$(1)/obj/%.d,$$(HOST_LIB_SRCS) $$(BAKE_SRCS)) $$(HOST_TESTS:%=$(1)/test/test_%.d)
endef
HOST_PLAIN_O := $(BUILD_ROOT)/host
HOST_O := $(BUILD_ROOT)/host$(SAN_SUFFIX)
$(eval $(call HOST_TREE,$(HOST_PLAIN_O),))
ifeq ($(SAN),1)
$(eval $(call HOST_TREE,$(HOST_O),$(HOST_SAN_FLAGS)))
endif
BAKE := $(HOST_PLAIN_O)/bin/hzbake
# The baker warns when a scene fits no board's scene arena: every board's HZ_ARENA_SCENE_BYTES (in MiB).
BOARD_SCENE_ARENAS := $(foreach b,$(wildcard boards/*/board.h),$(patsubst boards/%/board.h,%,$(b))=$(shell \
	sed -n 's/^\#define HZ_ARENA_SCENE_BYTES (\([0-9]*\)ull << 20).*/\1/p' $(b)))
$(HOST_PLAIN_O)/obj/programs/hzbake/main.o $(HOST_O)/obj/programs/hzbake/main.o: $(wildcard boards/*/board.h)
$(HOST_PLAIN_O)/obj/programs/hzbake/main.o $(HOST_O)/obj/programs/hzbake/main.o: HOST_CFLAGS += \
	-DHZ_BAKE_BOARD_SCENE_ARENAS='"$(BOARD_SCENE_ARENAS)"'
HOST_TEST_BINS := $(HOST_TESTS:%=$(HOST_O)/test/test_%)

bake: $(BAKE) ## build the scene baker programs/hzbake (hzbake) for the build machine into $(BUILD_ROOT)/host
