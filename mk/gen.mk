# ---------------------------------------------------------------------------------------------------------
# Generated tables (host tools under tools/gen; their output is committed and checked by tests)
GEN_BIN := $(BUILD_ROOT)/host/tools/gen
$(GEN_BIN)/srgb_tables: tools/gen/srgb_tables.c
	@mkdir -p $(dir $@)
	$(call msg,HOSTCC,$@)$(HOSTCC) $(WARN) -O2 -o $@ $< -lm

gen-srgb: $(GEN_BIN)/srgb_tables ## regenerate src/core/srgb_tables.c (exact sRGB 8-bit tables; test_image checks them)
	$(Q)$(GEN_BIN)/srgb_tables src/core/srgb_tables.c

$(GEN_BIN)/smoke_scene: tools/gen/smoke_scene.c tools/gen/genio.h
	@mkdir -p $(dir $@)
	$(call msg,HOSTCC,$@)$(HOSTCC) $(WARN) -D_POSIX_C_SOURCE=200809L -O2 -o $@ $< -lm

$(GEN_BIN)/skinned_gltf: tools/gen/skinned_gltf.c tools/gen/genio.h tools/gen/gltfio.h
	@mkdir -p $(dir $@)
	$(call msg,HOSTCC,$@)$(HOSTCC) $(WARN) -D_POSIX_C_SOURCE=200809L -O2 -o $@ $< -lm

$(GEN_BIN)/crossing_gltf: tools/gen/crossing_gltf.c tools/gen/genio.h tools/gen/gltfio.h
	@mkdir -p $(dir $@)
	$(call msg,HOSTCC,$@)$(HOSTCC) $(WARN) -D_POSIX_C_SOURCE=200809L -O2 -o $@ $< -lm

$(GEN_BIN)/hairball_gltf: tools/gen/hairball_gltf.c tools/gen/genio.h tools/gen/gltfio.h
	@mkdir -p $(dir $@)
	$(call msg,HOSTCC,$@)$(HOSTCC) $(WARN) -D_POSIX_C_SOURCE=200809L -O2 -o $@ $< -lm

$(GEN_BIN)/dither_tables: tools/gen/dither_tables.c tools/gen/vac.h
	@mkdir -p $(dir $@)
	$(call msg,HOSTCC,$@)$(HOSTCC) $(WARN) -O2 -o $@ $< -lm

gen-dither: $(GEN_BIN)/dither_tables ## regenerate src/pattern/dither_tables.c (STD maps, void-and-cluster blue noise; test_dither checks them)
	$(Q)$(GEN_BIN)/dither_tables src/pattern/dither_tables.c
