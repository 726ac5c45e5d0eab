# Real scenes (../shared/scenes, see SOURCES.md there): zips are unpacked into $(BUILD_ROOT)/scenes-src, each
# scene is baked with its sidecar programs/hzbake/scenes/<name>.hzs into $(BUILD_ROOT)/scenes/<name>.hzb. A scene is
# re-baked when its model, sidecar or the baker changes. The -small variants are the same models with tiny
# textures and few vertex-key frames: seeds for the fuzzer and images for the exhaustive corruption test.
SCENES_SRC ?= ../shared/scenes
SCENES_O := $(BUILD_ROOT)/scenes
SCENES_UNPACK := $(BUILD_ROOT)/scenes-src
SIDECAR_DIR := programs/hzbake/scenes
SCENE_ZIPS := CornellBox conference sponza lost-empire pine
SCENE_MODEL_CornellBox-Original := $(SCENES_UNPACK)/CornellBox/CornellBox-Original.obj
SCENE_MODEL_CornellBox-Mirror := $(SCENES_UNPACK)/CornellBox/CornellBox-Mirror.obj
SCENE_MODEL_conference := $(SCENES_UNPACK)/conference/conference.obj
SCENE_MODEL_sponza := $(SCENES_UNPACK)/sponza/sponza.obj
# sponza-smoke: Sponza with a 12000-particle smoke cloud (seed 004), written by tools/gen/smoke_scene.c.
SCENE_MODEL_sponza-smoke := $(SCENES_UNPACK)/sponza/sponza-smoke.obj
SCENE_MODEL_lost-empire := $(SCENES_UNPACK)/lost-empire/lost_empire.obj
SCENE_MODEL_pine := $(SCENES_UNPACK)/pine/scrubPine.obj
SCENE_MODEL_dragon-res4 := $(SCENES_SRC)/dragon/dragon_vrip_res4.ply.gz
SCENE_MODEL_dragon-res4-still := $(SCENE_MODEL_dragon-res4)
SCENE_MODEL_dragon-res3 := $(SCENES_SRC)/dragon/dragon_vrip_res3.ply.gz
SCENE_MODEL_dragon-res2 := $(SCENES_SRC)/dragon/dragon_vrip_res2.ply.gz
SCENE_MODEL_dragon := $(SCENES_SRC)/dragon/dragon_vrip.ply.gz
SCENE_MODEL_furball := $(SCENES_SRC)/furball/furBall_A.xml
SCENE_MODEL_BoxAnimated := $(SCENES_SRC)/gltf/BoxAnimated/glTF/BoxAnimated.gltf
SCENE_MODEL_CesiumMan := $(SCENES_SRC)/gltf/CesiumMan/glTF/CesiumMan.gltf
SCENE_MODEL_AlphaBlendModeTest := $(SCENES_SRC)/gltf/AlphaBlendModeTest/glTF/AlphaBlendModeTest.gltf
SCENE_MODEL_CesiumMan-small := $(SCENE_MODEL_CesiumMan)
SCENE_MODEL_CesiumMan-keys := $(SCENE_MODEL_CesiumMan)
SCENE_MODEL_CesiumMan-skin-small := $(SCENE_MODEL_CesiumMan)
# tentacles: the long skinned test model (48 joints, 61,440 triangles, 35 s), written by tools/gen/skinned_gltf.c.
SCENE_MODEL_tentacles := $(BUILD_ROOT)/scenes-gen/tentacles/tentacles.gltf
# crossing: blended panes and confetti moving through each other (seed 004, moving transparency), written by
# tools/gen/crossing_gltf.c.
SCENE_MODEL_crossing := $(BUILD_ROOT)/scenes-gen/crossing/crossing.gltf
# hairball: 348,000 triangles of curly strands in 64 groups swinging past each other (seed 002's moving hairball),
# written by tools/gen/hairball_gltf.c.
SCENE_MODEL_hairball := $(BUILD_ROOT)/scenes-gen/hairball/hairball.gltf
# smoke-column: 6000 smoke particles rising from a ground plane (seed 004), written by tools/gen/smoke_scene.c.
SCENE_MODEL_smoke-column := $(BUILD_ROOT)/scenes-gen/smoke-column/smoke-column.obj
SCENE_MODEL_AlphaBlendModeTest-small := $(SCENE_MODEL_AlphaBlendModeTest)
SCENE_MODEL_furball-sway := $(SCENE_MODEL_furball)
SCENE_MODEL_sponza-rotated := $(SCENE_MODEL_sponza)
SCENES := CornellBox-Original CornellBox-Mirror conference sponza lost-empire pine dragon-res4 dragon-res3 \
          dragon-res2 dragon furball BoxAnimated CesiumMan AlphaBlendModeTest CesiumMan-small \
          AlphaBlendModeTest-small sponza-smoke dragon-res4-still furball-sway sponza-rotated \
          CesiumMan-keys CesiumMan-skin-small tentacles crossing hairball smoke-column
