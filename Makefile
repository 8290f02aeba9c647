# blockworld: the README's two commands are `make demo` and `make test`. Both install what a
# fresh Debian machine lacks (lavapipe, Mesa's CPU Vulkan driver) before building.

CARGO ?= cargo
export XDG_RUNTIME_DIR ?= /tmp/blockworld-xdg
VULKAN_PKGS := mesa-vulkan-drivers libvulkan1
# The Khronos glTF-Validator (npm), which tests/gltf_validator.rs runs on every .glb it writes.
GLTF_VALIDATOR_VERSION := 2.0.0-dev.3.10
GLTF_VALIDATOR_DIR := target/gltf-validator

.PHONY: setup demo test lint ci bless

# Installs the Vulkan loader and lavapipe only when absent (needs root, as on this machine kind).
setup:
	@mkdir -p "$(XDG_RUNTIME_DIR)" && chmod 700 "$(XDG_RUNTIME_DIR)"
	@if ! dpkg -s $(VULKAN_PKGS) >/dev/null 2>&1; then \
		echo "installing $(VULKAN_PKGS) (lavapipe)"; \
		SUDO=$$( [ "$$(id -u)" = 0 ] || echo sudo ); \
		$$SUDO apt-get update -qq && \
		DEBIAN_FRONTEND=noninteractive $$SUDO apt-get install -y -qq $(VULKAN_PKGS); \
	fi
	@if ! command -v npm >/dev/null 2>&1; then \
		echo "installing nodejs npm (for the glTF-Validator)"; \
		SUDO=$$( [ "$$(id -u)" = 0 ] || echo sudo ); \
		$$SUDO apt-get update -qq && \
		DEBIAN_FRONTEND=noninteractive $$SUDO apt-get install -y -qq nodejs npm; \
	fi
	@if [ ! -f $(GLTF_VALIDATOR_DIR)/node_modules/gltf-validator/package.json ]; then \
		echo "installing gltf-validator $(GLTF_VALIDATOR_VERSION) into $(GLTF_VALIDATOR_DIR)"; \
		npm install --prefix $(GLTF_VALIDATOR_DIR) --no-audit --no-fund --silent \
			gltf-validator@$(GLTF_VALIDATOR_VERSION); \
	fi

# Runs the main job on the built-in example (scenes/thesis_sample.json) into out/demo.
demo: setup
	$(CARGO) run --quiet -- demo -o out/demo

# The whole test suite; a missing GPU adapter is a failure here, not a skip.
test: setup
	BLOCKWORLD_REQUIRE_GPU=1 $(CARGO) test --all-targets

lint:
	$(CARGO) fmt --check
	$(CARGO) clippy --all-targets -- -D warnings
	@# One glam, parry3d, rapier3d and wgpu each: scene types are physics types, no conversions.
	@if $(CARGO) tree -d -e normal --depth 0 --prefix none | grep -E '^(glam|parry3d|rapier3d|wgpu) v'; then \
		echo "a second version of the crate above is compiled: keep glam/parry3d/rapier3d in lockstep (README Dependencies)"; \
		exit 1; \
	fi

ci: lint test

# Re-bless golden images and scores on purpose; review the diff before committing.
bless: setup
	BLESS=1 $(CARGO) test --all-targets