SCENE_FILES := $(SCENES:%=$(SCENES_O)/%.hzb)
# What each scene reads besides its model: the unpacked zip (its stamp) or every file beside the model.
scene_inputs = $(if $(filter $(SCENES_UNPACK)/%,$(1)),$(dir $(1)).unpacked,$(1) $(wildcard $(dir $(1))*))

$(SCENES_UNPACK)/%/.unpacked: $(SCENES_SRC)/%.zip
	@rm -rf $(dir $@) && mkdir -p $(dir $@)
	$(call msg,UNZIP,$<)unzip -q -o $< -d $(dir $@) && rm -rf $(dir $@)__MACOSX && touch $@

$(SCENES_O)/%.hzb: $(BAKE) $(SIDECAR_DIR)/%.hzs
	@mkdir -p $(dir $@)
	$(call msg,BAKE,$@)$(BAKE) -q -s $(SIDECAR_DIR)/$*.hzs $(SCENE_MODEL_$*) $@
$(foreach s,$(SCENES),$(eval $(SCENES_O)/$(s).hzb: $(call scene_inputs,$(SCENE_MODEL_$(s)))))
$(SCENE_MODEL_sponza-smoke): $(SCENES_UNPACK)/sponza/.unpacked $(BUILD_ROOT)/host/tools/gen/smoke_scene
	$(call msg,GEN,$@)$(BUILD_ROOT)/host/tools/gen/smoke_scene $(SCENES_UNPACK)/sponza
$(SCENES_O)/sponza-smoke.hzb: $(SCENE_MODEL_sponza-smoke)
$(SCENE_MODEL_tentacles): $(BUILD_ROOT)/host/tools/gen/skinned_gltf
	@mkdir -p $(dir $@)
	$(call msg,GEN,$@)$(BUILD_ROOT)/host/tools/gen/skinned_gltf $(dir $@)
$(SCENES_O)/tentacles.hzb: $(SCENE_MODEL_tentacles)
$(SCENE_MODEL_crossing): $(BUILD_ROOT)/host/tools/gen/crossing_gltf
	@mkdir -p $(dir $@)
	$(call msg,GEN,$@)$(BUILD_ROOT)/host/tools/gen/crossing_gltf $(dir $@)
$(SCENES_O)/crossing.hzb: $(SCENE_MODEL_crossing)
$(SCENE_MODEL_hairball): $(BUILD_ROOT)/host/tools/gen/hairball_gltf
	@mkdir -p $(dir $@)
	$(call msg,GEN,$@)$(BUILD_ROOT)/host/tools/gen/hairball_gltf $(dir $@)
$(SCENES_O)/hairball.hzb: $(SCENE_MODEL_hairball)
$(SCENE_MODEL_smoke-column): $(BUILD_ROOT)/host/tools/gen/smoke_scene
	@mkdir -p $(dir $@)
	$(call msg,GEN,$@)$(BUILD_ROOT)/host/tools/gen/smoke_scene --column $(dir $@)
$(SCENES_O)/smoke-column.hzb: $(SCENE_MODEL_smoke-column)

ifeq ($(wildcard $(SCENES_SRC)/SOURCES.md),)
scenes:
	@echo "scenes: no scene sources in '$(SCENES_SRC)' (set SCENES_SRC to the folder with conference.zip, gltf/, ...)" >&2
	@exit 1
else
scenes: deps ## bake every scene of ../shared/scenes (SCENES_SRC) into $(BUILD_ROOT)/scenes/*.hzb
	$(Q)$(MAKE) --no-print-directory scenes-baked
scenes-baked: $(SCENE_FILES)
endif

# Tests read the baked scenes from here (qemu passes the environment to the AArch64 tests too).
HZ_SCENES_DIR ?= $(abspath $(SCENES_O))
export HZ_SCENES_DIR
# test_flip compares with NVIDIA's FLIP on crops of two textures of the unpacked scene zips.
HZ_SCENES_UNPACK ?= $(abspath $(SCENES_UNPACK))
export HZ_SCENES_UNPACK
$(O)/test/unit/test_flip: $(SCENES_UNPACK)/pine/.unpacked $(SCENES_UNPACK)/lost-empire/.unpacked
